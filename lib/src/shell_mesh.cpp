// The default mesher of a reconstruction, in one place for the CLI, benchmarks and tests:
// dual marching cubes (a third of the tetrahedra mesher's triangles, smoother normals).
#include "snvr/mesh.hpp"
#include "snvr/reconstruct.hpp"

namespace snvr {

Mesh shell_mesh(const Result& result) {
    return extract_dual_isosurface(result.phi, result.domain, 0.0, Interpolation::PhaseField);
}

}  // namespace snvr
