// Stray points near a surface (stray_points.cpp): the outliers that the density rule
// keeps because they lie within a few spacings of the surface, where each raises a bump
// on the shell.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "geometry/neighbour_counts.hpp"
#include "geometry/point_tree.hpp"

namespace snvr::detail {

struct StraySettings {
    std::size_t neighbours = 16;  // the plane is fitted to this many nearest other points
    // A point stands off its neighbours' plane when its distance to it exceeds both
    // plane_sigmas times their scatter about it and plane_reach times the distance to the
    // farthest of them.
    double plane_sigmas = 100;
    double plane_reach = 0.5;
    // Only lonely points are looked at: with fewer than `company` other points within
    // lonely_factor times the median distance to a point's nearest neighbour (a surface
    // point has a dozen there; a stray point, or two near each other, next to none).
    double lonely_factor = 2;
    std::size_t company = 3;
    // ... but never within less than this (world units): a point nearer the surface than
    // the shell can show (half a voxel) raises no bump worth a look, and in a cloud far
    // denser than the grid every point then has company.
    double least_lonely = 0;
    std::size_t median_sample = 100000;
};

// 1 by tree order for each point that stands off the plane of its nearest neighbours:
// the neighbourhood is flat (its scatter about the plane is small against the point's
// distance) and the point sits clearly above it. Points on an edge, a corner or thin
// detail have no flat neighbourhood to stand off; points in a sparse but flat part lie
// in their neighbours' plane. Empty when no point stands off.
// The lonely points are asked of short_of where given.
std::vector<std::uint8_t> stray_points(const PointTree& tree, const StraySettings& settings = {},
                                       const ShortOf& short_of = nullptr);

}  // namespace snvr::detail
