// choose_origin and refuse_point (float_origin.hpp).
#include "io/float_origin.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "io/io_common.hpp"
#include "snvr/error.hpp"

namespace snvr::detail {
namespace {

std::string triple(const Vec3& p) {
    return format_number(p[0]) + " " + format_number(p[1]) + " " + format_number(p[2]);
}

}  // namespace

Vec3 choose_origin(const SampleBox& sample) {
    if (sample.count == 0) return {0, 0, 0};
    const Bounds& box = sample.box;
    const Vec3 centre{box.lo[0] / 2 + box.hi[0] / 2, box.lo[1] / 2 + box.hi[1] / 2, box.lo[2] / 2 + box.hi[2] / 2};
    const double longest = box.longest();
    // hypot, not norm: the squares of survey-sized doubles may overflow.
    if (std::hypot(centre[0], centre[1], centre[2]) <= longest) return {0, 0, 0};
    if (!(longest > 0)) return centre;  // one point (or one place): itself, exactly
    const Vec3 round = round_centre(box);
    const bool finite = std::isfinite(round[0]) && std::isfinite(round[1]) && std::isfinite(round[2]);
    return finite ? round : centre;
}

bool within_origin_bound(const SampleBox& sample, const Vec3& origin) {
    if (sample.count == 0) return true;
    const Bounds& box = sample.box;
    Vec3 farthest;  // the corner farthest from the origin, as a difference
    for (int a = 0; a < 3; ++a) farthest[a] = std::max(std::abs(box.lo[a] - origin[a]), std::abs(box.hi[a] - origin[a]));
    return std::hypot(farthest[0], farthest[1], farthest[2]) <=
           2.5 * std::hypot(box.extent(0), box.extent(1), box.extent(2));
}

void refuse_point(const std::string& path, std::uint64_t index, const Vec3& p, const Vec3& origin) {
    const std::string point = path + ": point " + std::to_string(index);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
        throw InputError(point + " has a non-finite coordinate (" + triple(p) + ")");
    throw InputError(point + " (" + triple(p) + ") lies beyond 32-bit float range from the points' origin (" +
                     triple(origin) + "): the coordinates span too far");
}

}  // namespace snvr::detail
