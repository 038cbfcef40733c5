// End-to-end figures for one point cloud: seconds per stage (read to mesh written),
// V-cycles and contraction per step, peak memory, and how far the time steps are
// from the memory-bandwidth floor measured on this machine in the same run.
//
//   bench_pipeline FILE [--resolution N] [--steps N] [--precision double|float] [--out MESH]
#include <omp.h>
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "host_measures.hpp"
#include "snvr/snvr.hpp"

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s FILE [--resolution N] [--steps N] [--precision double|float] [--out MESH]\n", argv[0]);
        return 2;
    }
    snvr::Parameters params;
    params.resolution = 256;
    params.steps = 6;
    std::string out = "/tmp/bench_pipeline.stl";
    for (int a = 2; a + 1 < argc; a += 2) {
        const std::string opt = argv[a], val = argv[a + 1];
        if (opt == "--resolution") params.resolution = std::atoi(val.c_str());
        else if (opt == "--steps") params.steps = std::atoi(val.c_str());
        else if (opt == "--precision") params.precision = val == "float" ? snvr::Precision::Single : snvr::Precision::Double;
        else if (opt == "--out") out = val;
        else if (opt == "--pre") params.pre_smooth = std::atoi(val.c_str());
        else if (opt == "--post") params.post_smooth = std::atoi(val.c_str());
        else if (opt == "--prolong") params.trilinear = val != "constant";
        else if (opt == "--band") params.band_xi = std::atof(val.c_str());
        else if (opt == "--omega") params.omega = std::atof(val.c_str());
        else if (opt == "--coarse") params.exact_coarse = val != "sweeps";
        else if (opt == "--device") params.device = val;
        else {
            std::fprintf(stderr, "unknown option %s\n", opt.c_str());
            return 2;
        }
    }
    try {
        const auto t0 = std::chrono::steady_clock::now();
        auto t = t0;
        const snvr::PointSet points = snvr::read_points(argv[1]);
        const double read_s = seconds_since(t);
        const snvr::Result r = snvr::reconstruct(points, params);
        t = std::chrono::steady_clock::now();
        const snvr::Mesh mesh = snvr::extract_isosurface(r.phi, r.domain, 0.0, snvr::Interpolation::PhaseField);
        const double mesh_s = seconds_since(t);
        t = std::chrono::steady_clock::now();
        snvr::write_mesh(mesh, out);
        const double write_s = seconds_since(t);
        const double total = seconds_since(t0);

        const snvr::MeshReport rep = snvr::check_mesh(mesh);
        const std::size_t inside = snvr::count_points_inside(mesh, points);
        const double peak_mib = snvr::bench::peak_rss_mib();  // before the triad's own arrays
        const double bandwidth = snvr::bench::triad_bandwidth();

        std::printf("file %s, %zu points, grid %dx%dx%d, %s, %s precision, %d threads\n", argv[1], points.size(),
                    r.domain.nx, r.domain.ny, r.domain.nz, r.backend.c_str(),
                    params.precision == snvr::Precision::Double ? "double" : "single", omp_get_max_threads());
        std::printf("active cells %zu (%.1f%%), active bricks %zu of %zu\n", r.active_cells,
                    100.0 * double(r.active_cells) / double(r.domain.cells()), r.active_bricks, r.total_bricks);
        double bytes = 0;
        int cycles = 0;
        for (const snvr::StepStats& s : r.steps) {
            bytes += s.bytes_moved;
            cycles += s.cycles;
            std::printf("step %d: %d cycles, residual %.2e -> %.2e, contraction", s.step, s.cycles, s.initial_residual,
                        s.residual);
            double prev = s.initial_residual;
            for (double x : s.cycle_residuals) {
                std::printf(" %.3f", x / prev);
                prev = x;
            }
            std::printf(", linear %.3f s, nonlinear %.3f s\n", s.seconds_linear, s.seconds_nonlinear);
        }
        std::printf("seconds: read %.3f domain %.3f distance %.3f init %.3f steps %.3f mesh %.3f write %.3f | end to end %.3f\n",
                    read_s, r.seconds.domain, r.seconds.distance, r.seconds.init, r.seconds.steps, mesh_s, write_s, total);
        std::printf("V-cycles %d; steps moved at least %.2f GB; triad bandwidth %.2f GB/s; floor %.3f s; steps at %.1f%% of the floor rate\n",
                    cycles, bytes / 1e9, bandwidth / 1e9, bytes / bandwidth, 100.0 * (bytes / bandwidth) / r.seconds.steps);
        std::printf("mesh: %zu triangles, closed %s, manifold %s, oriented %s, %zu components, %zu of %zu points inside\n",
                    rep.triangles, rep.closed() ? "yes" : "no", rep.manifold() ? "yes" : "no",
                    rep.oriented() ? "yes" : "no", rep.components, inside, points.size());
        std::printf("peak RSS %.1f MiB (solver fields and distance %.1f MiB)\n", peak_mib, double(r.solver_bytes) / (1 << 20));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    return 0;
}
