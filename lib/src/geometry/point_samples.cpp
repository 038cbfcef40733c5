#include "geometry/point_samples.hpp"

#include <algorithm>

namespace snvr::detail {

namespace {

// The input indices of the sampled ranks (ascending): the ranks themselves when the
// indices are 0 .. n - 1, else each one found among bits per input index and their
// counts per word (points dropped leave gaps).
std::vector<std::uint32_t> sampled_indices(const std::uint32_t* input, std::size_t n, std::size_t samples) {
    std::uint32_t top = 0;
#pragma omp parallel for reduction(max : top) schedule(static)
    for (std::size_t k = 0; k < n; ++k) top = std::max(top, input[k]);
    std::vector<std::uint32_t> picked(samples);
    if (std::size_t(top) + 1 == n) {
        for (std::size_t s = 0; s < samples; ++s) picked[s] = std::uint32_t(s * n / samples);
        return picked;
    }
    std::vector<std::uint64_t> present(std::size_t(top) / 64 + 1, 0);
    for (std::size_t k = 0; k < n; ++k) present[input[k] / 64] |= std::uint64_t(1) << (input[k] % 64);
    std::size_t word = 0, below = 0;  // the indices present below `word`
    for (std::size_t s = 0; s < samples; ++s) {
        const std::size_t rank = s * n / samples;  // ascending
        std::size_t here = std::size_t(__builtin_popcountll(present[word]));
        while (below + here <= rank) {
            below += here;
            here = std::size_t(__builtin_popcountll(present[++word]));
        }
        std::uint64_t bits = present[word];
        for (std::size_t skip = rank - below; skip > 0; --skip) bits &= bits - 1;
        picked[s] = std::uint32_t(word * 64 + std::size_t(__builtin_ctzll(bits)));
    }
    return picked;
}

// As sampled_indices where the indices are 0 .. n + dropped.size() - 1 but `dropped`
// (ascending): the rank's index is the rank plus the dropped indices below it, found by
// walking both in turn (no pass over the points).
std::vector<std::uint32_t> indices_of_ranks(const std::vector<std::uint32_t>& dropped, std::size_t n,
                                            std::size_t samples) {
    std::vector<std::uint32_t> picked(samples);
    std::size_t below = 0;  // the dropped indices below the current one
    for (std::size_t s = 0; s < samples; ++s) {
        const std::size_t rank = s * n / samples;  // ascending
        while (below < dropped.size() && dropped[below] <= rank + below) ++below;
        picked[s] = std::uint32_t(rank + below);
    }
    return picked;
}

}  // namespace

std::vector<std::uint32_t> strided_sample(const PointTree& tree, std::size_t samples) {
    const std::size_t n = tree.size();
    samples = std::min(samples, n);
    if (samples == 0) return {};
    const auto& input = tree.input;
    // The sampled input indices as bits: one pass over the points then tests a bit each,
    // and only the few sampled ones look up their slot (a pass that ranked every point
    // cost 0.17 s a sample on the 50 M-point city block once points were dropped). A bit
    // a block of 64 indices first, small enough to stay in the cache, so that most points
    // are passed over without touching the larger array.
    const std::vector<std::uint32_t> picked = tree.numbering_known()
                                                  ? indices_of_ranks(tree.inputs_dropped, n, samples)
                                                  : sampled_indices(input.data(), n, samples);
    const std::size_t top = std::size_t(picked.back());
    std::vector<std::uint64_t> chosen(top / 64 + 1, 0), blocks(top / 4096 + 1, 0);
    for (std::uint32_t i : picked) {
        chosen[i / 64] |= std::uint64_t(1) << (i % 64);
        blocks[i / 4096] |= std::uint64_t(1) << (i / 64 % 64);
    }
    std::vector<std::uint32_t> out(samples);
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < n; ++k) {
        const std::uint32_t i = input[k];
        if (i > top || !(blocks[i / 4096] >> (i / 64 % 64) & 1) || !(chosen[i / 64] >> (i % 64) & 1)) continue;
        out[std::size_t(std::lower_bound(picked.begin(), picked.end(), i) - picked.begin())] = std::uint32_t(k);
    }
    // In the tree's order: searches from them in turn then walk nearby nodes.
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace snvr::detail
