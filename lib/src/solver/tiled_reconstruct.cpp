// reconstruct_tiled (tiled_reconstruct.hpp).
#include "solver/tiled_reconstruct.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "geometry/point_tree.hpp"
#include "snvr/error.hpp"
#include "snvr/stopwatch.hpp"
#include "solver/field_assembly.hpp"
#include "solver/session.hpp"
#include "solver/solver_memory.hpp"
#include "solver/tile_plan.hpp"

namespace snvr {

namespace {

// What the halo may let the tile's edge move the surface in its core, in voxels: a tenth
// of what a tiled run promises against the whole one (0.01 voxels), the rest left to the
// linear solve's stopping.
constexpr double kHaloMostVoxels = 1e-3;

int round_to_bricks(int cells) { return (cells + kBrick - 1) / kBrick * kBrick; }

int halo_of(const DomainPlan& plan, const Parameters& params, bool& derived) {
    derived = !params.tile_halo_cells;
    if (!derived) return *params.tile_halo_cells;
    const double h = plan.domain.h, L = plan.domain.length_scale();
    FlowReach flow;
    flow.dt_cells = plan.dt / ((h / L) * (h / L));
    flow.steps = plan.planned_steps;
    flow.rate = 2 * flow.dt_cells * (h / plan.eps) * (h / plan.eps);
    flow.width_cells = std::max(plan.xi, plan.eps) / h;
    return round_to_bricks(flow_halo_cells(flow, kHaloMostVoxels));
}

// What each tile needs of the points: how many lie within `reach` of its box (halo
// included), and whether any lies within reach of its core. A cell's distance and band
// depend only on the points within the offset and the band's cut of it; where no point
// comes that near the core, every cell of it is -1 in the whole run from the start, and
// the tile need not run.
struct TileNeeds {
    std::size_t points = 0;
    bool core_near = false;
};

// A box of world coordinates: a tile's cells [lo, hi) widened by `reach`.
struct Reach {
    Vec3 lo, hi;
    Reach(const Domain& whole, const std::array<int, 3>& from, const std::array<int, 3>& to, double reach) {
        for (int a = 0; a < 3; ++a) {
            lo[std::size_t(a)] = whole.origin[std::size_t(a)] + from[std::size_t(a)] * whole.h - reach;
            hi[std::size_t(a)] = whole.origin[std::size_t(a)] + to[std::size_t(a)] * whole.h + reach;
        }
    }
    bool holds(const Vec3& p) const {
        for (int a = 0; a < 3; ++a)
            if (!(p[a] >= lo[a] && p[a] <= hi[a])) return false;
        return true;
    }
    bool holds(const Vec3& from, const Vec3& to) const { return holds(from) && holds(to); }
    bool meets(const Vec3& from, const Vec3& to) const {
        for (int a = 0; a < 3; ++a)
            if (to[a] < lo[a] || from[a] > hi[a]) return false;
        return true;
    }
};

// One leaf's share of the tiles' needs: a leaf's box inside the tile's reach counts whole,
// one across its edge point by point.
void add_leaf(const detail::PointTree& tree, const detail::PointTree::Node& leaf, const Domain& whole,
              const Tile& t, double reach, TileNeeds& need) {
    const Vec3 lo = tree.lo(leaf), hi = tree.hi(leaf);
    const Reach box(whole, t.lo, t.hi, reach), core(whole, t.core_lo, t.core_hi, reach);
    if (!box.meets(lo, hi)) return;
    if (box.holds(lo, hi)) {
        need.points += leaf.count();
    } else {
        for (std::uint32_t k = leaf.begin; k < leaf.end; ++k) need.points += box.holds(tree.point(k));
    }
    if (need.core_near || !core.meets(lo, hi)) return;
    for (std::uint32_t k = leaf.begin; k < leaf.end && !need.core_near; ++k) need.core_near = core.holds(tree.point(k));
}

std::vector<TileNeeds> needs_of(const detail::PointTree& tree, const Domain& whole, const std::vector<Tile>& tiles,
                                int core_cells, int halo_cells, double reach) {
    std::vector<const detail::PointTree::Node*> leaves;
    tree.for_each_leaf([](const detail::PointTree::Node&) { return true; },
                       [&](const detail::PointTree::Node& leaf) { leaves.push_back(&leaf); });
    const int n[3] = {whole.nx, whole.ny, whole.nz};
    int count[3];
    for (int a = 0; a < 3; ++a) count[a] = (n[a] + core_cells - 1) / core_cells;
    std::vector<TileNeeds> needs(tiles.size());
    const std::ptrdiff_t nl = std::ptrdiff_t(leaves.size());
#pragma omp parallel
    {
        std::vector<TileNeeds> mine(tiles.size());
#pragma omp for schedule(dynamic, 1024)
        for (std::ptrdiff_t l = 0; l < nl; ++l) {
            const detail::PointTree::Node& leaf = *leaves[std::size_t(l)];
            const Vec3 lo = tree.lo(leaf), hi = tree.hi(leaf);
            int first[3], last[3];
            for (int a = 0; a < 3; ++a) {
                // The tiles whose box can come within reach, by core; add_leaf checks exactly.
                const double cells = reach / whole.h + halo_cells;
                first[a] = std::max(0, int(std::floor(((lo[a] - whole.origin[std::size_t(a)]) / whole.h - cells) / core_cells)));
                last[a] = std::min(count[a] - 1,
                                   int(std::floor(((hi[a] - whole.origin[std::size_t(a)]) / whole.h + cells) / core_cells)));
            }
            for (int kz = first[2]; kz <= last[2]; ++kz)
                for (int ky = first[1]; ky <= last[1]; ++ky)
                    for (int kx = first[0]; kx <= last[0]; ++kx) {
                        const std::size_t t = std::size_t(kx + count[0] * (ky + count[1] * kz));
                        add_leaf(tree, leaf, whole, tiles[t], reach, mine[t]);
                    }
        }
#pragma omp critical
        for (std::size_t t = 0; t < tiles.size(); ++t) {
            needs[t].points += mine[t].points;
            needs[t].core_near = needs[t].core_near || mine[t].core_near;
        }
    }
    return needs;
}

// The tile's own plan: the whole run's in world units, on the tile's grid (whose longest
// side is the solver's unit length: dt, given normalised, follows it).
DomainPlan tile_plan(const DomainPlan& whole, const Tile& tile) {
    DomainPlan plan = whole;
    plan.domain = tile_domain(whole.domain, tile);
    const double ratio = whole.domain.length_scale() / plan.domain.length_scale();
    plan.dt = whole.dt * ratio * ratio;
    plan.estimated_bytes = estimate_plan_bytes(plan.domain);
    return plan;
}

struct TileRun {
    std::vector<StepStats> steps;
    SessionFacts facts;
};

// The tile run on the whole cloud's tree: its distance queries only the tile's cells, and
// finds there what the whole run finds.
// One backend serves every tile in turn (set up again on each tile's layout).
template <class Real>
TileRun run_tile(const PointCloud& measured, const DomainPlan& whole, const Parameters& params, const Tile& tile,
                 const std::vector<int>& least, std::unique_ptr<Backend<Real>>& backend, FieldAssembly<Real>& field) {
    SolverSession<Real> session(measured, tile_plan(whole, tile), params, std::move(backend));
    TileRun run;
    while (session.steps_done() < session.problem().steps)
        run.steps.push_back(session.step(least[std::size_t(session.steps_done())]));
    run.facts = session.facts();
    field.place(session.take_field(), tile);
    backend = session.release_backend();
    return run;
}

bool fewer_cycles(const TileRun& run, const std::vector<int>& most) {
    for (std::size_t s = 0; s < run.steps.size(); ++s)
        if (run.steps[s].cycles < most[s]) return true;
    return false;
}

void tell(const ProgressCallback& progress, const std::string& message) {
    if (!progress) return;
    Progress p;
    p.stage = "tile";
    p.message = message;
    if (!progress(p)) throw Cancelled("cancelled between tiles");
}

// The whole run's steps from its tiles': as many cycles as each took (the same in all),
// the largest residuals, the seconds and bytes of all.
void merge_steps(const std::vector<TileRun>& runs, int steps, Result& res) {
    res.steps.assign(std::size_t(steps), StepStats{});
    for (int s = 0; s < steps; ++s) {
        StepStats& st = res.steps[std::size_t(s)];
        st.step = s + 1;
        st.converged = true;
        for (const TileRun& run : runs) {
            if (run.steps.empty()) continue;
            const StepStats& t = run.steps[std::size_t(s)];
            st.cycles = std::max(st.cycles, t.cycles);
            st.converged = st.converged && t.converged;
            st.initial_residual = std::max(st.initial_residual, t.initial_residual);
            st.residual = std::max(st.residual, t.residual);
            st.seconds_linear += t.seconds_linear;
            st.seconds_nonlinear += t.seconds_nonlinear;
            st.bytes_moved += t.bytes_moved;
        }
        res.seconds.steps += st.seconds_linear + st.seconds_nonlinear;
    }
}

}  // namespace

template <class Real>
void reconstruct_tiled(const PointCloud& points, const Parameters& params, const ProgressCallback& progress,
                       Result& res) {
    Stopwatch clock;
    DomainPlan plan = plan_domain(points, params);
    res.seconds.domain = clock.lap();
    const PointCloud with_added = points_with_added(points, plan);
    const PointCloud& measured = with_added.empty() ? points : with_added;
    static_cast<DomainPlan&>(res) = plan;
    TileFacts& facts = res.tiles;
    facts.core_cells = params.tile_cells;
    facts.halo_cells = halo_of(plan, params, facts.halo_derived);
    const std::vector<Tile> tiles = plan_tiles(plan.domain, facts.core_cells, facts.halo_cells);
    facts.tiles = tiles.size();
    const detail::PointTree& tree = detail::tree_of(measured);
    const double reach = plan.offset + std::max(params.band_xi * plan.xi, plan.domain.h) + plan.domain.h;
    const std::vector<TileNeeds> needs = needs_of(tree, plan.domain, tiles, facts.core_cells, facts.halo_cells, reach);
    res.seconds.distance = clock.lap();
    FieldAssembly<Real> field(plan.domain);
    std::unique_ptr<Backend<Real>> backend;
    std::vector<TileRun> runs(tiles.size());
    std::vector<int> most(std::size_t(plan.planned_steps), 0);
    double cells_run = 0, core_cells = 0;
    std::size_t done = 0, to_run = 0;
    double tiles_seconds = 0;
    for (const TileNeeds& need : needs) to_run += need.core_near;
    for (const Tile& t : tiles) {
        if (!needs[std::size_t(t.index)].core_near) continue;
        TileRun& run = runs[std::size_t(t.index)];
        run = run_tile<Real>(measured, plan, params, t, std::vector<int>(most.size(), 0), backend, field);
        for (std::size_t s = 0; s < most.size(); ++s) most[s] = std::max(most[s], run.steps[s].cycles);
        ++done;
        tiles_seconds += clock.lap();
        const double per_tile = tiles_seconds / double(done);
        tell(progress, std::to_string(done) + " of " + std::to_string(to_run) + " with points (" +
                           std::to_string(tiles.size()) + " in all), about " +
                           std::to_string(int(std::ceil(per_tile * double(to_run - done)))) + " s left");
    }
    // Every tile as many V-cycles in each step as the one that took most: the stopping
    // is the run's, not each tile's. A tile run again with more cycles needs no more.
    for (const Tile& t : tiles) {
        TileRun& run = runs[std::size_t(t.index)];
        if (run.steps.empty() || !fewer_cycles(run, most)) continue;
        run = run_tile<Real>(measured, plan, params, t, most, backend, field);
        ++facts.reruns;
    }
    for (const Tile& t : tiles) {
        const TileRun& run = runs[std::size_t(t.index)];
        if (run.steps.empty()) continue;
        ++facts.run;
        facts.most_points = std::max(facts.most_points, needs[std::size_t(t.index)].points);
        facts.most_band_cells = std::max(facts.most_band_cells, run.facts.active_cells);
        res.active_cells += run.facts.active_cells;
        res.solver_bytes = std::max(res.solver_bytes, run.facts.solver_bytes);
        res.seconds.distance += run.facts.seconds_distance;
        res.seconds.init += run.facts.seconds_domain + run.facts.seconds_init;
        if (res.backend.empty()) res.backend = run.facts.backend;
        for (const std::string& note : run.facts.notes)
            if (std::find(res.warnings.begin(), res.warnings.end(), note) == res.warnings.end())
                res.warnings.push_back(note);
        double cells = 1, core = 1;
        for (int a = 0; a < 3; ++a) {
            cells *= t.hi[std::size_t(a)] - t.lo[std::size_t(a)];
            core *= t.core_hi[std::size_t(a)] - t.core_lo[std::size_t(a)];
        }
        cells_run += cells;
        core_cells += core;
    }
    facts.cells_run = core_cells > 0 ? cells_run / core_cells : 0;
    merge_steps(runs, plan.planned_steps, res);
    res.phi = field.take();
    res.active_bricks = res.phi.stored_bricks() - kConstantSlots;
    res.total_bricks = res.phi.brick_count();
}

template void reconstruct_tiled<double>(const PointCloud&, const Parameters&, const ProgressCallback&, Result&);
template void reconstruct_tiled<float>(const PointCloud&, const Parameters&, const ProgressCallback&, Result&);

}  // namespace snvr
