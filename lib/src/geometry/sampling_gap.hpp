// How far apart the input points are: the offset must exceed about half the
// largest hole in the sampling, or the shell breaks into pieces.
#pragma once
#include "geometry/point_tree.hpp"

namespace snvr {

// A high percentile (99th) of nearest-distinct-neighbour distances, from up to
// 20,000 points evenly strided by input order (detail::strided_sample). 0 when there
// are fewer than two distinct points.
double sampling_gap(const detail::PointTree& tree);

}  // namespace snvr
