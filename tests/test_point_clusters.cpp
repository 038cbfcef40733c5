// The piece count the points suggest, used to warn when a shell breaks apart.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "geometry/point_clusters.hpp"
#include "geometry/point_tree.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/shapes.hpp"
#include "with_threads.hpp"

using namespace snvr;

TEST_CASE("clusters of points linked below a distance") {
    PointSet points = shapes::sphere({0, 0, 0}, 1.0, 0.05);
    const PointSet other = shapes::sphere({3, 0, 0}, 0.5, 0.05);
    points.insert(points.end(), other.begin(), other.end());
    CHECK(count_point_clusters(points, 0.2) == 2);   // two separate spheres
    CHECK(count_point_clusters(points, 2.0) == 1);   // linked across the 1.5 gap
    CHECK(count_point_clusters(points, 1e-6) == points.size());  // nothing linked
    CHECK(count_point_clusters(PointSet{}, 1.0) == 0);
}

namespace {

// Every pair looked at: the clusters by definition.
std::size_t clusters_brute_force(const PointSet& points, double link) {
    std::vector<std::size_t> parent(points.size());
    std::iota(parent.begin(), parent.end(), std::size_t(0));
    const auto root = [&](std::size_t n) {
        while (parent[n] != n) n = parent[n];
        return n;
    };
    for (std::size_t i = 0; i < points.size(); ++i)
        for (std::size_t j = i + 1; j < points.size(); ++j) {
            const double dx = points[i][0] - points[j][0], dy = points[i][1] - points[j][1],
                         dz = points[i][2] - points[j][2];
            if (dx * dx + dy * dy + dz * dz < link * link) {
                const std::size_t a = root(i), b = root(j);
                if (a != b) parent[std::max(a, b)] = std::min(a, b);
            }
        }
    std::size_t roots = 0;
    for (std::size_t k = 0; k < points.size(); ++k) roots += root(k) == k;
    return roots;
}

// Blobs of very different density in a box (every dense_every-th of them `dense` points,
// the others `sparse`), some touching at about a link, then `loose` points anywhere.
PointSet blobs(unsigned seed, const Vec3& box, double widest, int count, int dense_every, int dense, int sparse,
               int loose) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0, 1);
    PointSet points;
    for (int blob = 0; blob < count; ++blob) {
        const Vec3 centre{unit(rng) * box[0], unit(rng) * box[1], unit(rng) * box[2]};
        const double radius = 0.05 + widest * unit(rng);
        for (int k = 0, n = blob % dense_every == 0 ? dense : sparse; k < n; ++k)
            points.push_back({centre[0] + radius * (2 * unit(rng) - 1), centre[1] + radius * (2 * unit(rng) - 1),
                              centre[2] + radius * (2 * unit(rng) - 1)});
    }
    for (int k = 0; k < loose; ++k) points.push_back({unit(rng) * box[0], unit(rng) * box[1], unit(rng) * box[2]});
    return points;
}

}  // namespace

TEST_CASE("clusters: the same count as every pair looked at, dense, sparse and in between") {
    PointSet points = blobs(7, {4, 4, 1}, 0.3, 12, 3, 600, 40, 100);
    // Points exactly a link apart are not linked; a hair closer, they are.
    points.push_back({10, 10, 10});
    points.push_back({10.25, 10, 10});
    points.push_back({10, 10.2499, 10});
    // Counted on the points as the library holds them (float).
    const PointSet held = PointCloud(points).to_point_set();
    for (double link : {0.001, 0.02, 0.05, 0.1, 0.25, 0.4, 0.8, 1.5}) {
        CAPTURE(link);
        CHECK(count_point_clusters(points, link) == clusters_brute_force(held, link));
    }
}

TEST_CASE("cluster_roots: each point's cluster as its first member, on one thread or two") {
    // Enough points for the threads to share the linking (over 2^16), in clusters of
    // different density, some a hair more or less than a link apart.
    const PointCloud cloud(blobs(11, {6, 6, 2}, 0.25, 40, 4, 8000, 800, 3000));
    const detail::PointTree& t = detail::tree_of(cloud);
    REQUIRE(t.size() > (1u << 16));
    for (double link : {0.004, 0.02, 0.06, 0.3}) {
        CAPTURE(link);
        // The clusters by a search from each point not yet reached, labelled by their
        // first member.
        std::vector<std::uint32_t> label(t.size(), detail::PointTree::npos);
        for (std::uint32_t s = 0; s < t.size(); ++s) {
            if (label[s] != detail::PointTree::npos) continue;
            std::vector<std::uint32_t> todo{s};
            label[s] = s;
            while (!todo.empty()) {
                const std::uint32_t k = todo.back();
                todo.pop_back();
                t.for_each_within(t.point(k), link * link, [&](std::uint32_t j) {
                    if (label[j] == detail::PointTree::npos) label[j] = s, todo.push_back(j);
                });
            }
        }
        for (int threads : {1, 2}) {
            const detail::PointArray<std::uint32_t> roots =
                snvr::testing::with_threads(threads, [&] { return detail::cluster_roots(t, link); });
            std::size_t wrong = 0;
            for (std::size_t k = 0; k < t.size(); ++k) wrong += roots[k] != label[k];
            CHECK(wrong == 0);
        }
    }
}
