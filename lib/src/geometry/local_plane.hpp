// The plane that fits a point's neighbours best (least squares): for the stray points
// (a point standing off it) and the sampling's holes (its neighbours seen in it).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "geometry/point_tree.hpp"
#include "snvr/geometry.hpp"

namespace snvr::detail {

// The plane through the mean of the points d (about the point asked about) whose `use`
// is set, with the least scatter: its unit normal, the mean, and the RMS distance of the
// points from it.
struct Plane {
    Vec3 normal{0, 0, 1}, mean{0, 0, 0};
    double scatter = 0;
};
Plane fit_plane(const std::vector<Vec3>& d, const std::vector<std::uint8_t>& use);

// Two unit axes e1, e2 in the plane of unit normal n (e1 x e2 = n).
void plane_axes(const Vec3& n, Vec3& e1, Vec3& e2);

// Point k's nearest `neighbours` others seen from it: the plane of the nearest `plane_of`
// of them, its axes, and those no steeper off it than asin(off_plane) (others belong to
// another part of the surface) as (u, v, height above the plane). With `refits`, the plane
// is fitted again (so many times at most) to all the neighbours that stand near it.
// Where none of them lies farther than `within_only`, nothing is given (no distances).
struct LocalPatch {
    Vec3 e1{0, 0, 0}, e2{0, 0, 0}, normal{0, 0, 1};
    std::vector<std::array<double, 3>> uvw;  // nearest first; the point itself is not among them
    std::vector<double> distance;            // to each neighbour found, near the plane or not, nearest first
};
LocalPatch local_patch(const PointTree& tree, std::uint32_t k, std::size_t neighbours, std::size_t plane_of,
                       double off_plane, int refits = 0, double within_only = -1);

// The height field w = a u^2 + b u v + c v^2 + d u + e v + f over a point's plane that fits
// its neighbours (u, v, w) best (least squares): the surface they lie on, curved, to
// second order.
struct Quadric {
    double coef[6] = {0, 0, 0, 0, 0, 0};
    double at(double u, double v) const {
        return coef[0] * u * u + coef[1] * u * v + coef[2] * v * v + coef[3] * u + coef[4] * v + coef[5];
    }
};
// False where the points do not determine one (fewer than 6, or all on a line or conic).
bool fit_quadric(const std::vector<std::array<double, 3>>& uvw, Quadric& quadric);

}  // namespace snvr::detail
