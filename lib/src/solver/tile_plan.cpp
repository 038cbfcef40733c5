// flow_halo_cells, plan_tiles and tile_domain (tile_plan.hpp).
#include "solver/tile_plan.hpp"

#include <algorithm>
#include <cmath>

#include "solver/brick_grid.hpp"

namespace snvr {

namespace {

// log of E[e^(theta X)] for the two-sided geometric kernel P(X = x) = c r^|x|, c = (1 - r)
// / (1 + r), for 0 < theta < -log r.
double log_moment(double r, double theta) {
    const double c = (1 - r) / (1 + r);
    return std::log(c * (1 / (1 - r * std::exp(theta)) + 1 / (1 - r * std::exp(-theta)) - 1));
}

// log of the bound on the change n cells into the core (tile_plan.hpp).
double log_reach(const FlowReach& flow, double r, int n) {
    const double most_theta = -std::log(r);
    double best = 0;  // the bound is at most 2 N e^(N k / 2) whatever n
    for (int i = 1; i < 400; ++i) {
        const double theta = most_theta * i / 400.0;
        best = std::min(best, flow.steps * log_moment(r, theta) - theta * n);
    }
    return std::log(2.0 * flow.steps) + 0.5 * flow.steps * flow.rate + best;
}

constexpr double kHaloMostVoxels = 1e-3;  // tile_halo's bound (tile_plan.hpp)

int round_to_bricks(int cells) { return (cells + kBrick - 1) / kBrick * kBrick; }

}  // namespace

int tile_halo(const DomainPlan& plan, const Parameters& params, bool& derived) {
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

int flow_halo_cells(const FlowReach& flow, double most) {
    if (flow.steps <= 0) return 0;
    const double a = flow.dt_cells;
    const double r = (1 + 2 * a - std::sqrt(1 + 4 * a)) / (2 * a);
    // An error e in phi moves the surface by sqrt(2) w e voxels.
    const double allowed = std::log(most / (std::sqrt(2.0) * std::max(flow.width_cells, 1e-9)));
    int n = 0;
    while (log_reach(flow, r, n) > allowed && n < (1 << 20)) ++n;
    return n;
}

std::vector<Tile> plan_tiles(const Domain& whole, int core_cells, int halo_cells) {
    const int n[3] = {whole.nx, whole.ny, whole.nz};
    int count[3];
    for (int a = 0; a < 3; ++a) count[a] = (n[a] + core_cells - 1) / core_cells;
    std::vector<Tile> tiles;
    for (int k = 0; k < count[2]; ++k)
        for (int j = 0; j < count[1]; ++j)
            for (int i = 0; i < count[0]; ++i) {
                Tile t;
                const int at[3] = {i, j, k};
                for (int a = 0; a < 3; ++a) {
                    t.core_lo[std::size_t(a)] = at[a] * core_cells;
                    t.core_hi[std::size_t(a)] = std::min(n[a], (at[a] + 1) * core_cells);
                    t.lo[std::size_t(a)] = std::max(0, t.core_lo[std::size_t(a)] - halo_cells);
                    t.hi[std::size_t(a)] = std::min(n[a], t.core_hi[std::size_t(a)] + halo_cells);
                }
                t.index = int(tiles.size());
                tiles.push_back(t);
            }
    return tiles;
}

Domain tile_domain(const Domain& whole, const Tile& tile) {
    Domain d;
    d.h = whole.h;
    for (int a = 0; a < 3; ++a) d.origin[std::size_t(a)] = whole.origin[std::size_t(a)] + tile.lo[std::size_t(a)] * whole.h;
    d.nx = tile.hi[0] - tile.lo[0];
    d.ny = tile.hi[1] - tile.lo[1];
    d.nz = tile.hi[2] - tile.lo[2];
    d.unit_cells = whole.unit();  // the whole run's numbers: the same rounding in every cell
    // Every axis a multiple of 2^(levels - 1), the coarsest longest at least 8 cells.
    const int longest = std::max({d.nx, d.ny, d.nz});
    d.levels = 1;
    while (d.levels < whole.levels && longest >> d.levels >= 8 && d.nx % (1 << d.levels) == 0 &&
           d.ny % (1 << d.levels) == 0 && d.nz % (1 << d.levels) == 0)
        ++d.levels;
    return d;
}

}  // namespace snvr
