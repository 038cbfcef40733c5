// with_added_points (added_points.hpp).
#include "geometry/added_points.hpp"

#include <algorithm>

#include "geometry/point_tree.hpp"
#include "geometry/sampling_holes.hpp"
#include "geometry/surface_upsampling.hpp"

namespace snvr {
namespace {

// Drops the points farther than `slack` outside the box.
void within(const std::array<Vec3, 2>& box, double slack, PointSet& points) {
    points.erase(std::remove_if(points.begin(), points.end(),
                                [&](const Vec3& p) {
                                    for (int a = 0; a < 3; ++a)
                                        if (!(p[a] >= box[0][a] - slack && p[a] <= box[1][a] + slack)) return true;
                                    return false;
                                }),
                 points.end());
}

}  // namespace

PointCloud with_added_points(const PointCloud& points, double hole_least, double upsample_spacing, double slack,
                             AddedPoints& added, const AddingWays& ways) {
    added = {};
    const std::array<Vec3, 2> box = points.box();
    PointCloud with;
    if (hole_least > 0) {
        PointSet centres = hole_centres(points, hole_least, ways.holes, ways.holes_told);
        within(box, slack, centres);
        added.at_holes = centres.size();
        if (!centres.empty()) with = detail::cloud_with(points, centres);
    }
    if (upsample_spacing > 0) {
        const PointCloud& so_far = with.empty() ? points : with;
        PointSet between =
            ways.between ? ways.between(so_far) : upsample_surface(detail::tree_of(so_far), upsample_spacing);
        within(box, slack, between);
        added.between = between.size();
        if (!between.empty()) with = detail::cloud_with(so_far, between);
    }
    return with;
}

}  // namespace snvr
