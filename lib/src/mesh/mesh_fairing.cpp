// Taubin's lambda|mu smoothing: a low-pass filter on the vertex positions that removes
// what is a few vertices across (the isosurface's facets around grid nodes, a voxel's
// worth of scan noise) without shrinking what is larger. A plain umbrella step
// x += lambda (mean of ring - x) shrinks every curved surface; the following step with
// mu < -lambda inflates it back, so the pair passes ring-Laplacian eigenvalues below
// the pass band k_PB = 1/lambda + 1/mu unchanged and damps those above it.
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "snvr/error.hpp"
#include "snvr/mesh.hpp"
#include "mesh/vertex_lists.hpp"
#include "parallel_sizes.hpp"

namespace snvr {

void MeshFairing::validate() const {
    if (passes < 0 || passes > max_passes)
        throw ParameterError("mesh fairing (--fairing) must be 0 to " + std::to_string(max_passes) + " passes, got " +
                             std::to_string(passes));
    if (!(lambda > 0 && lambda < 1))
        throw ParameterError("mesh fairing: lambda must be in (0, 1), got " + std::to_string(lambda));
    if (!(pass_band > 0 && pass_band < 1))
        throw ParameterError("mesh fairing: the pass band must be in (0, 1), got " + std::to_string(pass_band));
}

void fair_mesh(Mesh& mesh, const MeshFairing& fairing) {
    fairing.validate();
    if (fairing.passes == 0 || mesh.triangles.empty()) return;
    detail::fair_mesh(mesh, fairing, detail::rings(mesh));
}

void detail::fair_mesh(Mesh& mesh, const MeshFairing& fairing, const VertexLists& ring) {
    fairing.validate();
    if (fairing.passes == 0 || mesh.triangles.empty()) return;
    // 1/lambda + 1/mu = k_PB.
    const double mu = fairing.lambda / (fairing.pass_band * fairing.lambda - 1);
    const std::ptrdiff_t nv = std::ptrdiff_t(mesh.vertices.size());
    std::vector<Vec3> next(mesh.vertices.size());
    for (int step = 0; step < 2 * fairing.passes; ++step) {
        const double f = step % 2 == 0 ? fairing.lambda : mu;
        const std::vector<Vec3>& x = mesh.vertices;
#pragma omp parallel for schedule(static) if (nv > detail::kParallelItems)
        for (std::ptrdiff_t v = 0; v < nv; ++v) {
            const std::size_t b = ring.start[std::size_t(v)], e = ring.start[std::size_t(v) + 1];
            const Vec3& here = x[std::size_t(v)];
            Vec3& moved = next[std::size_t(v)];
            moved = here;
            if (b == e) continue;  // a vertex no triangle uses
            Vec3 mean{0, 0, 0};
            for (std::size_t i = b; i < e; ++i)
                for (int d = 0; d < 3; ++d) mean[d] += x[ring.items[i]][d];
            for (int d = 0; d < 3; ++d) moved[d] += f * (mean[d] / double(e - b) - here[d]);
        }
        mesh.vertices.swap(next);
    }
}

}  // namespace snvr
