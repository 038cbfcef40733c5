// Tiles of the one lattice: a run cut into cores that each compute what the whole run
// computes there, run one at a time with a halo around them (tiled_reconstruct.cpp).
//
// Why a halo of a few cells is enough. A time step is the implicit linear solve
// (I - dt g Lap) phi* = phi, then the exact nonlinear step, then the tube's clamp. A
// tile's edge differs from the whole run's values there by at most 2 (phi lies in
// [-1, 1]) at each step; the linear solve carries that inwards through its inverse,
// which is non-negative with rows summing to at most 1 (g <= 1), and whose sum over the
// planes parallel to a face is the 1-D inverse of (1 - a D^2), a = dt / h^2: a two-sided
// geometric kernel of ratio r = (1 + 2a - sqrt(1 + 4a)) / 2a per cell (0.17 at the
// default a = 1/4). After s steps a change at the edge reaches n cells in by at most
// the tail P(S_s >= n) of a sum of s such steps, bounded by Chernoff's
// min_theta M(theta)^s e^(-theta n); the nonlinear step stretches differences by at
// most e^(k/2) (its slope at phi = 0; k = 2 dt / eps^2) and the clamp by at most 1.
// Summed over the N steps: 2 N e^(N k / 2) min_theta M(theta)^N e^(-theta n). An error e
// in phi moves the surface by about sqrt(2) w e, w the wider of xi and eps (the
// profile's width), so the halo is the least n that keeps that under `most` voxels,
// rounded up to whole bricks. At the defaults (6 steps of h^2 / 4, eps 1.6 h) it is 12
// cells for 1e-3 voxels (10 for 1e-2, 17 for 1e-6), so 16. A longer flow (--smoothing) or longer steps (--dt-cells) widen it.
// The linear solve's own stopping (tol) is a second, separate error (Parameters::tol).
#pragma once
#include <algorithm>
#include <array>
#include <vector>

#include "snvr/domain.hpp"
#include "snvr/parameters.hpp"
#include "snvr/reconstruct.hpp"

namespace snvr {

struct FlowReach {
    double dt_cells = 0;    // dt / h^2
    int steps = 0;
    double rate = 0;        // k = 2 dt / eps^2 of the nonlinear step
    double width_cells = 0; // the profile's width in cells (the wider of xi and eps)
};

// The least halo (cells, unrounded) beyond which the flow moves the surface in the
// core by at most `most` voxels; derived above.
int flow_halo_cells(const FlowReach& flow, double most);

// The run's halo in cells: as given (Parameters::tile_halo_cells), else the least that
// keeps the tile's edge from moving the surface in its core by more than 1e-3 voxels
// (a tenth of what a tiled run promises against the whole one, the rest left to the
// linear solve's stopping), rounded up to whole bricks. `derived` says which.
int tile_halo(const DomainPlan& plan, const Parameters& params, bool& derived);

// A tile: its core and its box with the halo (global cells, [lo, hi)), the box clipped
// to the grid.
struct Tile {
    std::array<int, 3> core_lo{}, core_hi{}, lo{}, hi{};
    int index = 0;
};

// Cores of `core_cells` (a multiple of the brick) over the grid, x fastest, each with a
// halo of `halo_cells` (a multiple of the brick) beyond it where the grid goes on.
std::vector<Tile> plan_tiles(const Domain& whole, int core_cells, int halo_cells);

// The index in plan_tiles(whole, core_cells, ...) of the tile whose core holds `cell`.
inline std::size_t tile_holding(const Domain& whole, int core_cells, const std::array<int, 3>& cell) {
    const auto across = [&](int n) { return std::size_t((n + core_cells - 1) / core_cells); };
    return std::size_t(cell[0] / core_cells) +
           across(whole.nx) * (std::size_t(cell[1] / core_cells) + across(whole.ny) * std::size_t(cell[2] / core_cells));
}

// Calls f(t) for each tile of `tiles` (plan_tiles(whole, core_cells, halo_cells)) whose
// box, halo included, meets the cells [lo, hi) (lo may be below 0, hi beyond the grid).
template <class F>
void for_tiles_meeting(const std::vector<Tile>& tiles, const Domain& whole, int core_cells, int halo_cells,
                       const std::array<int, 3>& lo, const std::array<int, 3>& hi, F&& f) {
    const int n[3] = {whole.nx, whole.ny, whole.nz};
    int count[3], first[3], last[3];
    for (int a = 0; a < 3; ++a) {
        count[a] = (n[a] + core_cells - 1) / core_cells;
        // Tiles by core, widened by the halo in whole cores: tested exactly below.
        const int halo_cores = halo_cells / core_cells + 1;
        first[a] = std::max(0, std::max(0, lo[std::size_t(a)]) / core_cells - halo_cores);
        last[a] = std::min(count[a] - 1, std::max(0, hi[std::size_t(a)] - 1) / core_cells + halo_cores);
    }
    for (int k = first[2]; k <= last[2]; ++k)
        for (int j = first[1]; j <= last[1]; ++j)
            for (int i = first[0]; i <= last[0]; ++i) {
                const std::size_t t = std::size_t(i + count[0] * (j + count[1] * k));
                bool meets = true;
                for (std::size_t a = 0; a < 3 && meets; ++a) meets = lo[a] < tiles[t].hi[a] && hi[a] > tiles[t].lo[a];
                if (meets) f(t);
            }
}

// A tile's own grid: the whole run's voxel, lattice and unit length (so that each cell's
// arithmetic rounds as the whole run's: with the tile's own, float's rounding differed and
// flipped phi's sign at nodes near 0), its box, and as many multigrid levels as its size
// takes (at most the whole run's).
Domain tile_domain(const Domain& whole, const Tile& tile);

}  // namespace snvr
