// Evenly strided samples of a cloud's points by their input order, the same points
// whatever order the cloud keeps them in (point_samples.cpp).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "geometry/point_tree.hpp"

namespace snvr::detail {

// The points of ranks floor(s n / samples), s = 0 .. samples - 1, among the tree's n
// points by input index (all of them when samples >= n): their positions in the tree,
// ascending (the callers' figures are over the sample as a set: medians, percentiles,
// counts; searches from points near each other in the tree go faster in turn).
std::vector<std::uint32_t> strided_sample(const PointTree& tree, std::size_t samples);

}  // namespace snvr::detail
