// exp and tanh for the phase field's nonlinear terms (the initial profile, the exact
// nonlinear step, the tube), written as plain IEEE arithmetic: a Cody-Waite reduction
// and a Taylor polynomial. kernels/common.cl holds the same operations in the same
// order, so both backends get the same bits (the libraries' exp and tanh differ by an
// ULP or two), and a loop of them vectorises (libm's calls do not). exp is within
// 1.2 ULP, tanh within 2.8 (tests/test_phase_math.cpp, against long double).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace snvr::detail {

template <class Real>
struct ExpConstants;

template <>
struct ExpConstants<float> {
    using Bits = std::uint32_t;
    static constexpr float lowest = -87.0f;       // exp(lowest) is still a normal float
    static constexpr float round = 12582912.0f;   // 1.5 * 2^23: x + round - round is x rounded to an integer
    static constexpr float log2e = 1.44269502f;
    static constexpr float ln2_hi = 6.9314575195e-01f;  // few bits: n * ln2_hi is exact for |n| < 2^9
    static constexpr float ln2_lo = 1.4286067653e-06f;
    static constexpr int mantissa = 23;
    static constexpr Bits bias = 127;  // of the exponent field
};

template <>
struct ExpConstants<double> {
    using Bits = std::uint64_t;
    static constexpr double lowest = -708.0;
    static constexpr double round = 6755399441055744.0;  // 1.5 * 2^52
    static constexpr double log2e = 1.4426950408889634;
    static constexpr double ln2_hi = 6.93147180369123816490e-01;  // n * ln2_hi exact for |n| < 2^11
    static constexpr double ln2_lo = 1.90821492927058770002e-10;
    static constexpr int mantissa = 52;
    static constexpr Bits bias = 1023;
};

// (e^r - 1) / r by Horner on 1/k!, |r| <= ln2 / 2: to r^6 in float, r^12 in double.
[[gnu::always_inline]] inline float expm1_over_r(float r) {
    float p = 1.0f / 5040.0f;
    p = p * r + 1.0f / 720.0f;
    p = p * r + 1.0f / 120.0f;
    p = p * r + 1.0f / 24.0f;
    p = p * r + 1.0f / 6.0f;
    p = p * r + 0.5f;
    return p * r + 1.0f;
}

[[gnu::always_inline]] inline double expm1_over_r(double r) {
    double p = 1.0 / 6227020800.0;
    p = p * r + 1.0 / 479001600.0;
    p = p * r + 1.0 / 39916800.0;
    p = p * r + 1.0 / 3628800.0;
    p = p * r + 1.0 / 362880.0;
    p = p * r + 1.0 / 40320.0;
    p = p * r + 1.0 / 5040.0;
    p = p * r + 1.0 / 720.0;
    p = p * r + 1.0 / 120.0;
    p = p * r + 1.0 / 24.0;
    p = p * r + 1.0 / 6.0;
    p = p * r + 0.5;
    return p * r + 1.0;
}

// e^x = s (1 + q) for x <= 0 (below `lowest`, e^lowest), s = 2^n, n = round(x / ln2).
template <class Real>
struct ExpParts {
    Real s, q;
};

// Always inlined: a call would stop the callers' loops from vectorising.
template <class Real>
[[gnu::always_inline]] inline ExpParts<Real> exp_parts(Real x) {
    using C = ExpConstants<Real>;
    using Bits = typename C::Bits;
    x = std::max(x, C::lowest);
    const Real shifted = x * C::log2e + C::round;  // n sits in the low bits
    const Real n = shifted - C::round;
    const Real r = (x - n * C::ln2_hi) - n * C::ln2_lo;
    Bits bits, round_bits;
    std::memcpy(&bits, &shifted, sizeof bits);
    std::memcpy(&round_bits, &C::round, sizeof round_bits);
    // 2^n: n + bias in the exponent field (n >= -126 or -1022 here).
    const Bits pow2 = Bits(bits - round_bits + C::bias) << C::mantissa;
    ExpParts<Real> e;
    std::memcpy(&e.s, &pow2, sizeof pow2);
    e.q = r * expm1_over_r(r);
    return e;
}

// e^x for x <= 0.
template <class Real>
[[gnu::always_inline]] inline Real exp_nonpositive(Real x) {
    const ExpParts<Real> e = exp_parts(x);
    return e.s + e.s * e.q;
}

// tanh(y) = -expm1(-2|y|) / (2 + expm1(-2|y|)), the sign of y; expm1 = (s - 1) + s q
// keeps its relative accuracy near 0 (s = 1 there).
template <class Real>
[[gnu::always_inline]] inline Real tanh_of(Real y) {
    const ExpParts<Real> e = exp_parts(Real(-2) * std::fabs(y));
    const Real m = (e.s - Real(1)) + e.s * e.q;
    const Real t = (Real(0) - m) / (Real(2) + m);  // 0 - m: tanh(0) = +0, not -0
    return y < 0 ? -t : t;
}

}  // namespace snvr::detail
