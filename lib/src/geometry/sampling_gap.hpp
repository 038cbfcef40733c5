// How far apart the input points are: the offset must exceed about half the
// largest hole in the sampling, or the shell breaks into pieces.
#pragma once
#include "geometry/point_index.hpp"
#include "snvr/geometry.hpp"

namespace snvr {

// A high percentile (99th) of nearest-distinct-neighbour distances, from up to
// 20,000 evenly strided points. 0 when there are fewer than two distinct points.
double sampling_gap(const PointSet& points, const PointIndex& index);

}  // namespace snvr
