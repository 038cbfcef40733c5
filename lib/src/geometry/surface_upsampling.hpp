// Points on the surface between the points of a sampling sparse against the offset: where
// the points are about the offset apart, the union of their balls (the distance's level
// l) is a bunch of grapes whose valleys sit a tenth of l inside the offset surface, and a
// flow at the voxel's scale cannot smooth that away. Filled in at a fraction of the
// offset on the surface the points describe, the union of balls is the offset surface.
#pragma once
#include <cstddef>

#include "geometry/point_tree.hpp"

namespace snvr {

// Points `spacing` apart on each point's local surface: the quadric height field over the
// plane of its nearest 20 others (those within 30 degrees of it; the plane of the nearest
// 8, fitted again to all that stand near it), on a triangular grid in
// the disc of half the distance to its 6th nearest, inside their convex hull (so that a
// surface's boundary does not grow). World units.
PointSet upsample_surface(const detail::PointTree& tree, double spacing);
// Those of points [begin, end) of the tree's order: the parts of a split, put together in
// order, are the whole's.
PointSet upsample_surface(const detail::PointTree& tree, double spacing, std::size_t begin, std::size_t end);

}  // namespace snvr
