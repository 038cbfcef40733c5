// round_centre: the shift that brings survey coordinates to the origin (geometry.hpp).
#include <algorithm>
#include <cmath>

#include "snvr/geometry.hpp"

namespace snvr {

Vec3 round_centre(const PointSet& points) {
    if (points.empty()) return {0, 0, 0};
    Vec3 lo = points[0], hi = points[0];
    for (const Vec3& p : points)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], p[a]);
            hi[a] = std::max(hi[a], p[a]);
        }
    const double longest = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    const double step = longest > 0 && std::isfinite(longest) ? std::pow(10.0, std::floor(std::log10(longest))) : 1.0;
    Vec3 centre{};
    for (int a = 0; a < 3; ++a) centre[a] = std::round((lo[a] / 2 + hi[a] / 2) / step) * step;
    return centre;
}

}  // namespace snvr
