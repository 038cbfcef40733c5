// What a tiled run's tiles need of the points, and which process runs each
// (tiled_reconstruct.cpp).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "geometry/point_tree.hpp"
#include "snvr/domain.hpp"
#include "snvr/reconstruct.hpp"
#include "solver/tile_plan.hpp"

namespace snvr {

// How far from a point a cell can be and still be in the band or the offset's reach: the
// offset, the band's cut (band_xi xi, at least a voxel) and a voxel more.
double band_reach(const DomainPlan& plan, const Parameters& params);

// How many points lie within `reach` of a tile's box (halo included), and whether any
// lies within reach of its core. A cell's distance and band depend only on the points
// within the offset and the band's cut of it; where no point comes that near the core,
// every cell of it is -1 in the whole run from the start, and the tile need not run.
struct TileNeeds {
    std::size_t points = 0;
    bool core_near = false;
};

// The points [begin, end) of a tree's order that a walk over its leaves looks at (a
// leaf across a bound, its points on this side): a process's own range of the points
// filed by all (ranged_tile_points.hpp). Every count and test below is a point's, so the
// ranges' answers add up to the whole tree's, whatever tree their leaves fall in.
struct PointRange {
    std::uint32_t begin = 0, end = std::numeric_limits<std::uint32_t>::max();
};

// Each tile's needs, leaf by leaf of the tree (in parallel).
std::vector<TileNeeds> needs_of(const detail::PointTree& tree, const Domain& whole, const std::vector<Tile>& tiles,
                                int core_cells, int halo_cells, double reach, PointRange range = {});

// Which points each other process's tiles need (the first's own: none, it has them all):
// those within `reach` of a tile's box (halo included) that the process runs, each once,
// as runs [begin, end) of the tree's order (by process; found in one walk over the tree's
// leaves, whatever the processes).
using PointRuns = std::vector<std::array<std::uint32_t, 2>>;
std::vector<PointRuns> point_runs(const detail::PointTree& tree, const Domain& whole, const std::vector<Tile>& tiles,
                                  const std::vector<int>& owner, int processes, int core_cells, int halo_cells,
                                  double reach, PointRange range = {});
// The points with z in each window [lo, hi] (world units; one a process, empty where
// hi < lo), as runs of the tree's order, found in one walk over the leaves.
std::vector<PointRuns> z_window_runs(const detail::PointTree& tree, const std::vector<std::array<double, 2>>& windows);
// Those points' float coordinates about the tree's origin, x y z in turn.
detail::PointArray<float> points_in(const detail::PointTree& tree, const PointRuns& runs);

// Which process runs each tile: the heaviest first (by the points near it), each to the
// process with the least so far; the same on every process. -1: not run.
std::vector<int> owners_of(const std::vector<TileNeeds>& needs, int processes);

}  // namespace snvr
