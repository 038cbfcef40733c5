// Differences between the two backends, in units of the values' ULP.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace snvr::testing {

// Spacing of Real numbers at |x| (the ULP of x).
template <class Real>
double ulp_of(Real x) {
    const Real a = std::abs(x);
    return double(std::nextafter(a, std::numeric_limits<Real>::infinity()) - a);
}

// max over cells of |a - b| / ulp(max(|a|, |b|, scale)); infinite where exactly one is
// NaN. `scale` is for fields whose small values come from cancellation (g = 1 - phi^2
// near the cut): their error is that of the terms, so it is counted in the terms' ULP.
template <class Real>
double max_ulps(const std::vector<Real>& a, const std::vector<Real>& b, Real scale = 0) {
    double worst = 0;
    for (std::size_t n = 0; n < a.size(); ++n) {
        if (a[n] == b[n] || (std::isnan(a[n]) && std::isnan(b[n]))) continue;
        if (std::isnan(a[n]) || std::isnan(b[n])) return std::numeric_limits<double>::infinity();
        const double d = std::abs(double(a[n]) - double(b[n])) / ulp_of(std::max({std::abs(a[n]), std::abs(b[n]), scale}));
        worst = std::max(worst, d);
    }
    return worst;
}

template <class Real>
double max_abs_difference(const std::vector<Real>& a, const std::vector<Real>& b) {
    double worst = 0;
    for (std::size_t n = 0; n < a.size(); ++n) {
        const double d = std::abs(double(a[n]) - double(b[n]));
        if (!(d <= worst)) worst = d;  // NaN propagates
    }
    return worst;
}

}  // namespace snvr::testing
