// Points held as floats about a double origin (FloatPoints): the rule that picks the
// origin from the first points read, the conversion of one point, and the refusal of a
// point that floats cannot hold.
#pragma once
#include <array>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>

#include "geometry/vec3_math.hpp"
#include "snvr/geometry.hpp"

namespace snvr::detail {

using Float3 = std::array<float, 3>;

// The box of a sample of points (the first ones read), non-finite ones left out: what
// the origin is chosen from before the points are stored.
struct SampleBox {
    Bounds box;
    std::size_t count = 0;  // finite points in the box

    void add(const Vec3& p) {
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) return;
        for (int a = 0; a < 3; ++a) {
            box.lo[a] = count ? std::min(box.lo[a], p[a]) : p[a];
            box.hi[a] = count ? std::max(box.hi[a], p[a]) : p[a];
        }
        ++count;
    }
};

// 0 when the sample's box is near the origin (its centre no farther from 0 than its
// longest side) or empty; otherwise its round centre (round_centre), or for a box of one
// point that point itself. For the bound this gives, see FloatPoints.
Vec3 choose_origin(const SampleBox& sample);

// Whether every point of the box lies within the bound FloatPoints promises of the
// origin: |x - origin| <= 2.5 times the box's diagonal.
bool within_origin_bound(const SampleBox& sample, const Vec3& origin);

// p - origin as floats in `out`; false (out then holds no number to trust) when a
// coordinate is not finite or its difference lies beyond float range.
inline bool to_float(const Vec3& p, const Vec3& origin, Float3& out) {
    bool held = true;
    for (int a = 0; a < 3; ++a) {
        const double d = p[a] - origin[a];
        // Checked before the cast: a double beyond float range has no defined float.
        held = held && std::abs(d) <= double(FLT_MAX);
        out[a] = std::abs(d) <= double(FLT_MAX) ? float(d) : std::numeric_limits<float>::infinity();
    }
    return held;
}

// Throws the InputError for point `index` (p as read), which to_float could not hold:
// a non-finite coordinate, or one beyond float range from the origin.
[[noreturn]] void refuse_point(const std::string& path, std::uint64_t index, const Vec3& p, const Vec3& origin);

}  // namespace snvr::detail
