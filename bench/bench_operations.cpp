// Each backend operation on the level-0 active bricks of a real reconstruction, timed
// alone: seconds per call, the bytes it must move (the traffic model of multigrid.cpp)
// and the bandwidth that implies, next to a copy over the same bricks (load_rhs) and a
// dense triad. Tells whether an operation is at its memory floor or far from it.
//
//   bench_operations FILE [--resolution N] [--repeat N] [--device D] [--precision float|double]
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "prepared_solver.hpp"

using namespace snvr;

template <class Real>
int run(const char* file, Parameters params, int repeat) {
    bench::PreparedSolver<Real> solver(read_points(file), params);
    Backend<Real>* backend = solver.backend;
    const Domain& dom = solver.domain;
    const Hierarchy& hier = solver.hierarchy;
    const Level& lv = hier.levels[0];
    const double cells = double(lv.brick_cells), bytes_per_stream = cells * sizeof(Real);
    const Real c = solver.coefficient, omega = Real(params.omega);
    std::printf("%s, %s: grid %dx%dx%d, %zu active bricks (%.0f cells), best of %d\n", backend->name().c_str(),
                sizeof(Real) == 8 ? "double" : "float", dom.nx, dom.ny, dom.nz, lv.bricks.size(), cells, repeat);

    struct Op {
        const char* name;
        double streams;  // per cell of level 0 (coarse-level traffic ignored: 1/8 or less)
        std::function<void()> run;
    };
    const std::vector<Op> ops = {
        {"copy (load_rhs)", 2, [&] { backend->load_rhs(); }},
        {"smooth, one colour", 4, [&] { backend->smooth(0, 0, c, omega); }},
        {"residual norm", 3, [&] { backend->residual_sum_squares(0, c); }},
        {"restrict residual", 3, [&] { backend->restrict_residual(0, c); }},
        {"prolong + correct", 3, [&] { backend->prolong_correct(0, true); }},
        {"nonlinear", 4, [&] { backend->nonlinear(Real(1e-3), solver.tube); }},
    };
    double copy_rate = 0;
    std::printf("| operation | ms | GB moved | GB/s | of copy |\n|---|---|---|---|---|\n");
    for (const Op& op : ops) {
        const double s = solver.best_seconds(repeat, op.run);
        const double gb = op.streams * bytes_per_stream / 1e9;
        if (copy_rate == 0) copy_rate = gb / s;
        std::printf("| %s | %.2f | %.3f | %.1f | %.0f%% |\n", op.name, s * 1e3, gb, gb / s, 100 * (gb / s) / copy_rate);
    }
    return 0;
}

int main(int argc, char** argv) {
    bench::SolverBenchArgs args;
    args.params.resolution = 256;
    args.params.device = "openmp";
    if (!bench::parse_solver_bench_args(argc, argv, args)) return 2;
    return args.single ? run<float>(args.file, args.params, args.repeat) : run<double>(args.file, args.params, args.repeat);
}
