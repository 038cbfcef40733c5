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

namespace snvr {

DepthGuardReport detail::fair_and_keep_deep(Mesh& mesh, const PointCloud& points, const MeshFairing& fairing,
                                            const KeepDeep* deep, const Begun& begun) {
    const bool fair = fairing.passes > 0 && !mesh.triangles.empty();
    const bool lists = deep && !mesh.triangles.empty() && !points.empty();
    // Both passes walk the same triangles: their per-vertex lists are built once.
    detail::VertexLists ring, fan;
    if (fair && begun) begun("fairing the surface");
    if (fair || lists) detail::rings_and_fans(mesh, ring, lists ? &fan : nullptr);
    if (fair) detail::fair_mesh(mesh, fairing, ring);
    if (!deep) return {};
    return lists ? detail::keep_points_deep(mesh, detail::tree_of(points), deep->depth, deep->voxel, deep->lone, std::move(ring), fan,
                                                     deep->elsewhere, begun)
                 : keep_points_deep(mesh, points, deep->depth, deep->voxel, deep->lone);
}

}  // namespace snvr
