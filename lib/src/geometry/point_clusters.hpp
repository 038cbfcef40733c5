// Clusters of points linked by distances below a link (point_clusters.cpp).
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "geometry/point_tree.hpp"

namespace snvr::detail {

// For each point of the tree (by tree order), the tree position of its cluster's first
// member, the same for every member and for any number of threads: points are linked
// when their squared distance ((dx^2 + dy^2) + dz^2) is below link_distance^2.
PointArray<std::uint32_t> cluster_roots(const PointTree& tree, double link_distance);

// The same where other processes link their own ranges of the tree (solver/
// shared_filing.hpp): `bounds` as PointTree::shared_ranges (this process's range first);
// this one links every pair but those within one other's range, and theirs(p) gives
// process p's range's own roots (cluster_roots of that range alone, by its places): the
// same roots, every pair's link made by one process or the other.
PointArray<std::uint32_t> cluster_roots(const PointTree& tree, double link_distance, const std::vector<std::size_t>& bounds,
                                        const std::function<PointArray<std::uint32_t>(int)>& theirs);

// The outlier rules' clusters (cluster_roots'), where others may link part of them
// (solver/shared_filing.hpp); null: this process alone.
using RootsOf = std::function<PointArray<std::uint32_t>(const PointTree& tree, double link_distance)>;

}  // namespace snvr::detail
