// Points seen in a plane (a point's neighbours in their local plane): the convex hull and
// whether a point lies strictly inside it. For the sampling's holes and the upsampling.
#pragma once
#include <algorithm>
#include <array>
#include <vector>

namespace snvr::detail {

using Flat = std::array<double, 2>;

// Twice the signed area of o, a, b: above 0 where they turn counter-clockwise.
inline double turn(const Flat& o, const Flat& a, const Flat& b) {
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

// The convex hull of the points, counter-clockwise (Andrew's monotone chain).
inline std::vector<Flat> convex_hull(std::vector<Flat> p) {
    std::sort(p.begin(), p.end());
    if (p.size() < 3) return p;
    std::vector<Flat> hull(2 * p.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {  // lower chain
        while (k >= 2 && turn(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
        hull[k++] = p[i];
    }
    for (std::size_t i = p.size() - 1, lower = k + 1; i-- > 0;) {  // upper chain
        while (k >= lower && turn(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
        hull[k++] = p[i];
    }
    hull.resize(k - 1);
    return hull;
}

inline bool strictly_inside(const std::vector<Flat>& hull, const Flat& c) {
    if (hull.size() < 3) return false;
    for (std::size_t i = 0; i < hull.size(); ++i)
        if (!(turn(hull[i], hull[(i + 1) % hull.size()], c) > 0)) return false;
    return true;
}

}  // namespace snvr::detail
