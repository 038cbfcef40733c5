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
#include "parallel_sizes.hpp"

namespace snvr {
namespace {

constexpr std::size_t kNeighbours = 20;
constexpr std::size_t kPlaneNeighbours = 8;  // the plane first of the nearest few: one sheet
constexpr std::size_t kReachNeighbour = 6;  // the disc sampled: half the distance to this one
constexpr double kOffPlane = 0.5;            // sin of the steepest a neighbour stands off the plane (30 degrees)

using detail::Flat;

void upsample_at(const detail::PointTree& tree, std::uint32_t k, double spacing, PointSet& out) {
    const Vec3 p = tree.point(k);
    const detail::LocalPatch patch = detail::local_patch(tree, k, kNeighbours, kPlaneNeighbours, kOffPlane, 2);
    if (patch.distance.size() < 12) return;
    const double reach = patch.distance[kReachNeighbour - 1];
    const Vec3 &e1 = patch.e1, &e2 = patch.e2, &normal = patch.normal;
    // The neighbours in the plane (u, v) and their heights w, the point itself at 0.
    std::vector<std::array<double, 3>> uvw{{0, 0, 0}};
    uvw.insert(uvw.end(), patch.uvw.begin(), patch.uvw.end());
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
    return upsample_surface(tree, spacing, 0, tree.size());
}

PointSet upsample_surface(const detail::PointTree& tree, double spacing, std::size_t begin, std::size_t end) {
    end = std::min(end, tree.size());
    begin = std::min(begin, end);
    std::vector<PointSet> at(end - begin);
    const std::ptrdiff_t n = std::ptrdiff_t(at.size());
#pragma omp parallel for schedule(dynamic, 64) if (n >= detail::kParallelCostlyItems)
    for (std::ptrdiff_t k = 0; k < n; ++k) upsample_at(tree, std::uint32_t(begin + std::size_t(k)), spacing, at[std::size_t(k)]);
    PointSet out;
    for (const PointSet& s : at) out.insert(out.end(), s.begin(), s.end());
    return out;
}

}  // namespace snvr
