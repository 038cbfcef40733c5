// The holes of a sparse scan's sampling (sampling_holes.hpp) found by all the processes of
// a tiled run, before the plan goes out: in the first pass each finds those at an equal
// run of the cloud's order, on the whole cloud filed in the first's frame (so that each
// point's neighbours are the first's), and the root puts them together: the same holes, so
// the same centres (a city block's 12.5 M points at 2048 cells: 9.8% of them border holes,
// about 10 us a point).
#pragma once

#include "geometry/sampling_holes.hpp"
#include "snvr/tiles.hpp"

namespace snvr {

// At the root, hole_centres' question of the others (null where no other is there): each
// is given the cloud and its run; the root's own run is the first; `elsewhere` counts the
// points of the others' runs. Whether it was asked is told by `asked`; where it was not,
// no_holes_asked tells the others.
AskHoles holes_shared(TileScheduler& on, bool& asked, std::size_t& elsewhere);
void no_holes_asked(TileScheduler& on);
// At another process, before the points between: its run's holes, found and sent back
// (nothing where the root asks none).
void holes_for_root(TileScheduler& on);

}  // namespace snvr
