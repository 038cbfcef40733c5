// A complete use of the library: sample a sphere, reconstruct its narrow volume,
// check the mesh, write it as STL.
#include <cstdio>

#include <snvr/snvr.hpp>

int main(int argc, char** argv) {
    const char* out = argc > 1 ? argv[1] : "sphere-shell.stl";
    try {
        const snvr::PointSet points = snvr::shapes::sphere({0, 0, 0}, 1.0, 0.02);
        snvr::Parameters params;
        params.resolution = 64;
        params.steps = 4;
        const snvr::Result result = snvr::reconstruct(points, params, [](const snvr::Progress& p) {
            if (p.stats) std::printf("step %d/%d: %d V-cycles\n", p.step, p.steps, p.stats->cycles);
        });
        const snvr::Mesh mesh = snvr::extract_isosurface(result.phi, result.domain, 0.0, snvr::Interpolation::PhaseField);
        const snvr::MeshReport report = snvr::check_mesh(mesh);
        std::printf("%zu triangles, closed %d, manifold %d, %zu of %zu points inside\n", report.triangles,
                    report.closed(), report.manifold(), snvr::count_points_inside(mesh, points), points.size());
        snvr::write_mesh(mesh, out);
        return report.closed() && report.manifold() ? 0 : 1;
    } catch (const snvr::Error& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
}
