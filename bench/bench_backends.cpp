// The two backends side by side in one run, both precisions: a whole reconstruction
// (seconds per stage, V-cycles), then each device's smoothing half sweep against a
// copy over the same bricks on that device (achieved bandwidth and its fraction).
//
//   bench_backends FILE [--resolution N] [--steps N] [--devices openmp,opencl] [--repeat N]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "prepared_solver.hpp"

using namespace snvr;

namespace {

struct Row {
    std::string device, precision, backend;
    StageSeconds stage;
    double mesh = 0;
    int cycles = 0;
    double smooth_gbs = 0, copy_gbs = 0, step_floor_gb = 0;
};

template <class Real>
Row measure(const PointSet& points, Parameters params, int repeat) {
    Row row;
    row.device = params.device;
    row.precision = sizeof(Real) == 8 ? "double" : "float";
    params.precision = sizeof(Real) == 8 ? Precision::Double : Precision::Single;
    warmup(params.device, sizeof(Real) == 4);  // the OpenCL build is not the solver's time
    const Result r = reconstruct(points, params);
    row.backend = r.backend;
    row.stage = r.seconds;
    const auto t0 = std::chrono::steady_clock::now();
    const Mesh mesh = extract_isosurface(r.phi, r.domain, 0.0, Interpolation::PhaseField);
    row.mesh = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (const StepStats& s : r.steps) {
        row.cycles += s.cycles;
        row.step_floor_gb += s.bytes_moved / 1e9;
    }

    bench::PreparedSolver<Real> solver(points, params);
    const double bytes = double(solver.hierarchy.levels[0].brick_cells) * sizeof(Real);
    const Real omega = Real(params.omega);
    const double smooth = solver.best_seconds(repeat, [&] { solver.backend->smooth(0, 0, solver.coefficient, omega); });
    const double copy = solver.best_seconds(repeat, [&] { solver.backend->load_rhs(); });
    row.smooth_gbs = 4 * bytes / smooth / 1e9;  // reads phi, rhs, g, writes phi
    row.copy_gbs = 2 * bytes / copy / 1e9;
    return row;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s FILE [--resolution N] [--steps N] [--devices openmp,opencl] [--repeat N]\n", argv[0]);
        return 2;
    }
    Parameters params;
    params.resolution = 256;
    params.steps = 6;
    std::string devices = "openmp,opencl";
    int repeat = 20;
    for (int a = 2; a + 1 < argc; a += 2) {
        const std::string opt = argv[a], val = argv[a + 1];
        if (opt == "--resolution") params.resolution = std::atoi(val.c_str());
        else if (opt == "--steps") params.steps = std::atoi(val.c_str());
        else if (opt == "--devices") devices = val;
        else if (opt == "--repeat") repeat = std::atoi(val.c_str());
    }
    try {
        const PointSet points = read_points(argv[1]);
        std::vector<Row> rows;
        std::stringstream list(devices);
        std::string device;
        while (std::getline(list, device, ',')) {
            params.device = device;
            rows.push_back(measure<double>(points, params, repeat));
            rows.push_back(measure<float>(points, params, repeat));
        }
        std::printf("%s, %d cells on the longest axis, %d steps\n\n", argv[1], params.resolution, *params.steps);
        std::printf("| backend | precision | distance s | init s | steps s | mesh s | V-cycles | steps at floor rate | smooth GB/s | copy GB/s | smooth / copy |\n");
        std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
        for (const Row& r : rows)
            std::printf("| %s | %s | %.2f | %.2f | %.2f | %.2f | %d | %.2f s (%.1f GB at copy rate) | %.1f | %.1f | %.0f%% |\n",
                        r.backend.c_str(), r.precision.c_str(), r.stage.distance, r.stage.init, r.stage.steps, r.mesh, r.cycles,
                        r.step_floor_gb / r.copy_gbs, r.step_floor_gb, r.smooth_gbs, r.copy_gbs, 100 * r.smooth_gbs / r.copy_gbs);
        // Steps time of each backend against the first one, precision by precision.
        std::printf("\n");
        for (std::size_t i = 2; i < rows.size(); ++i)
            std::printf("%s / %s, %s: steps %.2fx\n", rows[i].device.c_str(), rows[i % 2].device.c_str(), rows[i].precision.c_str(),
                        rows[i].stage.steps / rows[i % 2].stage.steps);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_backends: %s\n", e.what());
        return 1;
    }
    return 0;
}
