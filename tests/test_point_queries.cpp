// The point tree's per-cell queries against brute force over every point: eight queries
// in lanes (nearest_lanes), the neighbour counts of the outlier rules
// (points_short_of), and the stray points' rule on shapes made for it.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "geometry/neighbour_counts.hpp"
#include "geometry/point_samples.hpp"
#include "geometry/point_tree.hpp"
#include "geometry/stray_points.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/shapes.hpp"

using namespace snvr;
using detail::PointTree;

namespace {

struct Cloud {
    const char* what;
    PointSet points;
};

// Clouds where cells and lanes could go wrong: scattered, tight clusters, many copies
// of one point, every point in one cell, a surface far denser than the queries, far
// from the origin.
std::vector<Cloud> awkward_clouds() {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> unit(0, 1);
    std::normal_distribution<double> gauss(0, 1);
    std::vector<Cloud> out;
    PointSet scattered;
    for (int i = 0; i < 3000; ++i) scattered.push_back({unit(rng), unit(rng), unit(rng)});
    out.push_back({"scattered", scattered});
    PointSet clusters;
    for (int c = 0; c < 20; ++c) {
        const Vec3 m{unit(rng), unit(rng), unit(rng)};
        for (int i = 0; i < 200; ++i)
            clusters.push_back({m[0] + 1e-4 * gauss(rng), m[1] + 1e-4 * gauss(rng), m[2] + 1e-4 * gauss(rng)});
        for (int i = 0; i < 50; ++i) clusters.push_back(m);
    }
    out.push_back({"tight clusters with exact duplicates", clusters});
    PointSet copies(200000, Vec3{0.3, 0.6, 0.2});
    for (int i = 0; i < 20; ++i) copies.push_back({unit(rng), unit(rng), unit(rng)});
    out.push_back({"200000 copies of one point and 20 others", copies});
    PointSet one_cell;
    for (int i = 0; i < 2000; ++i) one_cell.push_back({0.5 + 1e-7 * unit(rng), 0.5 + 1e-7 * unit(rng), 0.5});
    out.push_back({"2000 points within 1e-7 of each other", one_cell});
    out.push_back({"a dense sphere", shapes::sphere({0.5, 0.5, 0.5}, 0.3, 0.004)});
    PointSet far = shapes::sphere({0.5, 0.5, 0.5}, 0.3, 0.01);
    for (Vec3& p : far) p = {p[0] + 1e6, p[1] - 3e6, p[2] + 2e5};
    out.push_back({"a sphere 3 million units from the origin", far});
    return out;
}

double brute_nearest_sq(const PointTree& t, const Vec3& q, double bound) {
    double best = bound;
    for (std::size_t k = 0; k < t.size(); ++k) best = std::min(best, PointTree::dist_sq(q, t.point(k)));
    return best;
}

// Faults of a tree's shape over `count` points: each node reached once, from its parent,
// its children after it, side by side, splitting its range in order; each point in its
// node's box, the boxes tight; each point in one leaf; a leaf of more than kLeafSize only
// where its points share one finest cell (`leaf_rule`). 0 when none.
std::size_t tree_faults(const PointTree& t, std::size_t count, bool leaf_rule) {
    std::vector<std::uint8_t> seen(count, 0);
    std::size_t bad = 0;
    std::vector<std::uint32_t> reached(t.nodes.size(), 0);
    reached[0] = 1;
    for (std::size_t i = 0; i < t.nodes.size(); ++i) {
        const PointTree::Node& n = t.nodes[i];
        bad += reached[i] != 1 || n.begin >= n.end;
        Vec3f lo = t.xyz[n.begin], hi = lo;
        for (std::uint32_t k = n.begin; k < n.end; ++k)
            for (int a = 0; a < 3; ++a) {
                bad += t.xyz[k][a] < n.lo[a] || t.xyz[k][a] > n.hi[a];
                lo[a] = std::min(lo[a], t.xyz[k][a]);
                hi[a] = std::max(hi[a], t.xyz[k][a]);
            }
        bad += lo != n.lo || hi != n.hi;
        if (n.leaf()) {
            // More points only when they share one finest cell (2^-21 of the box).
            const PointTree::Node& root = t.nodes[0];
            float span = 0, cell = 0;
            for (int a = 0; a < 3; ++a) {
                span = std::max(span, n.hi[a] - n.lo[a]);
                cell = std::max(cell, (root.hi[a] - root.lo[a]) * 0x1p-20f);
            }
            bad += leaf_rule && n.count() > PointTree::kLeafSize && span > cell;
            for (std::uint32_t k = n.begin; k < n.end; ++k) bad += seen[k]++ != 0;
            continue;
        }
        std::uint32_t at = n.begin;
        for (std::uint32_t c = 0; c < n.children; ++c) {
            const PointTree::Node& kid = t.nodes[n.child + c];
            bad += n.child + c <= i || kid.begin != at;
            at = kid.end;
            ++reached[n.child + c];
        }
        bad += at != n.end;
    }
    bad += std::size_t(std::count(seen.begin(), seen.end(), 0));
    return bad;
}

PointSet noisy_dense_sphere() {
    PointSet dense = shapes::sphere({0.5, 0.5, 0.5}, 0.3, 0.0015);
    std::mt19937 rng(11);
    std::normal_distribution<double> gauss(0.0, 1e-3);
    for (Vec3& p : dense)
        for (double& x : p) x += gauss(rng);
    return dense;
}

}  // namespace

TEST_CASE("PointTree: the nodes split their points in order and hold them in their boxes, threaded build included") {
    // Past 2^16 points the tree's lower levels are built by tasks and copied into place.
    const PointSet dense = noisy_dense_sphere();
    REQUIRE(dense.size() > (std::size_t(1) << 17));
    for (const PointSet& points : {dense, awkward_clouds()[2].points}) {
        const PointCloud cloud(points);
        const PointTree& t = detail::tree_of(cloud);
        REQUIRE(t.size() == points.size());
        CHECK(tree_faults(t, points.size(), true) == 0);
        std::size_t leaves = 0;
        for (const PointTree::Node& n : t.nodes) leaves += n.leaf();
        CHECK(leaves > 0);
        // Each point where the input had it, in float about the origin.
        std::size_t moved = 0;
        for (std::size_t k = 0; k < t.size(); ++k)
            for (int a = 0; a < 3; ++a) moved += std::abs(t.point(k)[a] - points[t.input[k]][a]) > 1e-6;
        CHECK(moved == 0);
    }
}

TEST_CASE("PointCloud::keep prunes the tree: its shape sound, its boxes tight, its queries brute force's") {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> unit(0, 1);
    for (const double drop : {0.001, 0.1, 0.6, 0.9999}) {
        CAPTURE(drop);
        const PointSet points = noisy_dense_sphere();
        PointCloud cloud(points);
        std::vector<std::uint8_t> flags(cloud.size());
        std::size_t kept = 0;
        for (std::uint8_t& f : flags) kept += f = unit(rng) >= drop;
        const std::vector<std::uint32_t> inputs_before(detail::tree_of(cloud).input.begin(), detail::tree_of(cloud).input.end());
        cloud.keep(flags);
        const PointTree& t = detail::tree_of(cloud);
        REQUIRE(t.size() == kept);
        CHECK(tree_faults(t, kept, false) == 0);
        // The points kept, in their order, each with its input place.
        std::size_t at = 0, wrong = 0;
        for (std::size_t k = 0; k < flags.size(); ++k)
            if (flags[k]) wrong += t.input[at++] != inputs_before[k];
        CHECK(wrong == 0);
        for (int q = 0; q < 200; ++q) {
            const Vec3 p{unit(rng), unit(rng), unit(rng)};
            const PointTree::Hit hit = t.nearest(p);
            CHECK(hit.dist_sq == brute_nearest_sq(t, p, std::numeric_limits<double>::infinity()));
            std::size_t within = 0, brute = 0;
            t.for_each_within(p, 0.01, [&](std::uint32_t) { ++within; });
            for (std::size_t k = 0; k < t.size(); ++k) brute += PointTree::dist_sq(p, t.point(k)) < 0.01;
            CHECK(within == brute);
        }
    }
}

TEST_CASE("points taken from a tree in its order and filed in its frame: the tree the sort makes, without sorting") {
    const PointCloud whole(noisy_dense_sphere());
    const PointTree& a = detail::tree_of(whole);
    // Every other leaf's points, in the tree's order (as a process is given its tiles').
    detail::PointArray<Vec3f> part;
    bool take = true;
    a.for_each_leaf([](const PointTree::Node&) { return true; }, [&](const PointTree::Node& leaf) {
        if (take) part.insert(part.end(), a.xyz.begin() + leaf.begin, a.xyz.begin() + leaf.end);
        take = !take;
    });
    const PointTree in_frame(part, {}, a.origin, &a.frame());
    detail::PointArray<Vec3f> shuffled = part;
    std::reverse(shuffled.begin(), shuffled.end());
    const PointTree reversed(shuffled, {}, a.origin, &a.frame());  // out of order: sorted as usual
    REQUIRE(in_frame.size() == part.size());
    CHECK(tree_faults(in_frame, part.size(), true) == 0);
    CHECK(tree_faults(reversed, part.size(), true) == 0);
    std::size_t moved = 0;
    for (std::size_t k = 0; k < part.size(); ++k) moved += in_frame.xyz[k] != part[k] || in_frame.input[k] != k;
    CHECK(moved == 0);
    // The same points, nodes and boxes as the sort makes of them in that frame.
    REQUIRE(reversed.nodes.size() == in_frame.nodes.size());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < in_frame.nodes.size(); ++i) {
        const PointTree::Node &x = in_frame.nodes[i], &y = reversed.nodes[i];
        differ += x.begin != y.begin || x.end != y.end || x.child != y.child || x.children != y.children || x.lo != y.lo || x.hi != y.hi;
    }
    CHECK(differ == 0);
    for (std::size_t k = 0; k < part.size(); ++k) differ += reversed.xyz[k] != in_frame.xyz[k];
    CHECK(differ == 0);
}

TEST_CASE("nearest_lanes: eight queries at once give nearest()'s distances, and brute force's") {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> unit(0, 1);
    for (const Cloud& c : awkward_clouds()) {
        CAPTURE(c.what);
        const PointCloud cloud(c.points);
        const PointTree& t = detail::tree_of(cloud);
        const auto box = cloud.box();
        const double span = std::max({box[1][0] - box[0][0], box[1][1] - box[0][1], box[1][2] - box[0][2], 1e-6});
        std::size_t mismatches = 0, brute_mismatches = 0, found = 0;
        for (int packet = 0; packet < 300; ++packet) {
            // A 2x2x2 block of cells somewhere about the cloud, at a random cell size.
            const double h = span * std::pow(10.0, -3 * unit(rng));
            Vec3 corner;
            for (int a = 0; a < 3; ++a) corner[a] = box[0][a] + (1.4 * unit(rng) - 0.2) * span;
            double q[3][PointTree::kLanes], best[PointTree::kLanes];
            std::uint32_t index[PointTree::kLanes];
            const double bound = packet % 3 == 0 ? std::numeric_limits<double>::infinity() : std::pow(span * unit(rng), 2);
            for (int lane = 0; lane < PointTree::kLanes; ++lane) {
                for (int a = 0; a < 3; ++a) q[a][lane] = corner[a] + ((lane >> a) & 1) * h;
                best[lane] = bound;
                index[lane] = PointTree::npos;
            }
            t.nearest_lanes(q, best, index);
            for (int lane = 0; lane < PointTree::kLanes; ++lane) {
                const Vec3 at{q[0][lane], q[1][lane], q[2][lane]};
                const PointTree::Hit hit = t.nearest(at, bound);
                mismatches += hit.index == PointTree::npos ? index[lane] != PointTree::npos
                                                           : best[lane] != hit.dist_sq || index[lane] == PointTree::npos;
                if (index[lane] != PointTree::npos) {
                    ++found;
                    mismatches += PointTree::dist_sq(at, t.point(index[lane])) != best[lane];
                }
                if (packet < 40) brute_mismatches += brute_nearest_sq(t, at, bound) != (index[lane] == PointTree::npos ? bound : best[lane]);
            }
        }
        CHECK(found > 0);
        CHECK(mismatches == 0);
        CHECK(brute_mismatches == 0);
    }
}

TEST_CASE("points_short_of: the cells' counts are the tree's, and brute force's") {
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> unit(0, 1);
    for (const Cloud& c : awkward_clouds()) {
        CAPTURE(c.what);
        const PointCloud cloud(c.points);
        const PointTree& t = detail::tree_of(cloud);
        const bool brute = t.size() <= 20000;
        for (double radius : {1e-9, 1e-4, 0.003, 0.02, 0.2}) {
            for (std::size_t need : {std::size_t(1), std::size_t(4), std::size_t(9), std::size_t(60)}) {
                CAPTURE(radius);
                CAPTURE(need);
                const double r2 = radius * radius;
                const std::vector<std::uint8_t> got = detail::points_short_of(t, r2, need);
                REQUIRE(got.size() == t.size());
                std::size_t wrong = 0, brute_wrong = 0;
                for (std::size_t k = 0; k < t.size(); k += brute ? 1 : 97) {
                    wrong += got[k] != (t.count_within(t.point(k), r2, need) < need);
                    if (brute && k % 7 == 0) {
                        std::size_t near = 0;
                        for (std::size_t j = 0; j < t.size(); ++j) near += PointTree::dist_sq(t.point(k), t.point(j)) <= r2;
                        brute_wrong += got[k] != (near < need);
                    }
                }
                CHECK(wrong == 0);
                CHECK(brute_wrong == 0);
            }
        }
    }
}

namespace {

// A flat square of points `spacing` apart (jittered by `noise` of it across the plane),
// in z = 0.5.
PointSet square(double spacing, double noise, std::uint64_t seed) {
    std::mt19937 rng{static_cast<unsigned>(seed)};
    std::normal_distribution<double> gauss(0, 1);
    PointSet out;
    for (double x = 0.2; x < 0.8; x += spacing)
        for (double y = 0.2; y < 0.8; y += spacing)
            out.push_back({x + 0.2 * spacing * gauss(rng), y + 0.2 * spacing * gauss(rng), 0.5 + noise * spacing * gauss(rng)});
    return out;
}

std::size_t strays_in(const PointSet& points, const std::vector<std::size_t>& of, std::size_t* others = nullptr) {
    const PointCloud cloud(points);
    const std::vector<std::uint8_t> stray = detail::stray_points(detail::tree_of(cloud));
    std::size_t hit = 0, rest = 0;
    for (std::size_t k = 0; k < stray.size(); ++k) {
        if (!stray[k]) continue;
        const std::size_t input = cloud.input_index(k);
        if (std::find(of.begin(), of.end(), input) != of.end()) ++hit;
        else ++rest;
    }
    if (others) *others = rest;
    return hit;
}

}  // namespace

TEST_CASE("stray points: one or two points above a flat surface go, a small feature and the surface stay") {
    const double s = 0.01;
    // A scan's own scatter (a fifth of the spacing across the surface) loses nothing.
    std::size_t others = 0;
    CHECK(strays_in(square(s, 0.2, 4), {}, &others) == 0);
    CHECK(others == 0);
    // Over a surface that flat (to a hundredth of their height) strays go; over the
    // scatter of a scan they stay (a real scan's points 10-60 times their neighbours'
    // scatter off it are not told from strays, and lose nothing: the rule's price).
    PointSet plane = square(s, 0.0, 3);
    const std::size_t n = plane.size();
    CHECK(strays_in(plane, {}, &others) == 0);
    CHECK(others == 0);
    // One point 2 and one 4 spacings off it, far apart: both go, nothing else.
    PointSet two = plane;
    two.push_back({0.35, 0.35, 0.5 + 2 * s});
    two.push_back({0.65, 0.6, 0.5 - 4 * s});
    CHECK(strays_in(two, {n, n + 1}, &others) == 2);
    CHECK(others == 0);
    // A pair of strays 1.5 spacings apart: both go.
    PointSet pair = plane;
    pair.push_back({0.5, 0.5, 0.5 + 3 * s});
    pair.push_back({0.5 + 1.5 * s, 0.5, 0.5 + 3 * s});
    CHECK(strays_in(pair, {n, n + 1}, &others) == 2);
    CHECK(others == 0);
    // Three points together above it: a small feature, kept.
    PointSet trio = plane;
    trio.push_back({0.5, 0.5, 0.5 + 3 * s});
    trio.push_back({0.5 + 1.2 * s, 0.5, 0.5 + 3 * s});
    trio.push_back({0.5, 0.5 + 1.2 * s, 0.5 + 3.2 * s});
    CHECK(strays_in(trio, {n, n + 1, n + 2}, &others) == 0);
    CHECK(others == 0);
    // Edges, corners, thin and sparse parts have no flat neighbourhood to stand off.
    for (const char* shape : {"cube", "cone", "cylinder", "sheets", "mobius", "helicoid", "varying-sphere", "lidar"}) {
        CAPTURE(shape);
        std::size_t others = 0;
        CHECK(strays_in(shapes::by_name(shape, 0.01), {}, &others) == 0);
        CHECK(others == 0);
    }
}

TEST_CASE("strided_sample: the points of ranks floor(s n / samples) by input index, whatever the tree's order") {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> unit(0, 1);
    std::uniform_int_distribution<std::uint32_t> step(1, 200);
    for (const int gaps : {0, 1, 2})  // none, even (as after dropped points), uneven (whole words empty)
        for (const std::size_t n : {1, 7, 1000, 54321}) {
            detail::PointArray<Vec3f> xyz(n);
            detail::PointArray<std::uint32_t> input(n);
            std::uint32_t next = 0;
            for (std::size_t i = 0; i < n; ++i) {
                xyz[i] = {unit(rng), unit(rng), unit(rng)};
                input[i] = gaps == 0 ? std::uint32_t(i) : gaps == 1 ? std::uint32_t(3 * i + 1) : (next += step(rng));
            }
            const std::vector<std::uint32_t> by_rank(input.begin(), input.end());  // ascending
            const PointTree t(xyz, input, {0, 0, 0});
            for (const std::size_t samples : {std::size_t(1), std::size_t(3), std::size_t(999), n, n + 5}) {
                CAPTURE(gaps);
                CAPTURE(n);
                CAPTURE(samples);
                const std::vector<std::uint32_t> got = detail::strided_sample(t, samples);
                const std::size_t m = std::min(samples, n);
                REQUIRE(got.size() == m);
                for (std::size_t s = 0; s < m; ++s) CHECK(t.input[got[s]] == by_rank[s * n / m]);
            }
        }
}
