// The default mesher of a reconstruction, in one place for the CLI, benchmarks and tests:
// dual marching cubes (a third of the tetrahedra mesher's triangles, smoother normals),
// faired at the vertex scale, then the tube's depth made good between grid nodes (after
// the fairing, so that nothing undoes it).
#include <limits>

#include "snvr/mesh.hpp"
#include "snvr/reconstruct.hpp"

namespace snvr {

Mesh shell_mesh(const Result& result, const PointSet& points, DepthGuardReport* guard, const MeshFairing& fairing) {
    Mesh mesh = extract_dual_isosurface(result.phi, result.domain, 0.0, Interpolation::PhaseField);
    fair_mesh(mesh, fairing);
    DepthGuardReport report;
    // Where the offset is below the points' spacing the shell is a chain of beads around
    // single points; lifting each bead's top made it grainier (undersampled torus: 8.1 ->
    // 8.8 deg dihedral), so those points are left out, unless the offset reaches the
    // sampling gap (then the promise covers every point).
    if (result.tube_inner > 0) {
        const double lone = result.offset >= result.gap ? std::numeric_limits<double>::infinity() : result.offset;
        report = keep_points_deep(mesh, points, result.offset - result.tube_inner, result.domain.h, lone);
    }
    if (guard) *guard = report;
    return mesh;
}

}  // namespace snvr
