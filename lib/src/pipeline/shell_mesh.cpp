// shell_mesh (reconstruct.hpp): the default mesher of a reconstruction, in one place for
// make_shell, benchmarks and tests: dual marching cubes (a third of the tetrahedra
// mesher's triangles, smoother normals), faired at the vertex scale, then the tube's
// depth made good between grid nodes.
#include "mesh/fair_and_keep_deep.hpp"
#include "pipeline/shell_mesh.hpp"
#include "solver/plan_guard.hpp"
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
    detail::KeepDeep deep = detail::keep_deep_of(result);
    deep.elsewhere = elsewhere;
    // A tiled run's surface may come faired already (Parameters::surface_fairing), and
    // its points kept deep (Parameters::surface_guard).
    const MeshFairing none{0};
    const bool to_guard = detail::has_inner_wall(result) && !result.surface_guarded;
    DepthGuardReport report = detail::fair_and_keep_deep(mesh, points, result.surface_faired ? none : fairing,
                                                         to_guard ? &deep : nullptr, begun);
    if (result.surface_guarded) report = result.surface_guard;
    if (guard) *guard = report;
    return mesh;
}

}  // namespace snvr
