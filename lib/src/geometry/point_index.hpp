// Nearest-neighbour queries on the input points. Wraps nanoflann (Debian ships 1.4,
// whose API differs from later versions) so that no other file depends on it.
#pragma once
#include <cstddef>
#include <functional>
#include <memory>

#include "snvr/geometry.hpp"

namespace snvr {

class PointIndex {
public:
    explicit PointIndex(const PointSet& points);  // keeps a reference to points
    ~PointIndex();
    PointIndex(const PointIndex&) = delete;
    PointIndex& operator=(const PointIndex&) = delete;

    struct Hit {
        double dist_sq;     // >= the bound when nothing was found
        std::size_t index;  // npos when nothing was found
    };
    static constexpr std::size_t npos = std::size_t(-1);

    // The nearest point if it is closer than sqrt(bound_sq). A tight bound (say the
    // distance to a point already known to be near) prunes most of the tree.
    Hit nearest(const Vec3& q, double bound_sq) const;

    const Vec3& point(std::size_t n) const;

    // Calls f(index) for every point closer than `radius` to q.
    void for_each_within(const Vec3& q, double radius, const std::function<void(std::size_t)>& f) const;

    // Distance from point n to its nearest *distinct* point (0 if all points coincide).
    double nearest_other(std::size_t n) const;

    // Distance from point n to its k-th nearest other point (duplicates count; k >= 1;
    // the farthest there is when there are fewer than k others).
    double kth_nearest(std::size_t n, std::size_t k) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace snvr
