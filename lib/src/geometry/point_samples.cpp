#include "geometry/point_samples.hpp"

#include <algorithm>

namespace snvr::detail {

std::vector<std::uint32_t> strided_sample(const PointTree& tree, std::size_t samples) {
    const std::size_t n = tree.size();
    samples = std::min(samples, n);
    if (samples == 0) return {};
    // A point's rank by input index, from a bit per input index and counts per word.
    std::uint32_t top = 0;
    for (std::uint32_t i : tree.input) top = std::max(top, i);
    const std::size_t words = std::size_t(top) / 64 + 1;
    std::vector<std::uint64_t> bits(words, 0);
    for (std::uint32_t i : tree.input) bits[i / 64] |= std::uint64_t(1) << (i % 64);
    std::vector<std::uint32_t> before(words, 0);
    for (std::size_t w = 1; w < words; ++w) before[w] = before[w - 1] + std::uint32_t(__builtin_popcountll(bits[w - 1]));
    std::vector<std::uint32_t> out(samples);
    for (std::size_t k = 0; k < n; ++k) {
        const std::uint32_t i = tree.input[k];
        const std::size_t rank = before[i / 64] + std::size_t(__builtin_popcountll(bits[i / 64] & ((std::uint64_t(1) << (i % 64)) - 1)));
        // Sampled when some s gives floor(s n / samples) == rank: the least s with s n >= rank samples.
        const std::size_t s = (rank * samples + n - 1) / n;
        if (s < samples && s * n / samples == rank) out[s] = std::uint32_t(k);
    }
    return out;
}

}  // namespace snvr::detail
