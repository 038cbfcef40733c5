// The points a run works on, compact and searchable (lib/src/geometry/point_cloud.cpp).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "snvr/geometry.hpp"

namespace snvr {

using Vec3f = std::array<float, 3>;

namespace detail {
class PointTree;
struct CloudAccess;  // the library's stages reach the tree through it (geometry/point_tree.hpp)
}

// Float coordinates about an origin (world = origin + coordinate, summed in double):
// 12 bytes a point and 4 for its place in the input, against 24 for a PointSet. The
// points are kept in a spatial (Morton) order and filed once into a tree of boxes that
// every stage of a run searches (outliers, sampling gap, distance, depth guard, check),
// so a stage looks at single points only where a box's bound is close to its threshold.
// Float holds a point to 6e-8 of its distance from the origin: with the origin near the
// points, a 1e6-cell grid's voxel is still 16 times coarser. A float file's points near
// the world origin are held exactly (origin 0).
class PointCloud {
public:
    PointCloud();
    // Rounds each point to float about an origin: 0 when every coordinate is a float or
    // the points' box is near the world origin (its centre no farther from it than its
    // longest side), else round_centre(points). Throws InputError for a non-finite
    // coordinate (naming the point, counted from 0), ResourceError beyond 2^32 - 1 points.
    explicit PointCloud(const PointSet& points);
    // The same from n points as 3n coordinates x0 y0 z0 x1 ... (a numpy (n, 3) array), read
    // straight into the cloud.
    PointCloud(const double* xyz, std::size_t n);
    PointCloud(const float* xyz, std::size_t n);
    // Takes coordinates about `origin`, as the readers make them; the same errors.
    PointCloud(std::vector<Vec3f> coordinates, const Vec3& origin);
    PointCloud(const PointCloud&);
    PointCloud& operator=(const PointCloud&);
    PointCloud(PointCloud&&) noexcept;
    PointCloud& operator=(PointCloud&&) noexcept;
    ~PointCloud();

    std::size_t size() const;
    bool empty() const { return size() == 0; }
    // Point k in the cloud's own (spatial) order, in world units.
    Vec3 operator[](std::size_t k) const;
    // Point k's place in the input it was made from (0-based).
    std::size_t input_index(std::size_t k) const;
    const Vec3& origin() const;
    // The points' box in world units, {lo, hi} (both the origin for no points).
    std::array<Vec3, 2> box() const;
    // The points in world units, in input order.
    PointSet to_point_set() const;

    // Keeps the points whose flag (by the cloud's order) is set: the order of the rest, and
    // each one's input index, stay as they were.
    void keep(const std::vector<std::uint8_t>& flags);
    // Multiplies every point by factor (> 0): a change of units, in float.
    void scale(double factor);
    // Adds `by` to every point (the origin moves; the coordinates stay).
    void translate(const Vec3& by);

private:
    friend struct detail::CloudAccess;
    std::unique_ptr<detail::PointTree> tree_;
};

// round_centre (geometry.hpp) of a cloud's points.
Vec3 round_centre(const PointCloud& points);

}  // namespace snvr
