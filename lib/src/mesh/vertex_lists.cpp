// rings_and_fans (vertex_lists.hpp).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mesh/vertex_lists.hpp"
#include "parallel_sizes.hpp"
#include "threads_here.hpp"

namespace snvr {

// Each part of the triangles first counts its corners per vertex, so that it knows where
// its items go and every list keeps triangle order.
void detail::rings_and_fans(const Mesh& m, VertexLists& ring, VertexLists* fan) {
    const std::size_t nv = m.vertices.size(), nt = m.triangles.size();
    const int parts = std::ptrdiff_t(nt) > 16 * detail::kParallelItems ? std::min(4, detail::threads_here()) : 1;
    const auto first = [&](int part) { return nt * std::size_t(part) / std::size_t(parts); };
    std::vector<std::vector<std::size_t>> at(std::size_t(parts), std::vector<std::size_t>(nv, 0));
#pragma omp parallel for num_threads(parts) schedule(static, 1)
    for (int part = 0; part < parts; ++part)
        for (std::size_t t = first(part); t < first(part + 1); ++t)
            for (std::uint32_t v : m.triangles[t]) ++at[std::size_t(part)][v];
    // Each vertex's row, and in it each part's first slot.
    ring.start.assign(nv + 1, 0);
    std::size_t total = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        ring.start[v] = total;
        for (auto& count : at) {
            const std::size_t c = count[v];
            count[v] = total;
            total += c;
        }
    }
    ring.start[nv] = total;
    ring.items.resize(total);
    if (fan) {
        fan->start = ring.start;
        fan->items.resize(total);
    }
#pragma omp parallel for num_threads(parts) schedule(static, 1)
    for (int part = 0; part < parts; ++part)
        for (std::size_t t = first(part); t < first(part + 1); ++t)
            for (int c = 0; c < 3; ++c) {
                const std::size_t slot = at[std::size_t(part)][m.triangles[t][c]]++;
                ring.items[slot] = m.triangles[t][(c + 1) % 3];
                if (fan) fan->items[slot] = std::uint32_t(t);
            }
}

}  // namespace snvr
