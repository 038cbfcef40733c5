// A solver ready to run, for the operation benchmarks: a solver session (the same
// set-up as reconstruct()) with rhs loaded, its parts at hand, plus a best-of-N timer
// that waits for the device.
#pragma once
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "snvr/snvr.hpp"
#include "solver/session.hpp"

#include <cstdio>

namespace snvr::bench {

template <class Real>
struct PreparedSolver {
    SolverSession<Real> session;  // the very set-up reconstruct() runs
    Domain domain;
    const Hierarchy& hierarchy;
    Backend<Real>* backend;
    Real coefficient = 0;  // dt / h^2 on level 0
    int exact_level = -1;  // the coarse level solved exactly, if any
    Tube<Real> tube;       // the run's tube
    double dt = 0;         // normalised

    PreparedSolver(const PointSet& points, const Parameters& params)
        : session(PointCloud(points), params),
          domain(session.domain()),
          hierarchy(session.hierarchy()),
          backend(&session.backend()),
          coefficient(Real(dt_over_h2(session.multigrid().dt, hierarchy.levels[0]))),
          exact_level(session.multigrid().exact_level),
          tube(session.problem().template tube<Real>()),
          dt(session.multigrid().dt) {
        backend->load_rhs();
    }

    // Seconds of `repeat` runs of f, each waited for, after one run that is not counted
    // (PoCL compiles a kernel's work-group function at its first launch).
    std::vector<double> samples(int repeat, const std::function<void()>& f) {
        f();
        backend->finish();
        std::vector<double> t;
        for (int r = 0; r < repeat; ++r) {
            const auto t0 = std::chrono::steady_clock::now();
            f();
            backend->finish();
            t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
        return t;
    }

    double best_seconds(int repeat, const std::function<void()>& f) {
        const std::vector<double> t = samples(repeat, f);
        return *std::min_element(t.begin(), t.end());
    }
};

// The command line the per-operation benchmarks share:
//   FILE [--resolution N] [--repeat N] [--device D] [--precision float|double]
struct SolverBenchArgs {
    const char* file = nullptr;
    Parameters params;
    int repeat = 10;
    bool single = false;
};

inline bool parse_solver_bench_args(int argc, char** argv, SolverBenchArgs& args) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s FILE [--resolution N] [--repeat N] [--device D] [--precision float|double]\n", argv[0]);
        return false;
    }
    args.file = argv[1];
    for (int a = 2; a + 1 < argc; a += 2) {
        const std::string opt = argv[a];
        if (opt == "--resolution") args.params.resolution = std::atoi(argv[a + 1]);
        else if (opt == "--repeat") args.repeat = std::atoi(argv[a + 1]);
        else if (opt == "--device") args.params.device = argv[a + 1];
        else if (opt == "--precision") args.single = std::string(argv[a + 1]) == "float";
    }
    return true;
}

}  // namespace snvr::bench
