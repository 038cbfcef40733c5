// exp and tanh for the phase field's nonlinear terms, for float and double: the
// operations are kernels/phase_math.h's, the one copy the OpenCL kernels also use (see
// there), so both backends get the same bits.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace snvr::detail {

// What phase_math.h needs that C++ spells differently from OpenCL C.
[[gnu::always_inline]] inline std::uint32_t bits_of(float x) {
    std::uint32_t b;
    std::memcpy(&b, &x, sizeof b);
    return b;
}
[[gnu::always_inline]] inline std::uint64_t bits_of(double x) {
    std::uint64_t b;
    std::memcpy(&b, &x, sizeof b);
    return b;
}
[[gnu::always_inline]] inline float from_bits(std::uint32_t b) {
    float x;
    std::memcpy(&x, &b, sizeof x);
    return x;
}
[[gnu::always_inline]] inline double from_bits(std::uint64_t b) {
    double x;
    std::memcpy(&x, &b, sizeof x);
    return x;
}
using std::fabs;

#define PM_INLINE [[gnu::always_inline]] inline
#define PM_AT_LEAST(x, m) std::max(x, m)
#define PM_BITS(x) bits_of(x)
#define PM_FROM_BITS(b) from_bits(b)

#define PM_REAL float
#define PM_SCALAR float
#define PM_DOUBLE 0
#define PM_PARTS ExpPartsFloat
#include "../../../kernels/phase_math.h"
#undef PM_REAL
#undef PM_SCALAR
#undef PM_DOUBLE
#undef PM_PARTS

#define PM_REAL double
#define PM_SCALAR double
#define PM_DOUBLE 1
#define PM_PARTS ExpPartsDouble
#include "../../../kernels/phase_math.h"
#undef PM_REAL
#undef PM_SCALAR
#undef PM_DOUBLE
#undef PM_PARTS

#undef PM_INLINE
#undef PM_AT_LEAST
#undef PM_BITS
#undef PM_FROM_BITS

}  // namespace snvr::detail
