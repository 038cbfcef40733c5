// CLBlast against our own kernels, for the two places the OpenCL backend could use a
// BLAS: the coarsest level's exact solve (a GEMV with its dense inverse) and the
// reductions of the residual norm. Sizes are those of a real run (FILE at the given
// resolution); best of N, each call waited for.
//
//   bench_clblast FILE [--resolution N] [--repeat N] [--device D] [--precision float|double]
#include <clblast.h>

#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "solver/coarse_inverse.hpp"
#include "opencl/runtime.hpp"
#include "prepared_solver.hpp"

using namespace snvr;

namespace {

template <class Real>
cl::Buffer random_buffer(opencl::Runtime& rt, std::size_t n, std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<Real> v(n);
    for (Real& x : v) x = Real(u(rng));
    cl::Buffer b = rt.buffer(n * sizeof(Real), "bench data");
    rt.queue().enqueueWriteBuffer(b, CL_TRUE, 0, n * sizeof(Real), v.data());
    return b;
}

void check(clblast::StatusCode s, const char* what) {
    if (s != clblast::StatusCode::kSuccess) {
        std::fprintf(stderr, "CLBlast %s failed with status %d\n", what, int(s));
        std::exit(1);
    }
}

template <class Real>
int run(const char* file, Parameters params, int repeat) {
    bench::PreparedSolver<Real> solver(read_points(file), params);
    Backend<Real>& backend = *solver.backend;
    const Hierarchy& hier = solver.hierarchy;
    const int solved = solver.exact_level;
    const Level& fine = hier.levels[0];
    std::size_t n = 0;
    if (solved > 0) {
        const Level& coarse = hier.levels[std::size_t(solved)];
        std::vector<Real> g(coarse.cells());
        backend.download(solved, FieldKind::g, g.data());
        n = coarse_inverse(coarse, std::vector<double>(g.begin(), g.end()), solver.dt / (coarse.h * coarse.h)).size();
    }
    const std::size_t cells = fine.brick_cells, bricks = fine.bricks.size();
    std::printf("%s, %s: coarse inverse %zu x %zu, %zu active bricks, %zu cells, best of %d\n\n", backend.name().c_str(),
                sizeof(Real) == 8 ? "double" : "float", n, n, bricks, cells, repeat);

    // CLBlast and our reduction kernel on buffers of their own, same device.
    opencl::Runtime rt(opencl::choose_device(params.device), sizeof(Real) == 8 ? "double" : "float");
    cl::CommandQueue& q = rt.queue();
    cl_command_queue queue = q();
    std::mt19937 rng(7);
    const cl::Buffer matrix = random_buffer<Real>(rt, n * n, rng), x = random_buffer<Real>(rt, n, rng);
    const cl::Buffer y = random_buffer<Real>(rt, n, rng), field = random_buffer<Real>(rt, cells, rng);
    const cl::Buffer partial_acc = rt.buffer(bricks * (rt.double_accumulator() ? 8 : 4), "partials");
    {
        std::vector<double> pd(bricks, 0.5);
        std::vector<float> pf(bricks, 0.5f);
        q.enqueueWriteBuffer(partial_acc, CL_TRUE, 0, bricks * (rt.double_accumulator() ? 8 : 4),
                             rt.double_accumulator() ? static_cast<const void*>(pd.data()) : static_cast<const void*>(pf.data()));
    }
    const cl::Buffer partial_real = random_buffer<Real>(rt, bricks, rng), out = rt.buffer(sizeof(double), "result");
    cl::Kernel sum = rt.kernel("sum_partials");
    const auto timed = [&](auto f) {
        f();
        q.finish();
        double best = 1e30;
        for (int r = 0; r < repeat; ++r) {
            const auto t0 = std::chrono::steady_clock::now();
            f();
            q.finish();
            best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
        return best * 1e3;
    };

    const double ours_gemv = n ? solver.best_seconds(repeat, [&] { backend.coarse_solve(solved); }) * 1e3 : 0;
    const double blas_gemv = n ? timed([&] {
        check(clblast::Gemv<Real>(clblast::Layout::kColMajor, clblast::Transpose::kNo, n, n, Real(1), matrix(), 0, n, x(), 0, 1,
                                  Real(0), y(), 0, 1, &queue),
              "Gemv");
    }) : 0;
    const double ours_sum = timed([&] {
        sum.setArg(0, partial_acc);
        sum.setArg(1, cl_uint(bricks));
        sum.setArg(2, out);
        q.enqueueNDRangeKernel(sum, cl::NullRange, cl::NDRange(256), cl::NDRange(256));
    });
    const double blas_sum = timed([&] { check(clblast::Sum<Real>(bricks, out(), 0, partial_real(), 0, 1, &queue), "Sum"); });
    const double ours_norm = solver.best_seconds(repeat, [&] { backend.residual_sum_squares(0, solver.coefficient); }) * 1e3;
    const double blas_nrm2 = timed([&] { check(clblast::Nrm2<Real>(cells, out(), 0, field(), 0, 1, &queue), "Nrm2"); });
    const double blas_dot = timed([&] { check(clblast::Dot<Real>(cells, out(), 0, field(), 0, 1, field(), 0, 1, &queue), "Dot"); });
    const double gb = double(cells) * sizeof(Real) / 1e9;

    std::printf("| task | ours, ms | CLBlast, ms | CLBlast / ours |\n|---|---|---|---|\n");
    if (n) std::printf("| coarse solve, %zu x %zu GEMV | %.3f (gather + GEMV + scatter) | %.3f (GEMV alone) | %.2f |\n", n, n,
                       ours_gemv, blas_gemv, blas_gemv / ours_gemv);
    std::printf("| sum of %zu brick partials | %.3f (sum_partials) | %.3f (Xsum) | %.2f |\n", bricks, ours_sum, blas_sum,
                blas_sum / ours_sum);
    std::printf("| residual norm over %zu cells | %.3f (residual + sums, fused) | %.3f (Xnrm2 of a stored residual, %.1f GB/s) | %.2f |\n",
                cells, ours_norm, blas_nrm2, gb / (blas_nrm2 / 1e3), blas_nrm2 / ours_norm);
    std::printf("| same, as a dot product | | %.3f (Xdot r.r, %.1f GB/s) | %.2f |\n", blas_dot, gb / (blas_dot / 1e3),
                blas_dot / ours_norm);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    bench::SolverBenchArgs args;
    args.params.resolution = 256;
    args.params.device = "opencl";
    args.repeat = 20;
    if (!bench::parse_solver_bench_args(argc, argv, args)) return 2;
    try {
        return args.single ? run<float>(args.file, args.params, args.repeat) : run<double>(args.file, args.params, args.repeat);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_clblast: %s\n", e.what());
        return 1;
    }
}
