// The points added between a sparse scan's points (surface_upsampling.hpp) made by all the
// processes of a tiled run, before the plan goes out: each makes those of an equal run of
// the cloud's order, on the whole cloud (a sparse scan's points are few against those
// added between them: the bunny at 512, 36 k points and 432 k added), and the root puts
// them together in order, the whole's points.
#pragma once
#include <cstddef>

#include "geometry/added_points.hpp"
#include "snvr/tiles.hpp"

namespace snvr {

// At the root, with_added_points' maker of the points between: its own run made here,
// the others' by them (the share given to each, then theirs taken in order). `elsewhere`
// counts the points the others made. Call it at most once.
PointSet points_between_shared(TileScheduler& on, const PointCloud& so_far, double spacing, std::size_t& elsewhere);
// At the root, where no points were made between: the others are told (they wait for it).
void no_points_between(TileScheduler& on);
// At another process, before anything else of the run: its share of the points between,
// made and sent back (none where the root adds none).
void points_between_for_root(TileScheduler& on);

}  // namespace snvr
