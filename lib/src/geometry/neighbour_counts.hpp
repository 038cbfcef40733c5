// Which points have few neighbours (neighbour_counts.cpp): the question both outlier
// rules ask of every point, answered by cells before the tree.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "geometry/point_tree.hpp"

namespace snvr::detail {

// 1 by tree order for each point with fewer than `need` points (itself and duplicates
// included) at squared distance r2 or less: exactly as PointTree::count_within says. A
// node of the tree (up to 128 points) whose box is within reach across clears all its
// points at once; else a point's neighbours are counted in its leaf, then in that node,
// in float with room for rounding, and only the few left open ask the tree.
// Only the points of the blocks that begin below `below` (tree order) are counted; the
// rest are left 0 (another process counts them, shared_filing.hpp).
std::vector<std::uint8_t> points_short_of(const PointTree& tree, double r2, std::size_t need,
                                          std::size_t below = std::size_t(-1));

// The outlier rules' question of every point (points_short_of's), where others may answer
// part of it (solver/shared_filing.hpp); null: this process alone.
using ShortOf = std::function<std::vector<std::uint8_t>(const PointTree& tree, double r2, std::size_t need)>;

}  // namespace snvr::detail
