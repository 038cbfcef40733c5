// The default mesher of a reconstruction, in one place for the CLI, benchmarks and tests:
// dual marching cubes (a third of the tetrahedra mesher's triangles, smoother normals),
// faired at the vertex scale, then the tube's depth made good between grid nodes (after
// the fairing, so that nothing undoes it).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "snvr/mesh.hpp"
#include "snvr/reconstruct.hpp"
#include "geometry/point_tree.hpp"
#include "mesh/vertex_lists.hpp"
#include "parallel_sizes.hpp"

namespace snvr {
namespace {

// Each vertex's ring, and fan if asked (as detail::rings and detail::fans), filled by
// threads over contiguous ranges of triangles: each part first counts its corners per
// vertex, so that it knows where its items go and every list keeps triangle order.
void rings_and_fans(const Mesh& m, detail::VertexLists& ring, detail::VertexLists* fan) {
    const std::size_t nv = m.vertices.size(), nt = m.triangles.size();
    int parts = 1;
#ifdef _OPENMP
    if (std::ptrdiff_t(nt) > 16 * detail::kParallelItems) parts = std::min(4, omp_get_max_threads());
#endif
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

Mesh shell_mesh(const Result& result, const PointSet& points, DepthGuardReport* guard, const MeshFairing& fairing) {
    return shell_mesh(result, PointCloud(points), guard, fairing);
}

Mesh shell_mesh(const Result& result, const PointCloud& points, DepthGuardReport* guard, const MeshFairing& fairing) {
    Mesh mesh = extract_dual_isosurface(result.phi, result.domain, 0.0, Interpolation::PhaseField);
    fairing.validate();
    const bool fair = fairing.passes > 0 && !mesh.triangles.empty();
    const bool deep = result.tube_inner > 0 && !mesh.triangles.empty() && !points.empty();
    // Both passes walk the same triangles: their per-vertex lists are built once.
    detail::VertexLists ring, fan;
    if (fair || deep) rings_and_fans(mesh, ring, deep ? &fan : nullptr);
    if (fair) detail::fair_mesh(mesh, fairing, ring);
    DepthGuardReport report;
    // Where the offset is below the points' spacing the shell is a chain of beads around
    // single points; lifting each bead's top made it grainier (undersampled torus: 8.1 ->
    // 8.8 deg dihedral), so those points are left out, unless the offset reaches the
    // sampling gap (then the promise covers every point).
    if (result.tube_inner > 0) {
        const double lone = result.offset >= result.gap ? std::numeric_limits<double>::infinity() : result.offset;
        report = deep ? detail::keep_points_deep(mesh, points.tree(), result.offset - result.tube_inner, result.domain.h,
                                                 lone, std::move(ring), fan)
                      : keep_points_deep(mesh, points, result.offset - result.tube_inner, result.domain.h, lone);
    }
    if (guard) *guard = report;
    return mesh;
}

}  // namespace snvr
