// Rounding a double to the float just below or above it, for float bounding boxes
// that still contain the exact (double) geometry.
#pragma once
#include <cstdint>
#include <cstring>

namespace snvr::detail {

// The float next to a finite f, up or down (std::nextafter is a library call).
inline float next_float(float f, bool up) {
    std::uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    if (f == 0)
        bits = up ? 1u : 0x80000001u;  // the smallest subnormal of either sign
    else if ((f > 0) == up)
        ++bits;
    else
        --bits;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}
inline float round_down(double v) {
    const float f = float(v);
    return double(f) > v ? next_float(f, false) : f;
}
inline float round_up(double v) {
    const float f = float(v);
    return double(f) < v ? next_float(f, true) : f;
}

}  // namespace snvr::detail
