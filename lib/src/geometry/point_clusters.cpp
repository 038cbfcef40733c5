// How many pieces the points themselves suggest: a shell of offset l joins points
// closer than 2l, so clusters linked at that distance bound the pieces a correct
// result can have (two sheets per closed piece, one per open piece).
#include <numeric>
#include <vector>

#include "geometry/point_index.hpp"
#include "snvr/reconstruct.hpp"

namespace snvr {

namespace {

std::size_t find_root(std::vector<std::size_t>& parent, std::size_t n) {
    while (parent[n] != n) n = parent[n] = parent[parent[n]];
    return n;
}

}  // namespace

std::size_t count_point_clusters(const PointSet& points, double link_distance) {
    if (points.empty()) return 0;
    const PointIndex index(points);
    std::vector<std::size_t> parent(points.size());
    std::iota(parent.begin(), parent.end(), std::size_t(0));
    for (std::size_t n = 0; n < points.size(); ++n)
        index.for_each_within(points[n], link_distance, [&](std::size_t m) {
            const std::size_t a = find_root(parent, n), b = find_root(parent, m);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
        });
    std::size_t roots = 0;
    for (std::size_t n = 0; n < points.size(); ++n) roots += find_root(parent, n) == n;
    return roots;
}

}  // namespace snvr
