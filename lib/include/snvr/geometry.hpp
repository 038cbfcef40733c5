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

}  // namespace snvr
