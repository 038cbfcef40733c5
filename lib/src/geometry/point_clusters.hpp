// Clusters of points linked by distances below a link (point_clusters.cpp).
#pragma once
#include <cstdint>
#include <vector>

#include "geometry/point_tree.hpp"

namespace snvr::detail {

// For each point of the tree (by tree order), the tree position of its cluster's first
// member, the same for every member and for any number of threads: points are linked
// when their squared distance ((dx^2 + dy^2) + dz^2) is below link_distance^2.
PointArray<std::uint32_t> cluster_roots(const PointTree& tree, double link_distance);

}  // namespace snvr::detail
