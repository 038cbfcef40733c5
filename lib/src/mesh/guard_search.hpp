// The depth guard's first search (depth_guard.cpp), which other processes can take in
// part: over a run spread over processes, each searches its own range of the points
// (pipeline/shared_guard.cpp), the search's answers being the same whoever finds them.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "snvr/mesh.hpp"

namespace snvr::detail {

class PointTree;

// A point, a triangle nearer than the depth to it, and their distance.
struct PointTriangle {
    std::uint32_t point, triangle;
    double dist;
};

// What the first search finds on the mesh as it starts, for a set of points: the
// vertices within `aim` of one of them (ascending), and every pair of a point and a
// triangle nearer than `depth` to it (by point, then triangle).
struct GuardFound {
    std::vector<std::uint32_t> near_vertices;
    std::vector<PointTriangle> close;
};
// The search for every point of `points` (another process's range, its points named by
// their places in it).
GuardFound guard_search(const Mesh& mesh, const PointTree& points, double aim, double depth);

// Other processes' part of the search: they search the points from `here_end` on (by
// the tree's order), this process those before. `ask` gives them the mesh and the
// lengths, before this process searches its own; `collect` then takes what they found,
// its points named by the tree's order.
struct GuardElsewhere {
    std::size_t here_end = 0;
    std::function<void(const Mesh& mesh, double aim, double depth)> ask;
    std::function<GuardFound()> collect;
};

}  // namespace snvr::detail
