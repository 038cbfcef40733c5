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

// Which of a mesh's vertices and of the points a guard's report counts: a slab's own,
// where each process guards a slab of the surface with ghosts (solver/slab_surface.hpp).
struct GuardCounted {
    std::size_t vertex_begin = 0, vertex_end = 0;
    std::function<bool(std::uint32_t point)> point;
};

// How far the guard's work on a vertex reaches, for a slab's ghosts: in planes of the
// mesh (the lift of the vertices within the aim of a point, spread over rings), and in
// world units from a vertex to the points that can move it (guard_point_reach: lone as
// keep_points_deep takes it). What the repair and untangling rounds add beyond this is
// not bounded here: a slab's guard checks its ghosts against its neighbours' own instead.
int guard_reach_planes(double depth, double voxel);
double guard_point_reach(double depth, double voxel, double lone);

}  // namespace snvr::detail
