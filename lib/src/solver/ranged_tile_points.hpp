// A tiled run's needs and points by the ranges of the points that its processes filed
// together and kept (shared_filing.hpp), where the others still hold theirs: each process
// counts the tiles' needs in its own range, the counts summed over all; and each gives
// every other the points of its range within reach of that one's tiles, taking its own
// range's itself. Every count and test is a point's (tile_needs.hpp), and a process's
// points come range by range in the ranges' order, the whole tree's: the same needs,
// owners and points in the same order as the first finds alone, where it walked every
// leaf and copied every point given (the 50 M-point city block: 30 M points, 1.1 s of its
// time while the other waited).
#pragma once
#include <cstddef>
#include <vector>

#include "geometry/point_tree.hpp"
#include "snvr/domain.hpp"
#include "snvr/tiles.hpp"
#include "solver/tile_needs.hpp"
#include "solver/tile_plan.hpp"

namespace snvr {
namespace detail {
struct KeptRange;  // solver/shared_filing.hpp
}

// At the first: whether the others hold their ranges of these points (then each must take
// part: told_range, ranged_needs and ranged_points in turn, on every process).
bool tiles_by_ranges(const detail::PointTree& tree, int processes);

// This process's range as the first has it: at the first, [0, its bound) of its tree,
// each other told its range's size, the first's origin and every scale factor since the
// filing; at another, its kept range, made the first's (whole: [0, its size)).
struct OwnRange {
    const detail::PointTree* tree = nullptr;
    PointRange range;
};
OwnRange tell_ranges(TileScheduler& on, const detail::PointTree& tree);  // at the first
OwnRange told_range(TileScheduler& on, detail::KeptRange* kept);          // at another

// The tiles' needs over every range, on every process.
std::vector<TileNeeds> ranged_needs(TileScheduler& on, const OwnRange& own, const Domain& whole,
                                    const std::vector<Tile>& tiles, int core_cells, int halo_cells, double reach);

// Every process gives every other (but the first, which has them all) its range's points
// within reach of that one's tiles, float coordinates about the first's origin; returns
// this process's own (none at the first), in the whole tree's order. At the first,
// `given` and `own` say how many points went between the processes and how many the
// others took from their own ranges.
struct RangedPointsFacts {
    std::size_t given = 0, own = 0;
};
detail::PointArray<Vec3f> ranged_points(TileScheduler& on, const OwnRange& own, const Domain& whole,
                                        const std::vector<Tile>& tiles, const std::vector<int>& owner,
                                        int core_cells, int halo_cells, double reach, RangedPointsFacts& facts);

}  // namespace snvr
