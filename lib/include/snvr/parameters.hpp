// Everything a reconstruction can be told, with the paper's defaults.
// Lengths are in world units (the points' units) unless the name says cells.
#pragma once
#include <array>
#include <cstddef>
#include <optional>
#include <string>

#include "snvr/field.hpp"
#include "snvr/geometry.hpp"
#include "snvr/mesh.hpp"

namespace snvr {

// The ranges Parameters::validate() and plan_domain() hold every value to, derived ones
// (xi or eps given as a length, dt in normalised units, the steps the flow time makes)
// included: beyond them a run would not end in reasonable time, or would mean nothing.
struct ParameterLimits {
    static constexpr int min_resolution = 16, max_resolution = 16384;
    static constexpr int max_steps = 100000;
    // dt / h^2: the default 0.25; the tests run the paper's dt = 1 (4096 h^2 at 64 cells); beyond
    // 1e9 even double loses the step's identity term.
    static constexpr double max_dt_cells = 1e9;
    static constexpr double max_smoothing_cells = 1000;   // T / h^2 (the default 1.5)
    static constexpr double max_tube_inner = 1, max_tube_outer = 10;  // shares of the offset
    static constexpr double max_width_cells = 100;        // eps and xi, in cells (defaults 12 and 4)
    static constexpr double min_offset_cells = 1, max_offset_cells = 100;
    static constexpr double max_tol = 1;
    static constexpr double min_upsample_spacing = 0.1;  // share of the offset: 100 points a point
    static constexpr int max_cycles = 10000;
    static constexpr int min_tile_cells = 16;
    static constexpr std::size_t min_memory = std::size_t(64) << 20;  // max_memory: below it a run holds little but the program
};

struct Parameters {
    // Offset l of the shell wall from the points (world units); the shell is 2l thick.
    // Unset: the larger of 2.5 voxels and the points' sampling gap.
    std::optional<double> offset;
    // Alternative to offset: the wall-to-wall thickness 2l.
    std::optional<double> thickness;
    // The unset offset in voxels, unless the sampling gap is larger (the paper's 2.5).
    double offset_cells = 2.5;

    // Fixed grid box (world min and max corners) instead of the points' padded box;
    // the grid then has exactly `resolution` cells on the box's longest side.
    std::optional<std::array<Vec3, 2>> box;

    int resolution = 128;          // cells on the longest axis (used when voxel is unset)
    std::optional<double> voxel;   // voxel size h in world units

    // The flow is set in cells, so that a run means the same at every resolution: the
    // total time T = smoothing_cells h^2 (a diffusion length of about sqrt(2 T) = 1.4
    // voxels), in steps of at most dt_cells h^2. Steps much longer than h^2 turn the
    // split scheme into thresholding that pins the surface to the grid (terraces).
    std::optional<int> steps;      // time steps Nt; unset: ceil(smoothing_cells / dt_cells)
    std::optional<double> dt;      // time step in normalised units (longest side = 1); unset: dt_cells h^2
    double dt_cells = 0.25;        // dt / h^2 when dt is unset
    double smoothing_cells = 1.5;  // T / h^2 when steps is unset
    // The flow moves the surface only within a tube around the exact offset surface
    // d = l (d: distance to the nearest point): never closer to the points than
    // (1 - tube_inner) l, so every point stays inside at depth (1 - tube_inner) l, and
    // never farther than (1 + tube_outer) l, so sheets 3l apart never fuse and no cavity
    // forms where the points enclose none. Curvature flow shrinks what is small against
    // the interface width (beads around single points, thin strands): the tube keeps them.
    double tube_inner = 0.2;       // share of l
    double tube_outer = 0.4;       // share of l
    bool keep_offset = true;       // false: the paper's free flow (no tube)
    // Points added on the surface the points describe, before the distance: where they
    // fall at random (a scanner's returns rather than a spacing), one at the centre of
    // each hole wider than (1 - tube_inner) x the offset, so that the shell is closed
    // where the surface was sampled, without thicker walls; and where the sampling sets
    // the offset (it is more than offset_cells voxels), points upsample_spacing x the
    // offset apart on each point's local quadric, so that the shell is smooth at the
    // sampling's scale rather than a bunch of grapes. false: the points as given.
    bool add_points = true;
    double upsample_spacing = 0.35;  // share of the offset
    double eps_cells = 12;         // epsilon of the Allen-Cahn equation, in cells (eps_m)
    std::optional<double> eps;     // ...or in world units
    double xi_cells = 4;           // xi of the initial profile, in cells
    std::optional<double> xi;      // ...or in world units

    // The linear solve stops when the RMS residual over the band's cells (those of the
    // active bricks) is below tol. Its error is at most the residual (A^-1 >= 0 with row
    // sums <= 1), and an error e in phi moves the surface by sqrt(2) xi e: at 2e-4 and
    // xi = 4 cells about 1e-3 voxels, far below what the flow itself moves. One V-cycle
    // reaches it on the bunny, igea and armadillo at 256 (1e-4 after one; 1e-7 took two
    // per step and left every quality figure the same to four digits).
    double tol = 2e-4;
    int max_cycles = 50;           // V-cycle cap per time step (reaching it is reported)
    int pre_smooth = 2;            // red-black Gauss-Seidel sweeps before coarse correction
    int post_smooth = 2;           // ...and after
    bool trilinear = true;         // trilinear prolongation (else piecewise constant)
    // V-cycles stop at the finest coarse level with at most 512 coupled cells (g > 0) and
    // solve it exactly (a dense inverse, one matrix-vector product); when false, or when
    // no level is that small, they go down to the coarsest and sweep there.
    bool exact_coarse = true;
    // Over-relaxation of the red-black Gauss-Seidel smoother. On the bunny at 256^3
    // (6 steps) 1.2 cut the V-cycles per step from 5 to 3 (contraction 0.07 -> 0.011);
    // 1.15 and 1.25 needed 4, 1.3 needed 4 and was slower.
    double omega = 1.2;
    // |l - d| beyond band_xi * xi counts as phi0 = +-1, g = 0 (there g < 1.5e-5). Against
    // 12 (g < 2e-7, float's own resolution): Table 2 the same to four digits, every quality
    // figure of the bunny at 256 and 1024 the same to eight, two sheets l apart (where the
    // two surfaces meet in the band) within 0.001 degree; 11% fewer bricks at 1024.
    double band_xi = 8;

    // Float fields halve the memory and the time steps' traffic; on the bunny, igea and
    // armadillo at 256 every quality figure matched double to four digits, and single
    // precision stalls the residual near 2e-8, far below tol.
    Precision precision = Precision::Single;
    std::string device = "auto";   // auto | openmp | opencl | opencl:P:D | name substring

    // Tiles (lib/src/solver/tile_plan.hpp): 0 runs the grid whole; otherwise the grid is
    // cut into cores of tile_cells cells a side (a multiple of 8), each run alone with a
    // halo around it as wide as the flow can reach (derived from the steps, dt, eps and
    // xi), or tile_halo_cells (a multiple of 8) when given: the same shell, one tile's
    // solver memory at a time.
    int tile_cells = 0;
    std::optional<int> tile_halo_cells;
    // A tiled run puts the whole grid's phase field together (Result::phi). false: the
    // tiles make the surface instead (Result::surface, the same mesh as the whole field's,
    // bit for bit; lib/src/solver/tile_surface.hpp), each from its own core, and the run
    // holds no more of the field than the bricks near the tiles' faces, which the seams
    // between them need. A run that is not tiled keeps its field either way.
    bool whole_field = true;
    // Where the tiles make the surface over several processes (a TileScheduler): it is
    // faired as it is welded, in slabs of planes one a process (lib/src/solver/
    // slab_surface.hpp; the same bytes as fair_mesh on the whole), and
    // Result::surface_faired says so. passes 0, or one process: left as extracted.
    MeshFairing surface_fairing{0};
    // And then the depth guard (keep_points_deep on the points given to reconstruct, at
    // make_shell's depth and lone distance: the tube's inner wall, the offset where it is
    // below the gap) run on each slab with its ghosts and the points near it, the first
    // giving each other process those; Result::surface_guarded says so. Only where the
    // tube has an inner wall. false, or one process: left to the caller.
    bool surface_guard = false;
    // And the surface left in its slabs, where nothing asks for it whole (make_shell with a
    // MeshSink and no stage that needs it whole): the first process keeps its own slab
    // only (Result::surface then; TileFacts::slabs_kept says so), each other its own, for
    // the check and then the sink, a slab at a time. The first still gathers them where it
    // keeps the points deep on the whole surface (TileFacts::guard_slabs false, or
    // guard_rerun).
    bool surface_in_parts = false;
    // A memory budget in bytes: what the run may add to the process (the points it files and
    // everything after; lib/src/solver/memory_budget.hpp). The run goes whole where its
    // estimate fits, else in tiles of the largest size that fits, else stops with an error
    // naming what does not fit. Unset: the memory available decides alike (whole wherever
    // it fits, as before). tile_cells, when given, is kept and checked against the budget.
    std::optional<std::size_t> max_memory;
    // Where the run may put its temporary files: a .gz input is inflated there into an
    // unnamed file (gone with the process however it ends), never whole in memory. Empty:
    // TMPDIR, else /tmp (snvr-cl: the output's folder, or --temp-dir).
    std::string temp_dir;

    // Throws ParameterError naming the first bad value.
    void validate() const;
};

// Multiplies every length in p (offset, thickness, box, voxel, eps, xi) by factor, as
// when the points are rescaled or given in other units; the rest is in cells or
// normalised units and stays.
void scale_lengths(Parameters& p, double factor);

// eps_m = m h / (2 sqrt(2) atanh(0.99)): the width (in the units of h) over which
// tanh profiles go from -0.99 to 0.99 across about m cells.
double eps_of_cells(double m, double h);

}  // namespace snvr
