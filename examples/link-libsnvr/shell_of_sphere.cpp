// A complete use of the library: sample a sphere, make the printable shell around it the
// way snvr-cl does (outliers, reconstruction, mesh, depth guard, check), write it as STL.
#include <cstdio>

#include <snvr/snvr.hpp>
#include "snvr/shapes.hpp"

int main(int argc, char** argv) {
    const char* out = argc > 1 ? argv[1] : "sphere-shell.stl";
    try {
        const snvr::PointSet points = snvr::shapes::sphere({0, 0, 0}, 1.0, 0.02);
        snvr::ShellSettings settings;
        settings.params.resolution = 64;
        settings.written_as = out;  // the mesh as STL holds it, and checked so
        const snvr::Shell shell = snvr::make_shell(points, settings, [](const snvr::Progress& p) {
            if (p.stats) std::printf("step %d/%d: %d V-cycles\n", p.step, p.steps, p.stats->cycles);
            return true;  // false would cancel (snvr::Cancelled)
        });
        const snvr::MeshQuality& q = shell.quality;
        std::printf("%zu triangles, closed %d, manifold %d, %zu of %zu points inside, the shallowest %.3g x offset deep\n",
                    shell.mesh.triangles.size(), q.report.closed(), q.report.manifold(), q.points_inside, shell.points,
                    q.depth_min);
        for (const std::string& w : shell.warnings) std::printf("warning: %s\n", w.c_str());
        snvr::write_mesh(shell.mesh, out);
        return q.report.closed() && q.report.manifold() ? 0 : 1;
    } catch (const snvr::Error& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
}
