// upsample_surface (surface_upsampling.hpp): a least-squares quadric over each point's
// neighbours in their plane, sampled on a triangular grid.
#include "geometry/surface_upsampling.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "geometry/flat_hull.hpp"
#include "geometry/local_plane.hpp"
#include "geometry/vec3_math.hpp"
#include "parallel_sizes.hpp"

namespace snvr {
namespace {

constexpr std::size_t kNeighbours = 20;
constexpr std::size_t kReachNeighbour = 6;  // the disc sampled: half the distance to this one

using detail::Flat;

void upsample_at(const detail::PointTree& tree, std::uint32_t k, double spacing, PointSet& out) {
    const Vec3 p = tree.point(k);
    std::vector<Vec3> d;
    double reach = 0;
    for (const auto& at : tree.nearest_points(p, kNeighbours + 1))
        if (at.dist_sq > 0) {
            d.push_back(sub(tree.point(at.index), p));
            if (d.size() == kReachNeighbour) reach = std::sqrt(at.dist_sq);
        }
    if (d.size() < 12) return;
    const Vec3 normal = detail::fit_plane(d, std::vector<std::uint8_t>(d.size(), 1)).normal;
    Vec3 e1, e2;
    detail::plane_axes(normal, e1, e2);
    // The neighbours in the plane (u, v) and their heights w, the point itself at 0.
    std::vector<std::array<double, 3>> uvw{{0, 0, 0}};
    for (const Vec3& v : d)
        if (2 * std::fabs(dot(v, normal)) <= norm(v)) uvw.push_back({dot(v, e1), dot(v, e2), dot(v, normal)});
    if (uvw.size() < 12) return;
    detail::Quadric surface;
    if (!detail::fit_quadric(uvw, surface)) return;
    std::vector<Flat> flat;
    for (const auto& q : uvw) flat.push_back({q[0], q[1]});
    const std::vector<Flat> hull = detail::convex_hull(std::move(flat));
    const double radius = 0.5 * reach;
    const double row = spacing * std::sqrt(3.0) / 2;
    const int rows = int(std::ceil(radius / row));
    for (int j = -rows; j <= rows; ++j)
        for (int i = -int(std::ceil(radius / spacing)) - 1; i <= int(std::ceil(radius / spacing)) + 1; ++i) {
            const Flat c{(i + 0.5 * (j & 1)) * spacing, j * row};
            if (c[0] * c[0] + c[1] * c[1] > radius * radius || (i == 0 && j == 0) || !detail::strictly_inside(hull, c)) continue;
            const double w = surface.at(c[0], c[1]);
            Vec3 q;
            for (int a = 0; a < 3; ++a) q[a] = p[a] + c[0] * e1[a] + c[1] * e2[a] + w * normal[a];
            out.push_back(q);
        }
}

}  // namespace

PointSet upsample_surface(const detail::PointTree& tree, double spacing) {
    std::vector<PointSet> at(tree.size());
    const std::ptrdiff_t n = std::ptrdiff_t(tree.size());
#pragma omp parallel for schedule(dynamic, 64) if (n >= detail::kParallelCostlyItems)
    for (std::ptrdiff_t k = 0; k < n; ++k) upsample_at(tree, std::uint32_t(k), spacing, at[std::size_t(k)]);
    PointSet out;
    for (const PointSet& s : at) out.insert(out.end(), s.begin(), s.end());
    return out;
}

}  // namespace snvr
