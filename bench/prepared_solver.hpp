// A solver ready to run, for the operation benchmarks: a point cloud's domain, band
// and hierarchy, and a backend set up and initialised on it (coarse levels prepared,
// rhs loaded), plus a best-of-N timer that waits for the device.
#pragma once
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "solver/backend.hpp"
#include "geometry/band_distance.hpp"
#include "geometry/domain_plan.hpp"
#include "solver/hierarchy.hpp"
#include "solver/multigrid.hpp"
#include "snvr/snvr.hpp"

#include <cstdio>

namespace snvr::bench {

template <class Real>
struct PreparedSolver {
    Domain domain;
    Hierarchy hierarchy;
    std::unique_ptr<Backend<Real>> backend;
    Real coefficient = 0;  // dt / h^2 on level 0
    int exact_level = -1;  // the coarse level solved exactly, if any
    Tube<Real> tube;       // the run's tube
    double dt = 0;         // normalised

    PreparedSolver(const PointSet& points, const Parameters& params) {
        const PointIndex index(points);
        const DomainPlan plan = plan_domain(points, params, index);
        domain = plan.domain;
        const double L = domain.length_scale();
        const Band band = band_of(plan, params.band_xi);
        BandDistance<Real> dist = band_distance<Real>(points, index, domain, band);
        classify_band(dist, domain, band);
        hierarchy = make_levels(domain);
        set_active_bricks(hierarchy, dist.brick_mask);
        std::string notice;
        backend = make_backend<Real>(params.device, notice);
        backend->setup(hierarchy);
        backend->init_phase(dist.distance.data(), Real(band.offset), Real(1 / (std::sqrt(2.0) * plan.xi / L)), Real(band.cut));
        MultigridSettings ms;
        ms.dt = plan.dt;
        tube = tube_of<Real>(plan);
        dt = plan.dt;
        ms.exact_coarse = params.exact_coarse;
        exact_level = prepare_coarse_levels(*backend, hierarchy, ms);
        backend->load_rhs();
        const double h = hierarchy.levels[0].h;
        coefficient = Real(plan.dt / (h * h));
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
