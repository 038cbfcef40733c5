// The check's walls shared among a tiled run's processes (shared_check.hpp).
#include "pipeline/shared_check.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "check/walls.hpp"
#include "snvr/error.hpp"
#include "solver/tile_plan.hpp"

namespace snvr::detail {
namespace {

// The cell holding coordinate x along an axis of `n` cells (clamped to the grid).
int cell_of(double x, double origin, double h, int n) {
    return std::clamp(int(std::floor((x - origin) / h)), 0, n - 1);
}

}  // namespace

MeshQuality check_sharing_walls(const Mesh& mesh, const PointCloud& points, const Result& run, bool surface,
                                TileScheduler& on) {
    const Domain& d = run.domain;
    const int core = run.tiles.core_cells;
    const std::array<int, 3> n{d.nx, d.ny, d.nz};
    const std::array<int, 3> across{(d.nx + core - 1) / core, (d.ny + core - 1) / core, (d.nz + core - 1) / core};
    const std::vector<int>& owners = run.tiles.owners;
    const int processes = on.processes();
    // Who measures the walls in each tile: the process that ran it; the first process's own
    // tiles (and those no one ran) are dealt to every process in turn, as it has the rest of
    // the check to do meanwhile (the grid, the edges and topology, the points' depths): on
    // two processes, dealt to the other alone, the first then waited for it (the bunny at
    // 512: its check 1.9 s; keeping all its own, 2.1 s; dealt to both, 1.75 s).
    const auto owner_at = [&](const std::array<int, 3>& cell) {
        const std::size_t t = tile_holding(d, core, cell);
        const int p = t < owners.size() ? owners[t] : 0;
        return p > 0 && p < processes ? p : int(t % std::size_t(processes));
    };
    // A wall thicker than this is measured by the first process: the shells' are about twice the offset.
    const double reach = 4 * run.offset + 2 * d.h;
    WallsElsewhere elsewhere;
    elsewhere.vertex.assign(mesh.vertices.size(), 0);
    std::vector<std::vector<std::uint32_t>> measured(static_cast<std::size_t>(processes));  // by each other process
    {  // what builds the shares, freed before the first measures its own part
        std::vector<int> by(mesh.vertices.size(), 0);  // the process that measures each vertex's wall
        // The tiles within the reach of each vertex, lowest and highest along each axis: a
        // triangle's box widened by the reach meets the tiles from its corners' lowest to their
        // highest (the cells are monotone in the coordinates).
        std::vector<std::array<std::uint16_t, 6>> reach_tiles(mesh.vertices.size());
        for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
            std::array<int, 3> c;
            for (std::size_t a = 0; a < 3; ++a) {
                const double x = mesh.vertices[v][a];
                c[a] = cell_of(x, d.origin[a], d.h, n[a]);
                reach_tiles[v][a] = std::uint16_t(cell_of(x - reach, d.origin[a], d.h, n[a]) / core);
                reach_tiles[v][3 + a] = std::uint16_t(cell_of(x + reach, d.origin[a], d.h, n[a]) / core);
            }
            by[v] = owner_at(c);
            elsewhere.vertex[v] = by[v] != 0;
        }
        std::vector<std::size_t> tiles_of(static_cast<std::size_t>(processes), 0);  // whose walls each measures
        const std::size_t tiles = std::size_t(across[0]) * std::size_t(across[1]) * std::size_t(across[2]);
        for (int k = 0; k < across[2]; ++k)
            for (int j = 0; j < across[1]; ++j)
                for (int i = 0; i < across[0]; ++i) ++tiles_of[std::size_t(owner_at({i * core, j * core, k * core}))];
        // Each other process's share: the triangles (in the shell's order, so that its normals
        // sum as the whole's) whose box, widened by the reach, meets one of its tiles.
        const double eps = wall_epsilon(mesh);
        std::vector<std::uint32_t> local(mesh.vertices.size());
        for (int p = 1; p < processes; ++p) {
            WallShare share;
            share.epsilon = eps;
            share.reach = reach;
            std::fill(local.begin(), local.end(), std::numeric_limits<std::uint32_t>::max());
            const bool every_tile = tiles_of[std::size_t(p)] == tiles;  // two processes: the other has them all
            for (const auto& t : mesh.triangles) {
                std::array<int, 3> lo, hi;
                for (std::size_t a = 0; a < 3; ++a) {
                    lo[a] = std::min({reach_tiles[t[0]][a], reach_tiles[t[1]][a], reach_tiles[t[2]][a]});
                    hi[a] = std::max({reach_tiles[t[0]][3 + a], reach_tiles[t[1]][3 + a], reach_tiles[t[2]][3 + a]});
                }
                bool near = every_tile;
                for (int k = lo[2]; k <= hi[2] && !near; ++k)
                    for (int j = lo[1]; j <= hi[1] && !near; ++j)
                        for (int i = lo[0]; i <= hi[0] && !near; ++i) near = owner_at({i * core, j * core, k * core}) == p;
                if (!near) continue;
                std::array<std::uint32_t, 3> mine;
                for (int c = 0; c < 3; ++c) {
                    std::uint32_t& at = local[t[std::size_t(c)]];
                    if (at == std::numeric_limits<std::uint32_t>::max()) {
                        at = std::uint32_t(share.vertices.size());
                        share.vertices.push_back(mesh.vertices[t[std::size_t(c)]]);
                        if (by[t[std::size_t(c)]] == p) {
                            share.measured.push_back(at);
                            measured[std::size_t(p)].push_back(t[std::size_t(c)]);
                        }
                    }
                    mine[std::size_t(c)] = at;
                }
                share.triangles.push_back(mine);
            }
            on.give_walls(p, share);
        }
    }
    // Vertices of another's tiles in no triangle: no wall anywhere (infinity, as alone).
    elsewhere.fill = [&](std::vector<double>& wall) {
        for (std::size_t v = 0; v < wall.size(); ++v)
            if (elsewhere.vertex[v]) wall[v] = std::numeric_limits<double>::infinity();
        for (int p = 1; p < processes; ++p) {
            const std::vector<double> got = on.take_walls(p);
            const std::vector<std::uint32_t>& ids = measured[std::size_t(p)];
            if (got.size() != ids.size()) throw Error("the walls from process " + std::to_string(p) + " are not whole");
            for (std::size_t k = 0; k < ids.size(); ++k) wall[ids[k]] = got[k];
        }
    };
    return measure_sharing_walls(mesh, points, run.offset, d.h, surface, elsewhere);
}

}  // namespace snvr::detail
