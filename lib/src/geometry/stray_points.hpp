// Stray points near a surface (stray_points.cpp): the outliers that the density rule
// keeps because they lie within a few spacings of the surface, where each raises a bump
// on the shell.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "geometry/neighbour_counts.hpp"
#include "geometry/point_tree.hpp"
#include "told_pace.hpp"

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
// Where other processes keep ranges of the points (solver/shared_filing.hpp), each tests
// its own range's lonely points: `ask`, given the rule and every point's lonely flag, puts
// the question and returns the end of the points this process tests itself, and what then
// takes the others' answers: their strays (flags set by place) and the places they could
// not decide, which this process tests.
struct StraysElsewhere {
    std::size_t here_end = 0;
    std::function<void(std::vector<std::uint8_t>& stray, std::vector<std::uint32_t>& undecided)> collect;
};
using AskStrays =
    std::function<StraysElsewhere(const PointTree&, const StraySettings&, const std::vector<std::uint8_t>& alone)>;

// The lonely points are asked of short_of where given, and tested elsewhere where asked;
// `told`: how far the tests here have come (the longest of the outlier rules).
std::vector<std::uint8_t> stray_points(const PointTree& tree, const StraySettings& settings = {},
                                       const ShortOf& short_of = nullptr, const AskStrays& elsewhere = nullptr,
                                       const Told& told = nullptr);

// Another process's answer for its range (`range`: a tree of the points whose filing keys
// lie in [keys_lo, keys_hi), the first's whole tree being all ranges in key order;
// `alone`: their lonely flags, by place): the places of those that stand off, and of
// those whose neighbours may lie in another range. Each decided is decided as the whole
// tree decides it: its nearest neighbours' ball, widened by `rounding_cells` of the
// frame's cells (the points may have been scaled since they were filed), holds keys of
// this range only, so that its neighbours are the whole cloud's, in the same order.
struct RangeStrays {
    std::vector<std::uint32_t> strays, undecided;
};
RangeStrays range_strays(const PointTree& range, const StraySettings& settings, const std::vector<std::uint8_t>& alone,
                         std::uint64_t keys_lo, std::uint64_t keys_hi, int rounding_cells);

}  // namespace snvr::detail
