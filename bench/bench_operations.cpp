// Each backend operation on the level-0 active bricks of a real reconstruction, timed
// alone: seconds per call, the bytes it must move (the table in solver/operations.hpp)
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
#include "solver/operations.hpp"

using namespace snvr;

template <class Real>
int run(const char* file, Parameters params, int repeat) {
    bench::PreparedSolver<Real> solver(read_points(file), params);
    Backend<Real>* backend = solver.backend;
    const Domain& dom = solver.domain;
    const Hierarchy& hier = solver.hierarchy;
    const Level& lv = hier.levels[0];
    const double cells = double(lv.brick_cells);
    const Real c = solver.coefficient, omega = Real(params.omega);
    std::printf("%s, %s: grid %dx%dx%d, %zu active bricks (%.0f cells), best of %d\n", backend->name().c_str(),
                sizeof(Real) == 8 ? "double" : "float", dom.nx, dom.ny, dom.nz, lv.bricks.size(), cells, repeat);

    OperationArgs<Real> args;
    args.coefficient = c;
    args.omega = omega;
    args.trilinear = params.trilinear;
    args.rate = Real(1e-3);
    args.tube = solver.tube;
    double copy_rate = 0;
    std::printf("| operation | ms | GB moved | GB/s | of copy |\n|---|---|---|---|---|\n");
    for (const OperationInfo& op : kOperations) {
        if (op.op == Operation::coarse_solve) continue;  // coarse levels only
        const double s = solver.best_seconds(repeat, [&] { run_operation(*backend, op.op, 0, args); });
        const double gb = operation_bytes(op.op, hier, 0, sizeof(Real)) / 1e9;
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
