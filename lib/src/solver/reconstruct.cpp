// reconstruct(): a solver session run through its Nt steps (session.hpp), reported
// as a Result with the phase field in the band's bricks.
#include "snvr/point_cloud.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/stopwatch.hpp"

#include <cmath>
#include <cstdio>

#include "process_limits.hpp"
#include "spilled_memory.hpp"
#include "snvr/error.hpp"
#include "solver/memory_budget.hpp"
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
void run(const PointCloud& measured, const DomainPlan& plan, const Parameters& params, BackendStart<Real>& start,
         const ProgressCallback& progress, Result& res) {
    SolverSession<Real> session(measured, plan, params, start, progress);
    const Problem& problem = session.problem();
    const SessionFacts& facts = session.facts();
    res.backend = facts.backend;
    res.warnings = facts.notes;
    res.active_cells = facts.active_cells;
    res.active_bricks = facts.active_bricks;
    res.total_bricks = facts.total_bricks;
    res.solver_bytes = facts.solver_bytes;
    res.seconds.distance += facts.seconds_distance;
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

// The plan, then the whole grid or tiles as the memory allows (memory_budget.hpp), or as
// Parameters::tile_cells asks.
template <class Real>
void plan_and_run(const PointCloud& points, const Parameters& params, const ProgressCallback& progress,
                  TileScheduler* tiles_on, Result& res) {
    Stopwatch clock;
    BackendStart<Real> start(params.device);
    DomainPlan plan = plan_domain(points, params);
    res.seconds.domain = clock.lap();
    if (progress) {
        Progress p;
        p.stage = "domain";
        p.message = "grid " + std::to_string(plan.domain.nx) + "x" + std::to_string(plan.domain.ny) + "x" +
                    std::to_string(plan.domain.nz) + ", " + std::to_string(plan.domain.levels) + " multigrid levels";
        if (!progress(p)) throw Cancelled("cancelled after the domain stage");
    }
    const PointCloud with_added = points_with_added(points, plan, tiles_on, progress);
    const PointCloud& measured = with_added.empty() ? points : with_added;
    static_cast<DomainPlan&>(res) = plan;
    const MemoryChoice memory = fit_memory(measured, plan, params);
    res.memory = memory.facts;
    res.seconds.distance = clock.lap();  // the points added and the memory's estimate: for the distance
    if (memory.tile_cells > 0) {
        Parameters tiled = params;
        tiled.tile_cells = memory.tile_cells;
        reconstruct_tiled<Real>(measured, points, plan, tiled, start, progress, tiles_on, res);
    } else {
        run<Real>(measured, plan, params, start, progress, res);
    }
}

}  // namespace

Result reconstruct_tiles_of(const Parameters& params, TileScheduler& tiles_on) {
    params.validate();
    if (params.tile_cells <= 0) throw ParameterError("another process's share of a tiled run needs its tile size");
    Stopwatch total;
    Result res;
    // Its points and its tiles' solver keep to the budget too, its points' arrays beyond
    // it in files (as make_shell's; under serve_shell, its scopes are in force).
    const detail::BudgetScope budget(params.max_memory.value_or(0), 0);
    const detail::SpillScope spill(params.max_memory.value_or(0), 0, params.temp_dir);
    if (params.precision == Precision::Double) reconstruct_tiles_given<double>(params, tiles_on, res);
    else reconstruct_tiles_given<float>(params, tiles_on, res);
    res.seconds.total = total.lap();
    return res;
}

Result reconstruct(const PointSet& points, const Parameters& params, const ProgressCallback& progress) {
    return reconstruct(PointCloud(points), params, progress);
}

Result reconstruct(const PointCloud& points, const Parameters& params, const ProgressCallback& progress,
                   TileScheduler* tiles_on) {
    if (points.empty()) throw InputError("the point set is empty");
    Stopwatch total;
    Result res;
    detail::BudgetScope budget(params.max_memory.value_or(0), 0);
    if (params.precision == Precision::Double) plan_and_run<double>(points, params, progress, tiles_on, res);
    else plan_and_run<float>(points, params, progress, tiles_on, res);
    res.seconds.total = total.lap();
    return res;
}

}  // namespace snvr
