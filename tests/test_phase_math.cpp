// The phase field's own exp and tanh (kernels/phase_math.h, through
// solver/phase_math.hpp; the kernels run the same header on rows, and
// test_opencl_operations checks they give the same bits): their error against long
// double, in ULP of the true value, over the ranges the solver feeds them.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "solver/phase_math.hpp"

using snvr::detail::exp_nonpositive;
using snvr::detail::tanh_of;

namespace {

// |got - truth| in ULP of truth (the spacing of Real at truth's magnitude).
template <class Real>
double ulps(Real got, long double truth) {
    const Real t = Real(truth);
    const long double ulp = std::nextafter(std::fabs(t), std::numeric_limits<Real>::infinity()) - std::fabs(t);
    return double(std::fabs((long double)got - truth) / ulp);
}

template <class Real>
void check_accuracy() {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> unit(0, 1);
    double exp_worst = 0, tanh_worst = 0;
    const double lowest = std::is_same<Real, float>::value ? -87 : -708;
    for (int n = 0; n < 400000; ++n) {
        // exp over [lowest, 0]: uniform, and near 0 where the reduction's n is 0.
        const Real x = Real(n % 2 ? lowest * unit(rng) : -std::pow(10.0, -12 * unit(rng)));
        exp_worst = std::max(exp_worst, ulps(exp_nonpositive(x), std::exp((long double)x)));
        // tanh over magnitudes 1e-12 .. 20, both signs (tiny arguments test expm1's accuracy).
        const Real y = Real((n % 4 < 2 ? -1 : 1) * std::pow(10.0, -12 + 13.3 * unit(rng)));
        tanh_worst = std::max(tanh_worst, ulps(tanh_of(y), std::tanh((long double)y)));
    }
    std::printf("%s: exp within %.2f ULP, tanh within %.2f ULP\n", std::is_same<Real, float>::value ? "float" : "double",
                exp_worst, tanh_worst);
    // Measured: exp 1.15 / 1.10, tanh 2.48 / 2.75 (float / double). OpenCL allows its
    // own exp and tanh 3 and 5 ULP.
    CHECK(exp_worst <= 1.5);
    CHECK(tanh_worst <= 3);
}

}  // namespace

TEST_CASE("exp and tanh: near the correctly rounded values, float") { check_accuracy<float>(); }

TEST_CASE("exp and tanh: near the correctly rounded values, double") { check_accuracy<double>(); }

TEST_CASE("exp and tanh: exact where the solver relies on it") {
    CHECK(exp_nonpositive(0.0f) == 1.0f);
    CHECK(exp_nonpositive(0.0) == 1.0);
    CHECK(exp_nonpositive(-1e30f) >= 0.0f);
    CHECK(exp_nonpositive(-1e30f) < 1e-37f);
    // tanh(0) = +0 (the mesher reads signs), +-1 far out (the tube switched off).
    CHECK(tanh_of(0.0f) == 0.0f);
    CHECK(!std::signbit(tanh_of(0.0f)));
    CHECK(!std::signbit(tanh_of(0.0)));
    CHECK(tanh_of(1e30f) == 1.0f);
    CHECK(tanh_of(-1e30f) == -1.0f);
    CHECK(tanh_of(-1e300) == -1.0);
    CHECK(tanh_of(20.0) == 1.0);
    // Odd to the bit.
    for (float y : {1e-20f, 3e-4f, 0.1f, 0.5f, 0.9f, 2.0f, 7.5f}) CHECK(tanh_of(-y) == -tanh_of(y));
}
