// The default mesher of a reconstruction, in one place for the CLI, benchmarks and tests:
// dual marching cubes (a third of the tetrahedra mesher's triangles, smoother normals),
// then the tube's depth made good between grid nodes.
#include "snvr/mesh.hpp"
#include "snvr/reconstruct.hpp"

namespace snvr {

Mesh shell_mesh(const Result& result, const PointSet& points, DepthGuardReport* guard) {
    Mesh mesh = extract_dual_isosurface(result.phi, result.domain, 0.0, Interpolation::PhaseField);
    DepthGuardReport report;
    // Below the sampling gap the shell is a chain of beads around single points; lifting
    // each bead's top made it grainier (undersampled torus: 8.1 -> 8.8 deg dihedral).
    if (result.tube_inner > 0 && result.offset >= result.gap)
        report = keep_points_deep(mesh, points, result.offset - result.tube_inner, result.domain.h);
    if (guard) *guard = report;
    return mesh;
}

}  // namespace snvr
