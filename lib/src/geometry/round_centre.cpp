// round_centre: the shift that brings survey coordinates to the origin (geometry.hpp).
#include <algorithm>
#include <cmath>

#include "geometry/vec3_math.hpp"
#include "snvr/geometry.hpp"
#include "snvr/point_cloud.hpp"

namespace snvr {

Vec3 round_centre(const PointSet& points) {
    return round_centre(bounds(points));  // both corners 0 for no points: no shift
}

Vec3 round_centre(const Bounds& box) {
    const double longest = box.longest();
    const double step = longest > 0 && std::isfinite(longest) ? std::pow(10.0, std::floor(std::log10(longest))) : 1.0;
    Vec3 centre{};
    for (int a = 0; a < 3; ++a) centre[a] = std::round((box.lo[a] / 2 + box.hi[a] / 2) / step) * step;
    return centre;
}

Vec3 round_centre(const PointCloud& points) {
    if (points.empty()) return {0, 0, 0};
    const std::array<Vec3, 2> box = points.box();
    return round_centre(Bounds{box[0], box[1]});
}

}  // namespace snvr
