#include "solver/session.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <future>
#include <system_error>
#include <type_traits>

#include "geometry/band_distance.hpp"
#include "geometry/added_points.hpp"
#include "process_limits.hpp"
#include "solver/operations.hpp"
#include "solver/solver_memory.hpp"
#include "snvr/error.hpp"
#include "snvr/stopwatch.hpp"

namespace snvr {

namespace {

// Level 0's distance in the layout's storage: the active bricks' cells (every active
// brick is near the points), zero beyond the grid and in the constant bricks.
template <class Real>
std::vector<Real> pack_band(const BrickLayout& layout, const BandDistance<Real>& dist) {
    const Level& lv = layout.level(0);
    const BrickGrid& bg = layout.grid(0);
    std::vector<Real> packed(bg.storage(), Real(0));
    std::size_t t = 0;  // both brick lists ascend
    for (std::uint32_t b : lv.bricks) {
        while (dist.near_bricks[t] != b) ++t;
        const CellRange r = lv.range(b);
        const Real* from = dist.brick_values(t);
        Real* to = packed.data() + bg.base(b);
        for (int k = 0; k < r.k1 - r.k0; ++k)
            for (int j = 0; j < r.j1 - r.j0; ++j)
                for (int i = 0; i < r.i1 - r.i0; ++i) to[BrickGrid::local(i, j, k)] = from[BrickGrid::local(i, j, k)];
    }
    return packed;
}

void report(const ProgressCallback& cb, const std::string& stage, const std::string& message) {
    if (!cb) return;
    Progress p;
    p.stage = stage;
    p.message = message;
    if (!cb(p)) throw Cancelled("cancelled before the " + stage + " stage");
}

}  // namespace

PointCloud points_with_added(const PointCloud& points, DomainPlan& plan) {
    // At most 4 voxels (a quarter of the offset) beyond the points' box: the grid pads the
    // box by the offset and over 6 voxels more, and the shell keeps the offset from every
    // point.
    AddedPoints added;
    const double slack = std::min(4 * plan.domain.h, 0.25 * plan.offset);
    PointCloud with_added = with_added_points(points, plan.hole_least, plan.upsample_spacing, slack, added);
    plan.hole_fills = added.at_holes;
    plan.upsampled = added.between;
    return with_added;
}

template <class Real>
SolverSession<Real>::SolverSession(const PointCloud& points, const Parameters& params, const ProgressCallback& progress) {
    Stopwatch clock;
    // Under `auto` the backend starts beside the planning and the distance (on PoCL,
    // loading the driver and the program takes 0.1 s), as any failure there only falls
    // back to OpenMP; a named device starts first, so that a wrong one stops the run
    // before any work.
    // Under a memory limit, or where its thread cannot start, the backend starts here
    // after the planning: a thread of its own would start a team of OpenMP threads of its
    // own too, which the runtime ends the process for when the room is not there.
    if (!detail::settle_threads().empty()) facts_.notes.push_back(detail::settle_threads());
    std::vector<std::string> start_notes;
    std::future<std::unique_ptr<Backend<Real>>> starting;
    bool start_later = params.device == "auto" && !detail::memory_limit_text().empty();
    if (params.device != "auto") {
        backend_ = make_backend<Real>(params.device, facts_.notes);
    } else if (!start_later) {
        try {
            starting = std::async(std::launch::async, [&] { return make_backend<Real>(params.device, start_notes); });
        } catch (const std::system_error& e) {
            start_later = true;
            facts_.notes.push_back(std::string("the backend could not start beside the planning (") + e.what() +
                                   "): started after it");
        }
    }
    problem_ = make_problem(plan_domain(points, params), params);
    facts_.seconds_domain = clock.lap();
    report(progress, "domain",
           "grid " + std::to_string(domain().nx) + "x" + std::to_string(domain().ny) + "x" +
               std::to_string(domain().nz) + ", " + std::to_string(domain().levels) + " multigrid levels");
    const PointCloud with_added = points_with_added(points, problem_.plan);
    const double adding = clock.lap();  // charged to the distance, which it is for
    prepare(with_added.empty() ? points : with_added, params, progress, [&] {
        if (starting.valid()) backend_ = starting.get();
        if (start_later) backend_ = make_backend<Real>(params.device, start_notes);
        facts_.notes.insert(facts_.notes.end(), start_notes.begin(), start_notes.end());
    });
    facts_.seconds_distance += adding;
}

template <class Real>
SolverSession<Real>::SolverSession(const PointCloud& measured, const DomainPlan& plan, const Parameters& params,
                                   std::unique_ptr<Backend<Real>> backend, const ProgressCallback& progress) {
    backend_ = backend ? std::move(backend) : make_backend<Real>(params.device, facts_.notes);
    problem_ = make_problem(plan, params);
    prepare(measured, params, progress, [] {});
}

template <class Real>
void SolverSession<Real>::prepare(const PointCloud& measured, const Parameters& params,
                                  const ProgressCallback& progress, const std::function<void()>& backend_ready) {
    Stopwatch clock;
    const Domain& dom = domain();
    const Band& band = problem_.band;
    BandDistance<Real> dist = band_distance<Real>(detail::tree_of(measured), dom, band, [&](std::size_t near_bricks) {
        require_memory(band_distance_bytes(near_bricks, params.precision) + problem_.plan.estimated_bytes, dom);
    });
    classify_band(dist, dom, band);
    facts_.queried_cells = dist.queried_cells;
    facts_.active_cells = dist.active_cells;
    facts_.seconds_distance = clock.lap();
    report(progress, "distance",
           std::to_string(dist.queried_cells) + " cells queried, " + std::to_string(dist.active_cells) + " in the band");

    backend_ready();
    layout_ = make_layout(dom, dist.brick_mask, dist.inside_bricks);
    {
        // Held now: the band's distance; then its packed copy beside it, then the fields
        // once it is gone.
        const std::size_t near = dist.near_values.size() * sizeof(Real);
        const std::size_t packed = layout_.grid(0).storage() * sizeof(Real);
        require_memory(std::max(layout_bytes(layout_, params.precision), near + packed) + problem_.plan.estimated_bytes,
                       dom, near);
    }
    facts_.active_bricks = layout_.level(0).bricks.size();
    facts_.total_bricks = layout_.level(0).brick_count();
    // The band's distance moves into the layout's storage before the fields exist, and
    // from there into the backend: never three copies at once.
    std::vector<Real> packed = pack_band(layout_, dist);
    dist.near_values = std::vector<Real>();
    setup_backend(backend_, params.device, layout_, facts_.notes);
    facts_.backend = backend_->name();
    backend_->init_phase(std::move(packed), Real(band.offset), Real(problem_.profile_slope), Real(band.cut));
    facts_.solver_bytes = backend_->bytes();
    problem_.multigrid.exact_level = prepare_coarse_levels(*backend_, hierarchy(), problem_.multigrid);
    backend_->finish();
    facts_.seconds_init = clock.lap();
    report(progress, "init",
           "phase field on " + std::to_string(facts_.active_bricks) + " of " + std::to_string(facts_.total_bricks) +
               " bricks, " + std::to_string(facts_.solver_bytes >> 20) + " MiB of fields, backend " + facts_.backend);
}

template <class Real>
StepStats SolverSession<Real>::step(int least_cycles) {
    Stopwatch clock;
    StepStats st;
    st.step = ++steps_done_;
    MultigridSettings settings = problem_.multigrid;
    settings.min_cycles = least_cycles;
    const LinearSolveStats ls = solve_linear(*backend_, hierarchy(), settings);
    st.seconds_linear = clock.lap();
    OperationArgs<Real> nonlinear;
    nonlinear.rate = Real(problem_.nonlinear_rate);
    nonlinear.tube = problem_.tube<Real>();
    run_operation(*backend_, Operation::nonlinear, 0, nonlinear);
    backend_->finish();  // devices run asynchronously: charge the step its own time
    st.seconds_nonlinear = clock.lap();
    st.cycles = ls.cycles;
    st.converged = ls.converged;
    st.initial_residual = ls.initial_residual;
    st.cycle_residuals = ls.residuals;
    st.bytes_moved = ls.bytes_moved + operation_bytes(Operation::nonlinear, hierarchy(), 0, sizeof(Real));
    st.residual = ls.residuals.empty() ? ls.initial_residual : ls.residuals.back();
    return st;
}

template <class Real>
void SolverSession<Real>::field(Real* dense) {
    backend_->download(0, FieldKind::phi, dense);
}

template <class Real>
Field SolverSession<Real>::take_field() {
    static_assert(Field::kBrick == kBrick && Field::kBrickCells == kBrickCells, "a Field brick is a solver brick");
    const Domain& dom = domain();
    // Constant slots first, as BrickGrid lays them out.
    return Field::from_bricks(dom.nx, dom.ny, dom.nz, layout_.grid(0).slot, backend_->take_phase());
}

template class SolverSession<double>;
template class SolverSession<float>;

}  // namespace snvr
