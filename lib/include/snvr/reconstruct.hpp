// The whole method: points in, phase field out (lib/src/solver/; shell_mesh in shell.hpp
// meshes it as snvr-cl does).
#pragma once
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "snvr/domain.hpp"
#include "snvr/field.hpp"
#include "snvr/geometry.hpp"
#include "snvr/mesh.hpp"
#include "snvr/parameters.hpp"
#include "snvr/point_cloud.hpp"

namespace snvr {

class TileScheduler;  // tiles.hpp

struct StepStats {
    int step = 0;                        // 1-based
    int cycles = 0;                      // V-cycles used
    bool converged = false;              // residual below tol within max_cycles
    double initial_residual = 0;         // before the first cycle
    double residual = 0;                 // after the last cycle
    std::vector<double> cycle_residuals; // after each cycle
    double seconds_linear = 0, seconds_nonlinear = 0;
    double bytes_moved = 0;              // least memory traffic of the step's operations
};

struct StageSeconds {
    double domain = 0;     // fitting the grid, gap estimate, kd-tree
    double distance = 0;   // unsigned distance in the band
    double init = 0;       // phase field, g, coarse coefficients
    double steps = 0;      // all time steps
    double seams = 0;      // a tiled run making the surface: its seams and the weld (the tiles' parts: in their stages)
    double total = 0;
};

// The grid reconstruct() would use, and the offset and gap it would choose.
struct DomainPlan {
    Domain domain;
    double offset = 0;
    std::string offset_reason;
    double gap = 0;
    // A random sampling's holes (sampling_holes.hpp): the share of the points that border a
    // hole wider than the gap (0 when not asked: no sampling's hole is as wide as the
    // offset's 0.8, 2.5 gaps), and the points added at the centres of the holes wider
    // than the tube's inner side (0 where the share is under HoleRules::random_share, or
    // Parameters::add_points is off).
    double hole_share = 0;
    std::size_t hole_fills = 0;
    double hole_least = 0;  // world units: the holes wider than this got a point (0: none looked for)
    std::size_t holes_sought_elsewhere = 0;  // the points whose holes the other processes of a tiled run sought
    // Where the sampling sets the offset: points added this far apart between the points,
    // on their local surfaces (0: none), and how many (Parameters::add_points).
    double upsample_spacing = 0;
    std::size_t upsampled = 0;
    std::size_t upsampled_elsewhere = 0;  // of them, added by the other processes of a tiled run
    double eps = 0, xi = 0;       // world units
    double dt = 0;                // normalised
    int planned_steps = 0;        // the time steps the flow takes
    double tube_inner = 0, tube_outer = 0;  // world units from the offset; 0: free flow
    std::size_t estimated_bytes = 0;  // what follows the box: brick tables, the mesher's sign bits (the band's fields come later)
};

// How a tiled run (Parameters::tile_cells) was cut, and what bounds its memory.
struct TileFacts {
    int core_cells = 0, halo_cells = 0;  // 0: the grid ran whole
    int processes = 1;                   // the tiles spread over (TileScheduler)
    bool worker = false;                 // this process ran its tiles and sent them to the root
    bool halo_derived = true;            // from the flow (else as given)
    std::size_t tiles = 0;               // cores over the grid
    std::size_t run = 0;                 // those with points near them (the rest are -1)
    std::size_t reruns = 0;              // run again to take as many V-cycles as the others
    std::size_t most_points = 0;         // in one tile, its halo's reach included
    std::size_t most_band_cells = 0;     // band cells of the busiest tile, halo included
    double cells_run = 0;                // cells of the tiles run over the cells of their cores
    double seconds = 0;                  // wall clock of the tiles, all passes (stage seconds sum the tiles')
    double busiest_over_mean = 0;        // the work (the tiles' seconds) of the busiest process over the mean
    std::size_t bytes_received = 0;      // the tiles' results the first process took from the others
    std::size_t face_bytes = 0;          // of which the bricks next to their cores' faces (the seams' need)
    std::size_t faces_received = 0;      // those tiles' faces inside the grid
    std::vector<int> owners;             // the process that ran each tile (-1: none, no points near)
    std::size_t points_sent = 0;         // points given the others for their tiles (by the first, or, where
                                         // they kept their ranges of the points, by each from its range)
    std::size_t points_from_ranges = 0;  // and those the others took from their own ranges
    // The check shared (make_shell): what the others measured, the bytes of their shares,
    // and the points no share could decide (their side a ray would tell, or their nearest
    // triangle beyond reach), asked of every slab of the shell.
    std::size_t check_walls = 0, check_points = 0, check_bytes = 0, check_points_far = 0;
    // The depth guard's first search shared: the points the others searched (their ranges),
    // and the bytes of the mesh sent them.
    std::size_t guard_points = 0, guard_bytes = 0;
    // The tiles making the surface: welded and faired in slabs of planes, one a process
    // (lib/src/solver/shared_slabs.hpp): how many, the planes of ghosts on either side of
    // each, and the bytes the processes sent each other for them (tiles' parts, faces'
    // bricks, the slabs to the first).
    int slabs = 0, slab_ghost = 0;
    std::size_t slab_bytes = 0;
    // The depth guard run on the slabs as well (Parameters::surface_guard), where the points
    // near the others' slabs (the first gives them those) are no more than the vertices they
    // own; the slabs' checked ghosts that came out other than their owners' vertices, and
    // so whether the first ran the whole guard again.
    bool guard_slabs = false, guard_rerun = false;
    std::size_t guard_slab_points = 0, guard_ghosts_differing = 0;
    // Where each slab's own vertices begin in the surface (and their count, last), this
    // process's slab's own triangles (at the first, the surface's first ones), and whether
    // the check counted the shell's topology by the slabs (the others keeping theirs:
    // lib/src/check/slab_topology.hpp).
    std::vector<std::size_t> slab_starts;
    std::size_t slab_triangles = 0;
    // The whole surface's triangles, and whether it stays in its slabs, the first holding
    // its own only (Parameters::surface_in_parts; the slabs' own are not sent it then).
    std::size_t surface_triangles = 0;
    bool slabs_kept = false;
    bool check_topology_slabs = false;
};

// How the run fitted its memory (Parameters::max_memory, or what the machine had free),
// estimated after the plan, before the band's distance (lib/src/solver/memory_budget.hpp).
struct MemoryFacts {
    std::size_t budget = 0;          // what the run could use: the budget, or what it held and had free
    bool budget_given = false;       // Parameters::max_memory (else the memory available)
    std::size_t held = 0;            // what it held then: the points, filed
    std::size_t near_bricks = 0;     // bricks within the band's reach of a point (the band's at most)
    std::size_t whole_solver = 0;    // the whole grid's solver
    std::size_t tile_solver = 0;     // the largest tile's solver at the size run (0: whole)
    std::size_t field = 0;           // the phase field kept for the mesh (tiles making the surface:
                                     // the bricks next to their cores' faces)
    std::size_t surfaces = 0;        // tiles making the surface: their parts, held until welded
    std::size_t mesh = 0;            // the mesh, its fairing and guard, and its check
    std::size_t grid = 0;            // the whole grid's tables (the mesher's sign bits)
    std::size_t runtime = 0;         // an OpenCL runtime's own (0 on OpenMP)
    std::size_t estimated_peak = 0;  // held + the largest stage after
    bool tiled_by_budget = false;    // tiles chosen to fit (Parameters::tile_cells was 0)
    std::string bound;               // what sets the estimated peak ("the points", "the mesh and its check", ...)
    // Under a budget, the points' arrays beyond it kept in files in the temporary folder
    // (make_shell fills these at its end, the read's files counted).
    std::size_t spilled_arrays = 0;  // arrays put in files
    std::size_t spilled_bytes = 0;   // the most the files held at once
    std::size_t spill_trims = 0;     // times their pages were given back to stay in the budget
    std::string spill_folder;
    std::size_t storage_read = 0;     // bytes the process read from storage meanwhile (the
    std::size_t storage_written = 0;  // input's too) and wrote (the files' pages written out)
};

// What reconstruct() ran (the plan it fitted to the points) and what it found.
struct Result : DomainPlan {
    Field phi;                    // phi^{Nt} in the band's bricks (+-1 beyond); the shell is where phi > 0
                                  // (empty where the tiles made the surface instead)
    bool surface_made = false;    // the tiles made the zero level set (Parameters::whole_field false)
    Mesh surface;                 // that level set, as extract_dual_isosurface gives it from phi
    bool surface_faired = false;  // and faired (Parameters::surface_fairing): the mesher fairs it no more
    bool surface_guarded = false;  // and its points kept deep (Parameters::surface_guard): the mesher's guard
    DepthGuardReport surface_guard;  // is not run again, its report is this one
    std::string backend;          // which backend ran
    std::size_t active_cells = 0; // cells with g > 0
    std::size_t active_bricks = 0, total_bricks = 0;
    std::size_t solver_bytes = 0; // memory held by the solver's fields
    std::vector<StepStats> steps;
    StageSeconds seconds;
    std::vector<std::string> warnings;
    TileFacts tiles;
    MemoryFacts memory;
};

// A run's progress, as each stage ends (reconstruct: "domain", "distance", "init", "step";
// "tile" as each tile is done and "mesh" as a tiled run welds its tiles' surfaces;
// make_shell adds its own). Returning false cancels: the call stops there, frees what it
// holds and throws Cancelled.
struct Progress {
    std::string stage;
    int step = 0, steps = 0;
    const StepStats* stats = nullptr;  // set for "step"
    // How far the stage has come or which of its parts begins; with `outcome`, what the
    // stage did (the outliers dropped, the vertices the depth guard lifted).
    std::string message;
    bool outcome = false;
};
using ProgressCallback = std::function<bool(const Progress&)>;

// Fits the grid (see fit_domain), computes the distance, runs the split scheme.
// Throws InputError / ParameterError / ResourceError with a message naming the problem.
// A tiled run's tiles go where `tiles_on` sends them (tiles.hpp); none: all here.
Result reconstruct(const PointCloud& points, const Parameters& params, const ProgressCallback& progress = {},
                   TileScheduler* tiles_on = nullptr);
Result reconstruct(const PointSet& points, const Parameters& params,
                   const ProgressCallback& progress = {});  // makes a PointCloud

// Another process's share of a tiled run whose root called reconstruct() with `tiles_on`
// (tiles.hpp): it reads nothing, takes the plan and the points within reach of its own
// tiles from the root, runs those tiles and sends them; Result::tiles.worker is set, and
// the result holds the plan and its tiles' figures, no phase field.
Result reconstruct_tiles_of(const Parameters& params, TileScheduler& tiles_on);

DomainPlan plan_domain(const PointCloud& points, const Parameters& params);
DomainPlan plan_domain(const PointSet& points, const Parameters& params);  // makes a PointCloud

}  // namespace snvr
