#include "solver/session.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <future>
#include <system_error>
#include <type_traits>

#include "geometry/band_distance.hpp"
#include "geometry/added_points.hpp"
#include "solver/shared_holes.hpp"
#include "solver/shared_upsampling.hpp"
#include "process_limits.hpp"
#include "told_pace.hpp"
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

PointCloud points_with_added(const PointCloud& points, DomainPlan& plan, TileScheduler* on,
                             const ProgressCallback& progress) {
    // Seeking a sparse scan's holes takes a while (a minute for 12.5 M points at 2048 cells):
    // said before, as the distance's (it is charged to it).
    if (plan.hole_least > 0 || plan.upsample_spacing > 0) {
        char text[200];
        std::snprintf(text, sizeof text, "points added %s%s%s (%zu points to look at)",
                      plan.hole_least > 0 ? "at the sampling's holes" : "",
                      plan.hole_least > 0 && plan.upsample_spacing > 0 ? " and " : "",
                      plan.upsample_spacing > 0 ? "between the points" : "", points.size());
        report(progress, "distance", text);
    }
    // At most 4 voxels (a quarter of the offset) beyond the points' box: the grid pads the
    // box by the offset and over 6 voxels more, and the shell keeps the offset from every
    // point.
    AddedPoints added;
    const double slack = std::min(4 * plan.domain.h, 0.25 * plan.offset);
    const bool shared = on && on->processes() > 1;
    bool made = false;
    MakePointsBetween between;
    AskHoles holes;
    bool holes_told = false;
    // The others wait for the holes' questions first, then the points between's.
    const auto holes_settled = [&] {
        if (!holes_told) holes_done(*on);
        holes_told = true;
    };
    if (shared) {
        between = [&](const PointCloud& so_far) {
            holes_settled();
            made = true;
            return points_between_shared(*on, so_far, plan.upsample_spacing, plan.upsampled_elsewhere);
        };
        holes = holes_shared(*on, plan.holes_sought_elsewhere);
    }
    // A pass over millions of points takes a minute: how far it has gone, every few seconds.
    detail::ToldPace pace;
    const auto tell_holes = [&](std::size_t done, std::size_t all, int pass) {
        double left = 0;
        if (!pace.due(done, all, left)) return;
        char text[160];
        std::snprintf(text, sizeof text, "holes sought at %zu of %zu points%s (pass %d), about %.0f s left", done, all,
                      shared ? " on this process" : "", pass, left);
        report(progress, "distance", text);
    };
    PointCloud with_added = with_added_points(points, plan.hole_least, plan.upsample_spacing, slack, added,
                                              {between, holes, progress ? HolesTold(tell_holes) : nullptr});
    if (shared) holes_settled();
    if (shared && !made) no_points_between(*on);
    plan.hole_fills = added.at_holes;
    plan.upsampled = added.between;
    return with_added;
}

template <class Real>
BackendStart<Real>::BackendStart(const std::string& device) : device_(device) {
    if (!detail::settle_threads().empty()) notes_.push_back(detail::settle_threads());
    later_ = device == "auto" && !detail::memory_limit_text().empty();
    if (device != "auto") {
        backend_ = make_backend<Real>(device, notes_);
    } else if (!later_) {
        try {
            starting_ = std::async(std::launch::async, [this] { return make_backend<Real>(device_, starting_notes_); });
        } catch (const std::system_error& e) {
            later_ = true;
            notes_.push_back(std::string("the backend could not start beside the planning (") + e.what() +
                             "): started after it");
        }
    }
}

template <class Real>
std::unique_ptr<Backend<Real>> BackendStart<Real>::take(std::vector<std::string>& notes) {
    if (starting_.valid()) backend_ = starting_.get();
    if (later_ && !backend_) backend_ = make_backend<Real>(device_, starting_notes_);
    notes.insert(notes.end(), notes_.begin(), notes_.end());
    notes.insert(notes.end(), starting_notes_.begin(), starting_notes_.end());
    notes_.clear();
    starting_notes_.clear();
    return std::move(backend_);
}

template <class Real>
SolverSession<Real>::SolverSession(const PointCloud& points, const Parameters& params, const ProgressCallback& progress) {
    Stopwatch clock;
    BackendStart<Real> start(params.device);
    DomainPlan plan = plan_domain(points, params);
    facts_.seconds_domain = clock.lap();
    report(progress, "domain",
           "grid " + std::to_string(plan.domain.nx) + "x" + std::to_string(plan.domain.ny) + "x" +
               std::to_string(plan.domain.nz) + ", " + std::to_string(plan.domain.levels) + " multigrid levels");
    const PointCloud with_added = points_with_added(points, plan, nullptr, progress);
    const double adding = clock.lap();  // charged to the distance, which it is for
    problem_ = make_problem(plan, params);
    prepare(with_added.empty() ? points : with_added, params, progress, start);
    facts_.seconds_distance += adding;
}

template <class Real>
SolverSession<Real>::SolverSession(const PointCloud& measured, const DomainPlan& plan, const Parameters& params,
                                   BackendStart<Real>& start, const ProgressCallback& progress) {
    problem_ = make_problem(plan, params);
    prepare(measured, params, progress, start);
}

template <class Real>
void SolverSession<Real>::prepare(const PointCloud& measured, const Parameters& params,
                                  const ProgressCallback& progress, BackendStart<Real>& start) {
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

    backend_ = start.take(facts_.notes);
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
    dist.near_values = detail::FreshVector<Real>();
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

template class BackendStart<double>;
template class BackendStart<float>;
template class SolverSession<double>;
template class SolverSession<float>;

}  // namespace snvr
