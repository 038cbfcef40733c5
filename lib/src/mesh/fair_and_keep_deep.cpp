// fair_and_keep_deep (fair_and_keep_deep.hpp): both passes over an extracted surface,
// sharing the per-vertex lists they walk, the depth made good after the fairing so that
// nothing undoes it.
#include "mesh/fair_and_keep_deep.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "snvr/mesh.hpp"
#include "snvr/point_cloud.hpp"
#include "geometry/point_tree.hpp"
#include "mesh/vertex_lists.hpp"
#include "parallel_sizes.hpp"
#include "threads_here.hpp"

namespace snvr {
namespace {

// Each vertex's ring, and fan if asked (as detail::rings and detail::fans), filled by
// threads over contiguous ranges of triangles: each part first counts its corners per
// vertex, so that it knows where its items go and every list keeps triangle order.
void rings_and_fans(const Mesh& m, detail::VertexLists& ring, detail::VertexLists* fan) {
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

}  // namespace

DepthGuardReport detail::fair_and_keep_deep(Mesh& mesh, const PointCloud& points, const MeshFairing& fairing,
                                            const KeepDeep* deep, const Begun& begun) {
    const bool fair = fairing.passes > 0 && !mesh.triangles.empty();
    const bool lists = deep && !mesh.triangles.empty() && !points.empty();
    // Both passes walk the same triangles: their per-vertex lists are built once.
    detail::VertexLists ring, fan;
    if (fair && begun) begun("fairing the surface");
    if (fair || lists) rings_and_fans(mesh, ring, lists ? &fan : nullptr);
    if (fair) detail::fair_mesh(mesh, fairing, ring);
    if (!deep) return {};
    return lists ? detail::keep_points_deep(mesh, detail::tree_of(points), deep->depth, deep->voxel, deep->lone, std::move(ring), fan,
                                                     deep->elsewhere, begun)
                 : keep_points_deep(mesh, points, deep->depth, deep->voxel, deep->lone);
}

}  // namespace snvr
