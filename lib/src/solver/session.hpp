// One solver session: everything the method does between the points and the phase
// field, in the order it does it, written once. reconstruct(), the benchmarks and the
// tests all drive this type:
//   SolverSession<double> s(points, params);   // plan, distance, layout, backend, phi0
//   while (s.steps_done() < s.problem().steps) s.step();
//   Field phi = s.take_field();                // phi in the band's bricks; ends the session
#pragma once
#include <functional>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include "solver/backend.hpp"
#include "solver/layout.hpp"
#include "solver/problem.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/tiles.hpp"

namespace snvr {

// The distance is measured to the points and those added on their surface as the plan
// says (its hole_least and upsample_spacing; Parameters::add_points): those points, or
// none when nothing is added; the plan learns how many were added. With a scheduler of
// several processes (at the root of a tiled run) the points between are made by all of
// them (shared_upsampling.hpp).
PointCloud points_with_added(const PointCloud& points, DomainPlan& plan, TileScheduler* on = nullptr,
                             const ProgressCallback& progress = {});

// What preparing a session found and cost.
struct SessionFacts {
    std::string backend;                 // which backend runs it
    std::vector<std::string> notes;      // fallbacks and why
    std::size_t queried_cells = 0;       // cells that needed a nearest-point query
    std::size_t active_cells = 0;        // cells with g > 0
    std::size_t active_bricks = 0, total_bricks = 0;  // level 0
    std::size_t solver_bytes = 0;        // fields held by the backend
    double seconds_domain = 0, seconds_distance = 0, seconds_init = 0;
};

// A backend started by backend.hpp's rule for the run's device: a named device at once, so
// that a wrong one stops the run before any work; `auto` on a thread of its own beside the
// planning and the distance (on PoCL, loading the driver and the program takes 0.1 s), as
// any failure there only falls back to OpenMP. Under a memory limit, or where its thread
// cannot start, `auto` starts when taken: a thread of its own would start a team of OpenMP
// threads of its own too, which the runtime ends the process for when the room is not there.
template <class Real>
class BackendStart {
public:
    explicit BackendStart(const std::string& device);
    explicit BackendStart(std::unique_ptr<Backend<Real>> ready) : backend_(std::move(ready)) {}
    BackendStart(const BackendStart&) = delete;  // its thread refers to it
    BackendStart& operator=(const BackendStart&) = delete;
    // The backend (waiting for it); the start's notes go to `notes`. Once.
    std::unique_ptr<Backend<Real>> take(std::vector<std::string>& notes);
private:
    std::string device_;
    std::unique_ptr<Backend<Real>> backend_;
    std::future<std::unique_ptr<Backend<Real>>> starting_;
    std::vector<std::string> notes_, starting_notes_;
    bool later_ = false;
};

template <class Real>
class SolverSession {
public:
    // Plans the grid, computes the band distance, builds the brick layout, sets a backend
    // up on it (backend.hpp's rule), initialises phi and g and the coarse levels.
    // `progress` hears "domain", "distance" and "init" as each is done.
    SolverSession(const PointCloud& points, const Parameters& params, const ProgressCallback& progress = {});
    // The same on a plan made elsewhere (reconstruct.cpp's, or a tile's), the points
    // already with those added on their surface, on the backend `start` gives.
    SolverSession(const PointCloud& measured, const DomainPlan& plan, const Parameters& params,
                  BackendStart<Real>& start, const ProgressCallback& progress = {});

    // One operator-split time step: the linear half by multigrid, then the exact
    // nonlinear half held in the tube. Waits for the device, so its seconds are its own.
    // At least `least_cycles` V-cycles (tiles all run as many as the one that needs most).
    StepStats step(int least_cycles = 0);
    int steps_done() const { return steps_done_; }

    // phi on level 0 as a dense x-fastest array of the domain's cells.
    void field(Real* dense);
    // phi on level 0 as a Field sharing the layout's bricks (memory follows the band);
    // frees the solver's fields first. No step or field() after it.
    Field take_field();
    // The backend, for the next session, once take_field has freed its fields.
    std::unique_ptr<Backend<Real>> release_backend() { return std::move(backend_); }

    const Problem& problem() const { return problem_; }
    const Domain& domain() const { return problem_.plan.domain; }
    const BrickLayout& layout() const { return layout_; }
    const Hierarchy& hierarchy() const { return layout_.hierarchy; }
    const MultigridSettings& multigrid() const { return problem_.multigrid; }
    const SessionFacts& facts() const { return facts_; }
    Backend<Real>& backend() { return *backend_; }

private:
    // The distance, the layout, the backend (taken from `start` once the distance is
    // done), phi0 and g.
    void prepare(const PointCloud& measured, const Parameters& params, const ProgressCallback& progress,
                 BackendStart<Real>& start);
    Problem problem_;
    BrickLayout layout_;
    std::unique_ptr<Backend<Real>> backend_;
    SessionFacts facts_;
    int steps_done_ = 0;
};

}  // namespace snvr
