// The method, once: grid, distance, phase field, then Nt operator-split steps
// (implicit linear solve by multigrid, exact nonlinear step), on any backend.
#include "snvr/reconstruct.hpp"
#include "snvr/stopwatch.hpp"

#include <cmath>
#include <cstdio>

#include "geometry/band_distance.hpp"
#include "solver/backend.hpp"
#include "solver/hierarchy.hpp"
#include "solver/multigrid.hpp"
#include "geometry/domain_plan.hpp"
#include "snvr/error.hpp"

namespace snvr {

namespace {


void check_points(const PointSet& points) {
    if (points.empty()) throw InputError("the point set is empty");
    for (std::size_t n = 0; n < points.size(); ++n)
        for (double v : points[n])
            if (!std::isfinite(v)) throw InputError("point " + std::to_string(n) + " has a non-finite coordinate");
}

void report(const ProgressCallback& cb, const std::string& stage, const std::string& message) {
    if (cb) {
        Progress p;
        p.stage = stage;
        p.message = message;
        cb(p);
    }
}

template <class Real>
void run(const PointSet& points, const Parameters& params, const ProgressCallback& progress, Result& res,
         Stopwatch& clock) {
    const PointIndex index(points);
    const DomainPlan plan = plan_domain(points, params, index);
    const Domain& dom = plan.domain;
    res.domain = dom;
    res.offset = plan.offset;
    res.offset_reason = plan.offset_reason;
    res.gap = plan.gap;
    res.eps = plan.eps;
    res.xi = plan.xi;
    res.dt = plan.dt;
    res.tube_inner = plan.tube_inner;
    res.tube_outer = plan.tube_outer;
    const double L = dom.length_scale();
    const Band band = band_of(plan, params.band_xi);

    std::string notice;
    std::unique_ptr<Backend<Real>> backend = make_backend<Real>(params.device, notice);
    if (!notice.empty()) res.warnings.push_back(notice);
    res.backend = backend->name();
    res.seconds.domain = clock.lap();
    report(progress, "domain",
           "grid " + std::to_string(dom.nx) + "x" + std::to_string(dom.ny) + "x" + std::to_string(dom.nz) + ", " +
               std::to_string(dom.levels) + " multigrid levels, backend " + res.backend);

    BandDistance<Real> dist = band_distance<Real>(points, index, dom, band);
    classify_band(dist, dom, band);
    res.active_cells = dist.active_cells;
    res.seconds.distance = clock.lap();
    report(progress, "distance",
           std::to_string(dist.queried_cells) + " cells queried, " + std::to_string(dist.active_cells) +
               " in the band");

    Hierarchy hier = make_levels(dom);
    set_active_bricks(hier, dist.brick_mask);
    res.active_bricks = hier.levels[0].bricks.size();
    res.total_bricks = hier.levels[0].brick_count();
    try {
        backend->setup(hier);
    } catch (const ResourceError& e) {
        // Under auto, a device too small for this grid is not the end: the host may hold it.
        if (params.device != "auto" || backend->name().rfind("opencl", 0) != 0) throw;
        res.warnings.push_back(std::string(e.what()) + "; running on the OpenMP reference backend");
        backend = make_backend<Real>("openmp", notice);
        res.backend = backend->name();
        backend->setup(hier);
    }
    backend->init_phase(dist.distance.data(), Real(band.offset), Real(1 / (std::sqrt(2.0) * plan.xi / L)),
                        Real(band.cut));
    MultigridSettings ms;
    ms.dt = plan.dt;
    ms.tol = params.tol;
    ms.max_cycles = params.max_cycles;
    ms.pre_smooth = params.pre_smooth;
    ms.post_smooth = params.post_smooth;
    ms.trilinear = params.trilinear;
    ms.omega = params.omega;
    ms.exact_coarse = params.exact_coarse;
    ms.exact_level = prepare_coarse_levels(*backend, hier, ms);
    res.solver_bytes = backend->bytes() + dist.distance.size() * sizeof(Real);
    dist.distance = std::vector<Real>();  // the phase field now lives in the backend
    res.seconds.init = clock.lap();
    report(progress, "init",
           "phase field on " + std::to_string(res.active_bricks) + " of " + std::to_string(res.total_bricks) +
               " bricks, " + std::to_string(res.solver_bytes >> 20) + " MiB of fields");

    const double eps_n = plan.eps / L;
    const Real k = Real(2 * plan.dt / (eps_n * eps_n));
    const Tube<Real> tube = tube_of<Real>(plan);
    for (int step = 1; step <= plan.steps; ++step) {
        StepStats st;
        st.step = step;
        const LinearSolveStats ls = solve_linear(*backend, hier, ms);
        st.seconds_linear = clock.lap();
        backend->nonlinear(k, tube);
        backend->finish();  // devices run asynchronously: charge the step its own time
        st.seconds_nonlinear = clock.lap();
        st.cycles = ls.cycles;
        st.converged = ls.converged;
        st.initial_residual = ls.initial_residual;
        st.cycle_residuals = ls.residuals;
        st.bytes_moved = ls.bytes_moved + nonlinear_bytes(hier, sizeof(Real));
        st.residual = ls.residuals.empty() ? ls.initial_residual : ls.residuals.back();
        res.seconds.steps += st.seconds_linear + st.seconds_nonlinear;
        res.steps.push_back(st);
        if (!st.converged) {
            char text[160];
            std::snprintf(text, sizeof text, "step %d did not converge: residual %.3g after %d V-cycles (tol %g)", step,
                          st.residual, st.cycles, params.tol);
            res.warnings.push_back(text);
        }
        if (progress) {
            Progress p;
            p.stage = "step";
            p.step = step;
            p.steps = plan.steps;
            p.stats = &res.steps.back();
            progress(p);
        }
    }

    res.phi.nx = dom.nx;
    res.phi.ny = dom.ny;
    res.phi.nz = dom.nz;
    res.phi.precision = params.precision;
    std::vector<Real>& out = [&]() -> std::vector<Real>& {
        if constexpr (std::is_same_v<Real, double>) return res.phi.f64;
        else return res.phi.f32;
    }();
    out.resize(dom.cells());
    backend->download(0, FieldKind::phi, out.data());
}

}  // namespace

Result reconstruct(const PointSet& points, const Parameters& params, const ProgressCallback& progress) {
    check_points(points);
    Stopwatch clock, total;
    Result res;
    if (params.precision == Precision::Double) run<double>(points, params, progress, res, clock);
    else run<float>(points, params, progress, res, clock);
    res.seconds.total = total.lap();
    return res;
}

}  // namespace snvr
