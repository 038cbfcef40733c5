// reconstruct(): a solver session run through its Nt steps (session.hpp), reported
// as a Result with the phase field in the band's bricks.
#include "snvr/point_cloud.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/stopwatch.hpp"

#include <cmath>
#include <cstdio>

#include "snvr/error.hpp"
#include "solver/session.hpp"
#include "solver/tiled_reconstruct.hpp"

namespace snvr {

namespace {

std::string not_converged(const StepStats& st, double tol) {
    char text[160];
    std::snprintf(text, sizeof text, "step %d did not converge: residual %.3g after %d V-cycles (tol %g)", st.step,
                  st.residual, st.cycles, tol);
    return text;
}

template <class Real>
void run(const PointCloud& points, const Parameters& params, const ProgressCallback& progress, Result& res) {
    SolverSession<Real> session(points, params, progress);
    const Problem& problem = session.problem();
    const DomainPlan& plan = problem.plan;
    const SessionFacts& facts = session.facts();
    static_cast<DomainPlan&>(res) = plan;
    res.backend = facts.backend;
    res.warnings = facts.notes;
    res.active_cells = facts.active_cells;
    res.active_bricks = facts.active_bricks;
    res.total_bricks = facts.total_bricks;
    res.solver_bytes = facts.solver_bytes;
    res.seconds.domain = facts.seconds_domain;
    res.seconds.distance = facts.seconds_distance;
    res.seconds.init = facts.seconds_init;

    while (session.steps_done() < problem.steps) {
        res.steps.push_back(session.step());
        const StepStats& st = res.steps.back();
        res.seconds.steps += st.seconds_linear + st.seconds_nonlinear;
        if (!st.converged) res.warnings.push_back(not_converged(st, params.tol));
        if (progress) {
            Progress p;
            p.stage = "step";
            p.step = st.step;
            p.steps = problem.steps;
            p.stats = &st;
            if (!progress(p)) throw Cancelled("cancelled after step " + std::to_string(st.step));
        }
    }

    res.phi = session.take_field();
}

// Tiled where Parameters::tile_cells asks (plan_domain validates the parameters either way).
template <class Real>
void run_whole_or_tiled(const PointCloud& points, const Parameters& params, const ProgressCallback& progress,
                        TileScheduler* tiles_on, Result& res) {
    if (params.tile_cells > 0) reconstruct_tiled<Real>(points, params, progress, tiles_on, res);
    else run<Real>(points, params, progress, res);
}

}  // namespace

Result reconstruct(const PointSet& points, const Parameters& params, const ProgressCallback& progress) {
    return reconstruct(PointCloud(points), params, progress);
}

Result reconstruct(const PointCloud& points, const Parameters& params, const ProgressCallback& progress,
                   TileScheduler* tiles_on) {
    if (points.empty()) throw InputError("the point set is empty");
    Stopwatch total;
    Result res;
    if (params.precision == Precision::Double) run_whole_or_tiled<double>(points, params, progress, tiles_on, res);
    else run_whole_or_tiled<float>(points, params, progress, tiles_on, res);
    res.seconds.total = total.lap();
    return res;
}

}  // namespace snvr
