// The holes of a sparse scan's sampling (sampling_holes.hpp) found by all the processes of
// a tiled run, before the plan goes out: in each pass each finds those at an equal run of
// the cloud's order, on the whole cloud filed in the first's frame (so that each point's
// neighbours are the first's), and the root puts them together: the same holes, so the
// same centres (a city block's 12.5 M points at 2048 cells: 9.8% of them border holes,
// about 10 us a point).
#pragma once
#include <cstddef>

#include "geometry/sampling_holes.hpp"
#include "snvr/tiles.hpp"

namespace snvr {

// At the root, hole_centres' question of the others for each pass (null where no other is
// there): each is given the pass's cloud and its run; the root's own run is the first.
// `elsewhere` counts the points of the others' runs in the first pass (over all points).
AskHoles holes_shared(TileScheduler& on, std::size_t& elsewhere);
// At the root, once the holes are found (or none was looked for): the others are told.
void holes_done(TileScheduler& on);
// At another process, before the points between: its runs' holes in each pass, found and
// sent back, until the root says they are done.
void holes_for_root(TileScheduler& on);

}  // namespace snvr
