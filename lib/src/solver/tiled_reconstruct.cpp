// reconstruct_tiled (tiled_reconstruct.hpp).
#include "solver/tiled_reconstruct.hpp"

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <string>

#include "snvr/error.hpp"
#include "snvr/stopwatch.hpp"
#include "solver/field_assembly.hpp"
#include "solver/memory_budget.hpp"
#include "solver/plan_guard.hpp"
#include "solver/ranged_tile_points.hpp"
#include "solver/session.hpp"
#include "solver/shared_holes.hpp"
#include "solver/shared_slabs.hpp"
#include "solver/shared_upsampling.hpp"
#include "solver/slab_surface.hpp"
#include "solver/solver_memory.hpp"
#include "solver/tile_needs.hpp"
#include "solver/tile_plan.hpp"
#include "solver/tile_surface.hpp"

namespace snvr {

namespace {

// The tile's own plan: the whole run's, in the whole run's units, on the tile's grid.
DomainPlan tile_plan(const DomainPlan& whole, const Tile& tile) {
    DomainPlan plan = whole;
    plan.domain = tile_domain(whole.domain, tile);
    plan.estimated_bytes = estimate_plan_bytes(plan.domain);
    return plan;
}

struct TileRun {
    std::vector<StepStats> steps;
    SessionFacts facts;
    std::size_t core_bricks = 0;  // stored bricks of its core's field
};

// A run's figures as a TileResult carries them to the root (and back).
constexpr std::size_t kFacts = 5, kStepFigures = 7;
std::vector<double> figures_of(const TileRun& run) {
    const SessionFacts& f = run.facts;
    std::vector<double> out{double(f.active_cells), double(f.solver_bytes), f.seconds_distance,
                            f.seconds_domain + f.seconds_init, double(run.core_bricks)};
    for (const StepStats& st : run.steps)
        out.insert(out.end(), {double(st.cycles), st.converged ? 1.0 : 0.0, st.initial_residual, st.residual,
                               st.seconds_linear, st.seconds_nonlinear, st.bytes_moved});
    return out;
}
TileRun run_of(const std::vector<double>& figures) {
    TileRun run;
    if (figures.size() < kFacts) return run;
    run.facts.active_cells = std::size_t(figures[0]);
    run.facts.solver_bytes = std::size_t(figures[1]);
    run.facts.seconds_distance = figures[2];
    run.facts.seconds_init = figures[3];
    run.core_bricks = std::size_t(figures[4]);
    for (std::size_t at = kFacts; at + kStepFigures <= figures.size(); at += kStepFigures) {
        StepStats st;
        st.step = int(run.steps.size()) + 1;
        st.cycles = int(figures[at]);
        st.converged = figures[at + 1] != 0;
        st.initial_residual = figures[at + 2];
        st.residual = figures[at + 3];
        st.seconds_linear = figures[at + 4];
        st.seconds_nonlinear = figures[at + 5];
        st.bytes_moved = figures[at + 6];
        run.steps.push_back(st);
    }
    return run;
}

// "tile 12 (cells 128-256, 0-128, 64-192)": where a warning comes from.
std::string tile_name(const Tile& t) {
    std::string s = "tile " + std::to_string(t.index) + " (cells ";
    for (int a = 0; a < 3; ++a)
        s += (a ? ", " : "") + std::to_string(t.core_lo[std::size_t(a)]) + "-" + std::to_string(t.core_hi[std::size_t(a)]);
    return s + ")";
}

bool fewer_cycles(const TileRun& run, const std::vector<int>& most) {
    for (std::size_t s = 0; s < run.steps.size(); ++s)
        if (run.steps[s].cycles < most[s]) return true;
    return false;
}

void tell(const ProgressCallback& progress, const char* stage, const std::string& message) {
    if (!progress) return;
    Progress p;
    p.stage = stage;
    p.message = message;
    if (!progress(p)) throw Cancelled(std::string("cancelled in the ") + stage + " stage");
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

// The plan as the other processes need it (the grid, the offset, the flow, the tube), and
// the tiles' cores, whether the root puts the whole field together and how the surface is
// faired and guarded (the root's word: it may have chosen the tiles for a budget). The root
// appends its tree's frame (4 more), then whether the tiles' needs and points go by the
// processes' ranges (ranged_tile_points.hpp).
constexpr std::size_t kPlanFigures = 24;
constexpr std::size_t kSharedFigures = kPlanFigures + 5;
std::vector<double> plan_figures(const DomainPlan& p, const Parameters& params) {
    const Domain& d = p.domain;
    const MeshFairing& f = params.surface_fairing;
    return {d.origin[0], d.origin[1], d.origin[2], d.h, double(d.nx), double(d.ny), double(d.nz), double(d.levels),
            double(d.unit_cells), p.offset, p.xi, p.eps, p.dt, double(p.planned_steps), p.tube_inner, p.tube_outer,
            double(params.tile_cells), params.whole_field ? 1.0 : 0.0, double(f.passes), f.lambda, f.pass_band,
            params.surface_guard ? 1.0 : 0.0, p.gap, params.surface_in_parts ? 1.0 : 0.0};
}
DomainPlan plan_of(const std::vector<double>& f, Parameters& params) {
    if (f.size() != kSharedFigures) throw Error("tiles: the plan from the first process is not whole");
    params.tile_cells = int(f[16]);
    params.whole_field = f[17] != 0;
    params.surface_fairing.passes = int(f[18]);
    params.surface_fairing.lambda = f[19];
    params.surface_fairing.pass_band = f[20];
    params.surface_guard = f[21] != 0;
    params.surface_in_parts = f[23] != 0;
    DomainPlan p;
    Domain& d = p.domain;
    d.origin = {f[0], f[1], f[2]};
    d.h = f[3];
    d.nx = int(f[4]);
    d.ny = int(f[5]);
    d.nz = int(f[6]);
    d.levels = int(f[7]);
    d.unit_cells = int(f[8]);
    p.offset = f[9];
    p.xi = f[10];
    p.eps = f[11];
    p.dt = f[12];
    p.planned_steps = int(f[13]);
    p.tube_inner = f[14];
    p.tube_outer = f[15];
    p.gap = f[22];
    return p;
}

// The tiles of one run, on this process and (with a scheduler) the others.
template <class Real>
class TiledRun {
public:
    // At the root (or alone): which process runs each tile, from the points near each;
    // with a scheduler, the plan, the owners and each process's points go to the others.
    // At another process: `owners` as the root gave them (`measured`: its points alone).
    TiledRun(const PointCloud& measured, const DomainPlan& plan, const Parameters& params, BackendStart<Real>& start,
             TileScheduler* on, const ProgressCallback& progress, Result& res, const std::vector<int>* owners = nullptr)
        : measured_(measured), plan_(plan), params_(params), start_(start), on_(on), progress_(progress), res_(res),
          field_(plan.domain), whole_field_(params.whole_field) {
        TileFacts& facts = res.tiles;
        tiles_ = plan_tiles(plan.domain, facts.core_cells, facts.halo_cells);
        facts.tiles = tiles_.size();
        facts.processes = on ? on->processes() : 1;
        runs_.resize(tiles_.size());
        // Alone, the mesher fairs the whole surface with the lists the depth guard walks
        // too, built once (shell_mesh.hpp); else each process fairs its slab.
        slab_fairing_ = facts.processes > 1 ? params.surface_fairing : MeshFairing{0};
        if (!whole_field_) surfaces_.resize(tiles_.size());
        if (owners) {
            owner_ = *owners;
            needs_.resize(tiles_.size());
            return;
        }
        const double reach = band_reach(plan, params);
        const detail::PointTree& tree = detail::tree_of(measured);
        const bool ranged = on && tiles_by_ranges(tree, facts.processes);
        if (!ranged) {
            needs_ = needs_of(tree, plan.domain, tiles_, facts.core_cells, facts.halo_cells, reach);
            owner_ = owners_of(needs_, facts.processes);
        }
        if (!on) return;
        Parameters given = params;
        given.tile_cells = facts.core_cells;
        std::vector<double> figures = plan_figures(plan, given);
        // The tree's frame too: each process's points go in its order, and filed in the
        // same frame they need no sorting (the city block's 30 M points 2.0 -> 1.3 s).
        const std::array<double, 4> frame = tree.frame().figures();
        figures.insert(figures.end(), frame.begin(), frame.end());
        figures.push_back(ranged ? 1 : 0);
        on->share(figures, owner_);  // by ranges: no owners yet, each process finds them
        if (ranged) {
            const OwnRange own = tell_ranges(*on, tree);
            needs_ = ranged_needs(*on, own, plan.domain, tiles_, facts.core_cells, facts.halo_cells, reach);
            owner_ = owners_of(needs_, facts.processes);
            RangedPointsFacts moved;
            ranged_points(*on, own, plan.domain, tiles_, owner_, facts.core_cells, facts.halo_cells, reach, moved);
            facts.points_sent = moved.given;
            facts.points_from_ranges = moved.own;
            return;
        }
        std::vector<PointRuns> runs =
            point_runs(tree, plan.domain, tiles_, owner_, facts.processes, facts.core_cells, facts.halo_cells, reach);
        for (int p = 1; p < facts.processes; ++p) {
            const detail::PointArray<float> xyz = points_in(tree, runs[std::size_t(p)]);
            runs[std::size_t(p)] = PointRuns();
            facts.points_sent += xyz.size() / 3;
            on->give_points(p, tree.origin, xyz.data(), xyz.size());
        }
    }

    // Every tile once; then those that took fewer V-cycles in a step than the one that
    // took most, again with as many: the stopping is the run's, not each tile's (a tile
    // run again with more cycles needs no more).
    void run() {
        std::vector<int> most(std::size_t(plan_.planned_steps), 0);
        std::vector<std::size_t> first;
        for (const Tile& t : tiles_) first.push_back(std::size_t(t.index));
        pass(first, std::vector<int>(most.size(), 0));
        for (const TileRun& run : runs_)
            for (std::size_t s = 0; s < run.steps.size(); ++s) most[s] = std::max(most[s], run.steps[s].cycles);
        if (on_) most = on_->most(most);
        std::vector<std::size_t> again;
        for (const Tile& t : tiles_) {
            const TileRun& run = runs_[std::size_t(t.index)];
            if (!run.steps.empty() && fewer_cycles(run, most)) again.push_back(std::size_t(t.index));
        }
        res_.tiles.reruns = again.size();
        pass(again, most);
        if (on_ && !root()) on_->sent();
    }

    // The run's figures from its tiles'; the whole grid's phase field on the root.
    // `guarded`: at the root, the points the depth guard keeps deep, where the slabs run it
    // (Parameters::surface_guard); elsewhere null.
    void finish(const PointCloud* guarded) {
        TileFacts& facts = res_.tiles;
        facts.worker = !root();
        double cells_run = 0, core_cells = 0;
        for (const Tile& t : tiles_) {
            const TileRun& run = runs_[std::size_t(t.index)];
            if (run.steps.empty()) continue;
            ++facts.run;
            facts.most_points = std::max(facts.most_points, needs_[std::size_t(t.index)].points);
            facts.most_band_cells = std::max(facts.most_band_cells, run.facts.active_cells);
            res_.active_cells += run.facts.active_cells;
            res_.solver_bytes = std::max(res_.solver_bytes, run.facts.solver_bytes);
            res_.seconds.distance += run.facts.seconds_distance;
            res_.seconds.init += run.facts.seconds_domain + run.facts.seconds_init;
            if (res_.backend.empty()) res_.backend = run.facts.backend;
            for (const std::string& note : run.facts.notes)
                if (std::find(res_.warnings.begin(), res_.warnings.end(), note) == res_.warnings.end())
                    res_.warnings.push_back(note);
            // One warning a tile, naming it, for its worst step.
            const StepStats* worst = nullptr;
            std::size_t missed = 0;
            for (const StepStats& st : run.steps)
                if (!st.converged) {
                    ++missed;
                    if (!worst || st.residual > worst->residual) worst = &st;
                }
            if (worst) {
                char text[200];
                std::snprintf(text, sizeof text,
                              ": %zu of %zu steps did not converge (the worst: step %d, residual %.3g after %d "
                              "V-cycles; tol %g)",
                              missed, run.steps.size(), worst->step, worst->residual, worst->cycles, params_.tol);
                res_.warnings.push_back(tile_name(t) + text);
            }
            double cells = 1, core = 1;
            for (int a = 0; a < 3; ++a) {
                cells *= t.hi[std::size_t(a)] - t.lo[std::size_t(a)];
                core *= t.core_hi[std::size_t(a)] - t.core_lo[std::size_t(a)];
            }
            cells_run += cells;
            core_cells += core;
        }
        if (res_.backend.empty() && facts.run) res_.backend = "on the other processes";
        std::vector<double> work(std::size_t(facts.processes), 0);
        for (const Tile& t : tiles_) {
            const TileRun& run = runs_[std::size_t(t.index)];
            if (run.steps.empty()) continue;
            double seconds = run.facts.seconds_distance + run.facts.seconds_domain + run.facts.seconds_init;
            for (const StepStats& st : run.steps) seconds += st.seconds_linear + st.seconds_nonlinear;
            work[std::size_t(owner_[std::size_t(t.index)])] += seconds;
        }
        double all = 0;
        for (double w : work) all += w;
        facts.busiest_over_mean = all > 0 ? *std::max_element(work.begin(), work.end()) / (all / double(work.size())) : 0;
        facts.cells_run = core_cells > 0 ? cells_run / core_cells : 0;
        merge_steps(runs_, plan_.planned_steps, res_);
        facts.owners = owner_;
        if (whole_field_) {
            if (!root()) return;
            Field field = field_.take();
            res_.total_bricks = field.brick_count();
            res_.active_bricks = field.stored_bricks() - kConstantSlots;
            res_.phi = std::move(field);
            return;
        }
        // Every process welds and fairs a slab of the surface; the root puts them together.
        Field faces;
        if (root()) {
            faces = field_.take();
            res_.total_bricks = faces.brick_count();
            for (const TileRun& run : runs_) res_.active_bricks += run.core_bricks;
        }
        Stopwatch clock;
        // The guard too where the slabs are several and the tube has an inner wall (where
        // that pays: shared_slabs.hpp, facts.guard_slabs).
        SlabsGuard guard{detail::keep_deep_of(plan_), guarded};
        const bool guard_slabs = facts.processes > 1 && params_.surface_guard && detail::has_inner_wall(plan_);
        tell(progress_, "mesh",
             std::string(slab_fairing_.passes ? "welding and fairing" : "welding") + " the tiles' surfaces at their seams" +
                 (facts.processes > 1 ? ", in " + std::to_string(facts.processes) + " slabs of planes" : std::string()));
        std::vector<detail::MeshPiece> pieces;
        for (std::vector<detail::MeshPiece>& of_tile : surfaces_)
            for (detail::MeshPiece& p : of_tile) pieces.push_back(std::move(p));
        surfaces_.clear();
        res_.surface = surface_in_slabs(pieces, std::move(faces), plan_.domain, facts.core_cells, slab_fairing_,
                                        guard_slabs ? &guard : nullptr, params_.surface_in_parts, on_, facts,
                                        &res_.surface_guard);
        res_.surface_made = root();
        res_.surface_faired = root() && slab_fairing_.passes > 0;
        res_.surface_guarded = root() && facts.guard_slabs;
        res_.seconds.seams = clock.lap();
    }

private:
    int me() const { return on_ ? on_->rank() : 0; }
    bool root() const { return me() == 0; }

    // The tiles of `which` this process owns, run here (placed, or sent to the root); at
    // the root, those the others run, taken as they come in (between its own).
    void pass(const std::vector<std::size_t>& which, const std::vector<int>& least) {
        Stopwatch clock;
        std::size_t mine = 0, theirs = 0, done = 0;
        // Each process's tiles in this pass, and those done (as far as this one knows).
        const std::size_t processes = on_ ? std::size_t(on_->processes()) : 1;
        std::vector<std::size_t> owned(processes, 0), finished(processes, 0);
        for (std::size_t t : which) {
            mine += owner_[t] == me();
            theirs += root() && owner_[t] > 0;
            if (owner_[t] >= 0) ++owned[std::size_t(owner_[t])];
        }
        const auto progress = [&](std::size_t tile) {
            ++done;
            ++finished[std::size_t(owner_[tile])];
            seconds_ += clock.lap();
            const std::size_t all = mine + theirs;
            std::string per;  // "; process 0: 12 of 23, process 1: 10 of 22"
            for (std::size_t p = 0; processes > 1 && root() && p < processes; ++p)
                per += (p ? ", " : "; ") + std::string("process ") + std::to_string(p) + ": " +
                       std::to_string(finished[p]) + " of " + std::to_string(owned[p]);
            tell(progress_, "tile", std::to_string(done) + " of " + std::to_string(all) + " tiles with points" +
                                (on_ ? " on " + std::to_string(on_->processes()) + " processes" : std::string()) +
                                " (" + std::to_string(tiles_.size()) + " in all), about " +
                                std::to_string(int(std::ceil(seconds_ / double(done) * double(all - done)))) +
                                " s left" + per);
        };
        std::size_t taken = 0;
        const auto take = [&] {
            TileResult got = on_->receive();
            res_.tiles.bytes_received += got.field.bytes() + got.figures.size() * sizeof(double);
            if (!whole_field_) {
                res_.tiles.face_bytes += got.field.bytes();
                res_.tiles.faces_received += inner_faces(tiles_[got.tile], plan_.domain);
            }
            runs_[got.tile] = run_of(got.figures);
            field_.place(got.field, tiles_[got.tile]);
            ++taken;
            progress(got.tile);
        };
        for (std::size_t t : which) {
            if (owner_[t] != me()) continue;
            Field tile_field;
            runs_[t] = run_named(tiles_[t], least, tile_field);
            runs_[t].core_bricks = stored_core_bricks(tile_field, tiles_[t]);
            // Without the whole field: the tile's own part of the surface (kept here for the
            // slabs, shared_slabs.hpp, cut in their slices where there are several
            // processes), and of its field only the bricks the seams need.
            if (!whole_field_) {
                surfaces_[t] = tile_surface(tile_field, tiles_[t], plan_.domain, res_.tiles.processes > 1 ? kSlabSlice : 0);
                tile_field = tile_faces(tile_field, tiles_[t], plan_.domain);
            }
            if (root()) field_.place(tile_field, tiles_[t]);
            else on_->send({t, std::move(tile_field), figures_of(runs_[t])});
            progress(t);
            while (root() && on_ && taken < theirs && on_->waiting()) take();
        }
        while (taken < theirs) take();
    }

    // run_tile, its failure naming the tile (a process's failure names the process too:
    // the scheduler's).
    TileRun run_named(const Tile& tile, const std::vector<int>& least, Field& tile_field) {
        const std::string where = tile_name(tile) + ": ";
        try {
            test_fault(tile);
            return run_tile(tile, least, tile_field);
        } catch (const Cancelled&) {
            throw;
        } catch (const ResourceError& e) {
            throw ResourceError(where + e.what());
        } catch (const std::bad_alloc&) {
            throw ResourceError(where + "out of memory");
        } catch (const InputError& e) {
            throw InputError(where + e.what());
        } catch (const ParameterError& e) {
            throw ParameterError(where + e.what());
        } catch (const Error& e) {
            throw Error(where + e.what());
        }
    }

    // For tests only: SNVR_TEST_TILE_FAULT=K fails tile K as running out of memory would
    // ("first": the first tile this process runs; "kill": the process is killed there).
    void test_fault(const Tile& tile) {
        const char* text = std::getenv("SNVR_TEST_TILE_FAULT");
        if (!text) return;
        const std::string spec = text;
        if (spec == "kill") ::raise(SIGKILL);
        if ((spec == "first" && !ran_one_) || spec == std::to_string(tile.index))
            throw ResourceError("a test fault (SNVR_TEST_TILE_FAULT)");
        ran_one_ = true;
    }

    // The tile on the whole cloud's tree: its distance queries only the tile's cells, and
    // finds there what the whole run finds. One backend serves every tile in turn.
    TileRun run_tile(const Tile& tile, const std::vector<int>& least, Field& tile_field) {
        const bool started = bool(backend_);
        BackendStart<Real> again(std::move(backend_));
        SolverSession<Real> session(measured_, tile_plan(plan_, tile), params_, started ? again : start_);
        TileRun run;
        while (session.steps_done() < session.problem().steps)
            run.steps.push_back(session.step(least[std::size_t(session.steps_done())]));
        run.facts = session.facts();
        tile_field = session.take_field();
        backend_ = session.release_backend();
        return run;
    }

    const PointCloud& measured_;
    const DomainPlan& plan_;
    const Parameters& params_;
    BackendStart<Real>& start_;  // the first tile's backend
    TileScheduler* on_;
    const ProgressCallback& progress_;
    Result& res_;
    FieldAssembly<Real> field_;  // the cores, or (without the whole field) their faces' bricks
    const bool whole_field_;
    std::vector<std::vector<detail::MeshPiece>> surfaces_;  // by tile, without the whole field
    MeshFairing slab_fairing_;  // how the slabs of the surface are faired
    std::vector<Tile> tiles_;
    std::vector<TileNeeds> needs_;
    std::vector<int> owner_;
    std::vector<TileRun> runs_;
    std::unique_ptr<Backend<Real>> backend_;
    double seconds_ = 0;
    bool ran_one_ = false;
};

}  // namespace

template <class Real>
void reconstruct_tiled(const PointCloud& measured, const PointCloud& points, const DomainPlan& plan,
                       const Parameters& params, BackendStart<Real>& start, const ProgressCallback& progress,
                       TileScheduler* tiles_on, Result& res) {
    Stopwatch clock;
    res.tiles.core_cells = params.tile_cells;
    res.tiles.halo_cells = tile_halo(plan, params, res.tiles.halo_derived);
    TiledRun<Real> tiled(measured, plan, params, start, tiles_on, progress, res);
    res.seconds.distance += clock.lap();
    tiled.run();
    res.tiles.seconds = clock.lap();
    tiled.finish(&points);
}

template <class Real>
void reconstruct_tiles_given(const Parameters& params, TileScheduler& on, Result& res) {
    Stopwatch clock;
    holes_for_root(on);
    points_between_for_root(on);
    std::vector<double> figures;
    std::vector<int> owners;
    on.share(figures, owners);
    Parameters mine = params;  // as the root runs it
    const DomainPlan plan = plan_of(figures, mine);
    static_cast<DomainPlan&>(res) = plan;
    res.tiles.core_cells = mine.tile_cells;
    res.tiles.halo_cells = tile_halo(plan, mine, res.tiles.halo_derived);
    Vec3 origin{0, 0, 0};
    detail::PointArray<Vec3f> xyz;
    if (figures[kSharedFigures - 1] != 0) {  // the needs and points by ranges, this one's its kept range
        const OwnRange own = told_range(on, on.points_kept.get());
        origin = own.tree->origin;
        const std::vector<Tile> tiles = plan_tiles(plan.domain, res.tiles.core_cells, res.tiles.halo_cells);
        const double reach = band_reach(plan, mine);
        const std::vector<TileNeeds> needs =
            ranged_needs(on, own, plan.domain, tiles, res.tiles.core_cells, res.tiles.halo_cells, reach);
        owners = owners_of(needs, on.processes());
        RangedPointsFacts moved;
        xyz = ranged_points(on, own, plan.domain, tiles, owners, res.tiles.core_cells, res.tiles.halo_cells, reach,
                            moved);
    } else {
        // Received straight into the cloud's own array (in a file under a budget).
        on.take_points(origin, [&xyz](std::size_t floats) {
            if (floats % 3) throw InputError("points sent as x y z in turn are not whole");
            xyz.resize(floats / 3);
            return xyz.empty() ? nullptr : xyz.front().data();
        });
    }
    const auto frame = detail::PointTree::Frame::of(&figures[kPlanFigures]);
    const PointCloud measured = detail::cloud_of(std::move(xyz), origin, &frame);
    BackendStart<Real> start(mine.device);
    const ProgressCallback quiet;
    TiledRun<Real> tiled(measured, plan, mine, start, &on, quiet, res, &owners);
    res.seconds.distance = clock.lap();
    tiled.run();
    res.tiles.seconds = clock.lap();
    tiled.finish(nullptr);
}

template void reconstruct_tiles_given<double>(const Parameters&, TileScheduler&, Result&);
template void reconstruct_tiles_given<float>(const Parameters&, TileScheduler&, Result&);

template void reconstruct_tiled<double>(const PointCloud&, const PointCloud&, const DomainPlan&, const Parameters&, BackendStart<double>&,
                                        const ProgressCallback&, TileScheduler*, Result&);
template void reconstruct_tiled<float>(const PointCloud&, const PointCloud&, const DomainPlan&, const Parameters&, BackendStart<float>&,
                                       const ProgressCallback&, TileScheduler*, Result&);

}  // namespace snvr
