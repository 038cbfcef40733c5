// exp and tanh for the phase field's nonlinear terms (the initial profile, the exact
// nonlinear step, the tube), written as plain IEEE arithmetic: a Cody-Waite reduction
// and a Taylor polynomial. The one copy of these operations for both backends, so both
// get the same bits (the libraries' exp and tanh differ by an ULP or two), and a loop of
// them vectorises (libm's calls do not). exp is within 1.2 ULP, tanh within 2.8
// (tests/test_phase_math.cpp, against long double).
//
// Common C++ and OpenCL C, included once per type (so no include guard): by
// lib/src/solver/phase_math.hpp for float and double, and spliced into common.cl at
// build time (cmake/embed_kernels.cmake) for the row vector. The includer defines
//   PM_REAL           the argument type: float, double, or a vector of one of them
//   PM_SCALAR         its element type
//   PM_DOUBLE         1: double's constants and polynomial, 0: float's
//   PM_PARTS          a name for this type's ExpParts
//   PM_INLINE         the functions' qualifiers: they must dissolve into their callers'
//                     loops (a call stops them vectorising)
// and what the languages spell differently:
//   PM_AT_LEAST(x, m) max(x, m) per lane
//   PM_BITS(x)        x's bits as an integer (of a vector: per lane)
//   PM_FROM_BITS(b)   the inverse
// and makes fabs(PM_REAL) callable.

#if PM_DOUBLE
#define PM_LOWEST -708.0                          // exp(lowest) is still a normal double
#define PM_ROUND 6755399441055744.0               // 1.5 * 2^52: x + round - round is x rounded to an integer
#define PM_LOG2E 1.4426950408889634
#define PM_LN2_HI 6.93147180369123816490e-01      // few bits: n * ln2_hi is exact for |n| < 2^11
#define PM_LN2_LO 1.90821492927058770002e-10
#define PM_MANTISSA 52
#define PM_BIAS 1023                              // of the exponent field
#else
#define PM_LOWEST -87.0f
#define PM_ROUND 12582912.0f                      // 1.5 * 2^23
#define PM_LOG2E 1.44269502f
#define PM_LN2_HI 6.9314575195e-01f               // n * ln2_hi exact for |n| < 2^9
#define PM_LN2_LO 1.4286067653e-06f
#define PM_MANTISSA 23
#define PM_BIAS 127
#endif

// (e^r - 1) / r by Horner on 1/k!, |r| <= ln2 / 2: to r^6 in float, r^12 in double.
// 1 / (PM_SCALAR)k: the coefficient rounded once, in the type.
PM_INLINE PM_REAL expm1_over_r(PM_REAL r) {
#if PM_DOUBLE
    PM_REAL p = (PM_REAL)(1 / (PM_SCALAR)6227020800);
    p = p * r + 1 / (PM_SCALAR)479001600;
    p = p * r + 1 / (PM_SCALAR)39916800;
    p = p * r + 1 / (PM_SCALAR)3628800;
    p = p * r + 1 / (PM_SCALAR)362880;
    p = p * r + 1 / (PM_SCALAR)40320;
    p = p * r + 1 / (PM_SCALAR)5040;
#else
    PM_REAL p = (PM_REAL)(1 / (PM_SCALAR)5040);
#endif
    p = p * r + 1 / (PM_SCALAR)720;
    p = p * r + 1 / (PM_SCALAR)120;
    p = p * r + 1 / (PM_SCALAR)24;
    p = p * r + 1 / (PM_SCALAR)6;
    p = p * r + (PM_SCALAR)0.5;
    return p * r + (PM_SCALAR)1;
}

// e^x = s (1 + q) for x <= 0 (below `lowest`, e^lowest), s = 2^n, n = round(x / ln2).
typedef struct {
    PM_REAL s, q;
} PM_PARTS;

PM_INLINE PM_PARTS exp_parts(PM_REAL x) {
    x = PM_AT_LEAST(x, (PM_SCALAR)PM_LOWEST);
    const PM_REAL shifted = x * (PM_SCALAR)PM_LOG2E + (PM_SCALAR)PM_ROUND;  // n sits in the low bits
    const PM_REAL n = shifted - (PM_SCALAR)PM_ROUND;
    const PM_REAL r = (x - n * (PM_SCALAR)PM_LN2_HI) - n * (PM_SCALAR)PM_LN2_LO;
    PM_PARTS e;
    // 2^n: n + bias in the exponent field (n >= -126 or -1022 here).
    e.s = PM_FROM_BITS((PM_BITS(shifted) - PM_BITS((PM_REAL)(PM_SCALAR)PM_ROUND) + PM_BIAS) << PM_MANTISSA);
    e.q = r * expm1_over_r(r);
    return e;
}

// e^x for x <= 0.
PM_INLINE PM_REAL exp_nonpositive(PM_REAL x) {
    const PM_PARTS e = exp_parts(x);
    return e.s + e.s * e.q;
}

// tanh(y) = -expm1(-2|y|) / (2 + expm1(-2|y|)), the sign of y; expm1 = (s - 1) + s q
// keeps its relative accuracy near 0 (s = 1 there).
PM_INLINE PM_REAL tanh_of(PM_REAL y) {
    const PM_PARTS e = exp_parts((PM_SCALAR)-2 * fabs(y));
    const PM_REAL m = (e.s - (PM_SCALAR)1) + e.s * e.q;
    const PM_REAL t = ((PM_SCALAR)0 - m) / ((PM_SCALAR)2 + m);  // 0 - m: tanh(0) = +0, not -0
    return y < (PM_SCALAR)0 ? -t : t;  // on vectors: per lane (OpenCL C's select)
}

#undef PM_LOWEST
#undef PM_ROUND
#undef PM_LOG2E
#undef PM_LN2_HI
#undef PM_LN2_LO
#undef PM_MANTISSA
#undef PM_BIAS
