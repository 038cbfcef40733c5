// The run in the solver's units (the grid's longest side is 1). Every conversion from
// Parameters and the world-unit plan happens here, once: the band, the initial
// profile's slope, the time step and its count, the nonlinear rate, the tube and the
// multigrid settings. The session, the benchmarks and the tests all start from this.
#pragma once
#include <cmath>

#include "geometry/band_distance.hpp"
#include "solver/backend.hpp"
#include "solver/multigrid.hpp"
#include "snvr/parameters.hpp"
#include "snvr/reconstruct.hpp"

namespace snvr {

// The band of a planned run: cut = band_xi * xi, but at least a cell, because d changes
// by at most h from cell to cell: then no cell jumps across the band, and a brick
// without band cells is all +1 or all -1.
Band band_of(const DomainPlan& plan, double band_xi);

// The tube of a planned run (backend.hpp), normalised; off for a free flow.
template <class Real>
Tube<Real> tube_of(const DomainPlan& plan) {
    Tube<Real> t;
    if (plan.tube_inner <= 0) return t;
    const double L = plan.domain.length_scale();
    t.inner = Real((plan.offset - plan.tube_inner) / L);
    t.outer = Real((plan.offset + plan.tube_outer) / L);
    t.s = Real(L / (std::sqrt(2.0) * plan.xi));
    return t;
}

struct Problem {
    DomainPlan plan;              // world units, as fitted to the points
    Band band;                    // offset l and cut, normalised
    double profile_slope = 0;     // 1 / (sqrt(2) xi), normalised: phi0 = tanh((l - d) slope)
    int steps = 0;                // time steps Nt
    double nonlinear_rate = 0;    // k = 2 dt / eps^2 of the exact nonlinear step (eq. 11)
    MultigridSettings multigrid;  // dt (normalised) and the linear solver's settings

    template <class Real>
    Tube<Real> tube() const { return tube_of<Real>(plan); }
};

Problem make_problem(const DomainPlan& plan, const Parameters& params);

// The linear solver's settings from the parameters (their defaults live there only).
MultigridSettings multigrid_settings(const Parameters& params, double dt);

}  // namespace snvr
