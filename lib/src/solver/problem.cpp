#include "solver/problem.hpp"

#include <algorithm>
#include <cmath>

namespace snvr {

Band band_of(const DomainPlan& plan, double band_xi) {
    const double L = plan.domain.length_scale();
    return {plan.offset / L, std::max(band_xi * plan.xi, plan.domain.h) / L};
}

MultigridSettings multigrid_settings(const Parameters& params, double dt) {
    MultigridSettings ms;
    ms.dt = dt;
    ms.tol = params.tol;
    ms.max_cycles = params.max_cycles;
    ms.pre_smooth = params.pre_smooth;
    ms.post_smooth = params.post_smooth;
    ms.omega = params.omega;
    ms.trilinear = params.trilinear;
    ms.exact_coarse = params.exact_coarse;
    return ms;
}

Problem make_problem(const DomainPlan& plan, const Parameters& params) {
    Problem p;
    p.plan = plan;
    const double L = plan.domain.length_scale();
    p.band = band_of(plan, params.band_xi);
    p.profile_slope = 1 / (std::sqrt(2.0) * plan.xi / L);
    p.steps = plan.planned_steps;
    const double eps = plan.eps / L;
    p.nonlinear_rate = 2 * plan.dt / (eps * eps);
    p.multigrid = multigrid_settings(params, plan.dt);
    return p;
}

}  // namespace snvr
