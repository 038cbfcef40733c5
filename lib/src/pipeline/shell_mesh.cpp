// shell_mesh (reconstruct.hpp): the default mesher of a reconstruction, in one place for
// make_shell, benchmarks and tests: dual marching cubes (a third of the tetrahedra
// mesher's triangles, smoother normals), faired at the vertex scale, then the tube's
// depth made good between grid nodes.
#include <limits>

#include "mesh/fair_and_keep_deep.hpp"
#include "pipeline/shell_mesh.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/shell.hpp"

namespace snvr {

Mesh shell_mesh(const Result& result, const PointSet& points, DepthGuardReport* guard, const MeshFairing& fairing) {
    return shell_mesh(result, PointCloud(points), guard, fairing);
}

Mesh shell_mesh(const Result& result, const PointCloud& points, DepthGuardReport* guard, const MeshFairing& fairing) {
    // A tiled run may have made the level set by its tiles instead (Parameters::whole_field).
    return detail::shell_mesh_of(result.surface_made ? result.surface : detail::level_set_of(result), result, points,
                                 guard, fairing);
}

Mesh detail::level_set_of(const Result& result) {
    return extract_dual_isosurface(result.phi, result.domain, 0.0, Interpolation::PhaseField);
}

Mesh detail::shell_mesh_of(Mesh mesh, const Result& result, const PointCloud& points, DepthGuardReport* guard,
                           const MeshFairing& fairing, const GuardElsewhere* elsewhere, const Begun& begun) {
    fairing.validate();
    // The tube's inner wall is the depth promised. Where the offset is below the points'
    // spacing the shell is a chain of beads around single points; lifting each bead's top
    // made it grainier (undersampled torus: 8.1 -> 8.8 deg dihedral), so those points are
    // left out, unless the offset reaches the sampling gap (then the promise covers every
    // point).
    detail::KeepDeep deep;
    deep.depth = result.offset - result.tube_inner;
    deep.voxel = result.domain.h;
    deep.lone = result.offset >= result.gap ? std::numeric_limits<double>::infinity() : result.offset;
    deep.elsewhere = elsewhere;
    // A tiled run's surface may come faired already (Parameters::surface_fairing).
    const MeshFairing none{0};
    const DepthGuardReport report = detail::fair_and_keep_deep(mesh, points, result.surface_faired ? none : fairing,
                                                               result.tube_inner > 0 ? &deep : nullptr, begun);
    if (guard) *guard = report;
    return mesh;
}

}  // namespace snvr
