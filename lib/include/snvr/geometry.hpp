// Basic geometric types shared by every part of the library.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

namespace snvr {

using Vec3 = std::array<double, 3>;
using PointSet = std::vector<Vec3>;

// Triangle mesh with shared (welded) vertices; triangles are counter-clockwise
// seen from outside, so their normals point out of the solid.
struct Mesh {
    std::vector<Vec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
};

// A round translation to the points' box centre: the centre rounded to a multiple of
// the largest power of ten not above the box's longest side. Subtracted from the
// points it brings them near the origin, where float32 files hold them to a small
// fraction of a voxel; a user adds it back by hand. Zero for an empty set.
Vec3 round_centre(const PointSet& points);

}  // namespace snvr
