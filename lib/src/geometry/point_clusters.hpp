// Clusters of points linked by distances below a link (point_clusters.cpp).
#pragma once
#include <cstddef>
#include <vector>

#include "snvr/geometry.hpp"

namespace snvr {

// For each point, the smallest index in its cluster (the same for every member, so
// label[k] == k marks one point of each cluster). Points with a coordinate that is not
// finite are clusters of their own.
std::vector<std::size_t> point_cluster_labels(const PointSet& points, double link_distance);

}  // namespace snvr
