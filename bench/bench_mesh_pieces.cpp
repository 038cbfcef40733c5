// bench_mesh_pieces CLOUD [--resolution R] [--cells C] [--margin M] [--repeat N]: the dual
// mesh of a reconstruction extracted whole and in pieces of C samples a side (what a
// tiled run's tiles extract, welded by the whole grid's keys), on this process's threads.
// Prints both times (the best of N), their ratio and whether the meshes are the same bit
// for bit (they must be).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <limits>
#include <string>

#include "mesh/dual_pieces.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/point_io.hpp"
#include "snvr/reconstruct.hpp"

namespace {

template <class F>
double best_seconds(int repeat, F&& f) {
    double best = std::numeric_limits<double>::infinity();
    for (int r = 0; r < repeat; ++r) {
        const auto start = std::chrono::steady_clock::now();
        f();
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    return best;
}

}  // namespace

int main(int argc, char** argv) {
    std::string path;
    int resolution = 256, cells = 128, margin = 0, repeat = 3;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        const bool value = i + 1 < argc;
        if (arg == "--resolution" && value) resolution = std::atoi(argv[++i]);
        else if (arg == "--cells" && value) cells = std::atoi(argv[++i]);
        else if (arg == "--margin" && value) margin = std::atoi(argv[++i]);
        else if (arg == "--repeat" && value) repeat = std::max(1, std::atoi(argv[++i]));
        else if (path.empty() && arg.rfind("--", 0) != 0) path = arg;
        else {
            std::fprintf(stderr, "usage: bench_mesh_pieces CLOUD [--resolution R] [--cells C] [--margin M] [--repeat N]\n");
            return 2;
        }
    }
    if (path.empty()) {
        std::fprintf(stderr, "usage: bench_mesh_pieces CLOUD [--resolution R] [--cells C] [--margin M] [--repeat N]\n");
        return 2;
    }
    try {
        snvr::Parameters params;
        params.resolution = resolution;
        params.precision = snvr::Precision::Single;
        const snvr::Result run = snvr::reconstruct(snvr::PointCloud(snvr::read_points(path)), params);
        snvr::Mesh whole, pieces;
        const double t_whole = best_seconds(repeat, [&] { whole = snvr::extract_dual_isosurface(run.phi, run.domain); });
        const double t_pieces =
            best_seconds(repeat, [&] { pieces = snvr::detail::extract_in_pieces(run.phi, run.domain, cells, margin); });
        const bool same = whole.vertices == pieces.vertices && whole.triangles == pieces.triangles;
        std::printf("%s at %d cells: %zu triangles; whole %.3f s, in pieces of %d (margin %d) %.3f s, %.2fx; %s\n",
                    path.c_str(), resolution, whole.triangles.size(), t_whole, cells, margin, t_pieces,
                    t_pieces / t_whole, same ? "the same mesh, bit for bit" : "DIFFERENT meshes");
        return same ? 0 : 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_mesh_pieces: %s\n", e.what());
        return 1;
    }
}
