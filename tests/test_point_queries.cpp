// The point tree's per-cell queries against brute force over every point: eight queries
// in lanes (nearest_lanes), the neighbour counts of the outlier rules
// (points_short_of), and the stray points' rule on shapes made for it; the tree filed by
// several processes (threads here) is the one a process files alone.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <functional>
#include <fstream>
#include <iterator>
#include <limits>
#include <mutex>
#include <random>
#include <stdexcept>
#include <thread>
#include <vector>

#include "geometry/neighbour_counts.hpp"
#include "geometry/point_clusters.hpp"
#include "geometry/outliers.hpp"
#include "geometry/point_samples.hpp"
#include "geometry/point_tree.hpp"
#include "geometry/sampling_holes.hpp"
#include "geometry/stray_points.hpp"
#include "mesh/fair_and_keep_deep.hpp"
#include "mesh/guard_search.hpp"
#include "mesh_fields.hpp"
#include "thread_processes.hpp"
#include "pipeline/shared_guard.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/point_io.hpp"
#include "snvr/shapes.hpp"
#include "snvr/tiles.hpp"
#include "solver/ranged_tile_points.hpp"
#include "solver/shared_filing.hpp"
#include "solver/tile_needs.hpp"
#include "solver/tile_plan.hpp"
#include "solver/shared_holes.hpp"
#include "temp_dir.hpp"

using namespace snvr;
using detail::PointTree;
using snvr::testing::TempDir;
using snvr::testing::ThreadProcesses;
using snvr::testing::each_of;

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

// The cloud the first of `processes` files with the others' help (each a thread); then
// `then` on it, the others answering the sparse rule's counts where it asks them.
PointCloud filed_by(int processes, const PointCloud& alone,
                    const std::function<void(PointCloud&, const detail::RuleQuestions&)>& then = {}) {
    const PointTree& t = detail::tree_of(alone);
    detail::PointArray<Vec3f> as_read(t.size());  // in input order, as a reader gives them
    for (std::size_t k = 0; k < t.size(); ++k) as_read[t.input[k]] = t.xyz[k];
    ThreadProcesses all(processes);
    const auto each = each_of(all, processes);
    std::vector<std::thread> others;
    for (int p = 1; p < processes; ++p) others.emplace_back([&each, p] { detail::file_for_root(*each[std::size_t(p)]); });
    PointCloud filed = detail::cloud_filed_with(*each[0], std::move(as_read), t.origin);
    {
        detail::NeighbourCountsShared counts(each[0].get(), filed);
        if (then) then(filed, {counts.short_of(), counts.roots_of(), counts.strays_of()});
    }
    for (std::thread& o : others) o.join();
    return filed;
}

// The cloud the first of `processes` files where each reads its own part of the file.
PointCloud read_in_parts_by(int processes, const std::string& path) {
    ThreadProcesses all(processes);
    const auto each = each_of(all, processes);
    std::vector<std::thread> others;
    for (int p = 1; p < processes; ++p)
        others.emplace_back([&each, &path, p] {
            TileScheduler& mine = *each[std::size_t(p)];
            const std::size_t n = detail::parts_to_read(&mine, path);
            detail::file_part_for_root(mine, detail::read_my_part(mine, path, n, ""), n);
        });
    const std::size_t n = detail::parts_to_read(each[0].get(), path);
    REQUIRE(n > 0);
    PointCloud filed = detail::cloud_read_with(*each[0], detail::read_my_part(*each[0], path, n, ""), n);
    { const detail::NeighbourCountsShared unasked(each[0].get(), filed); }
    for (std::thread& o : others) o.join();
    return filed;
}

// At the first of processes as threads: `points` as a reader gives them, filed with the
// others' help (each in file_for_root meanwhile), the rules asking them nothing.
PointCloud filed_at_first(TileScheduler& first, const PointSet& points) {
    const PointCloud as_given(points);
    const PointTree& t = detail::tree_of(as_given);
    detail::PointArray<Vec3f> as_read(t.size());
    for (std::size_t k = 0; k < t.size(); ++k) as_read[t.input[k]] = t.xyz[k];
    PointCloud filed = detail::cloud_filed_with(first, std::move(as_read), t.origin);
    { const detail::NeighbourCountsShared unasked(&first, filed); }
    return filed;
}

// What a tree holds that another could differ in: 0 when none. The nodes are compared as
// a walk from the root meets them (a node's children in order), not by where the array
// holds them: no query depends on that, and a tree filed by several processes holds
// another's nodes after its own.
std::size_t tree_differences(const PointTree& a, const PointTree& b) {
    std::size_t differ = a.size() != b.size() || a.nodes.size() != b.nodes.size() || a.origin != b.origin ||
                         a.frame().figures() != b.frame().figures();
    if (differ) return differ;
    for (std::size_t k = 0; k < a.size(); ++k) differ += a.xyz[k] != b.xyz[k] || a.input[k] != b.input[k];
    std::vector<std::array<std::uint32_t, 2>> stack;
    if (!a.nodes.empty()) stack.push_back({0, 0});
    std::size_t met = 0;
    while (!stack.empty()) {
        const auto [i, j] = stack.back();
        stack.pop_back();
        ++met;
        const PointTree::Node &x = a.nodes[i], &y = b.nodes[j];
        if (x.begin != y.begin || x.end != y.end || x.children != y.children || x.lo != y.lo || x.hi != y.hi) {
            ++differ;
            continue;
        }
        for (std::uint32_t c = 0; c < x.children; ++c) stack.push_back({x.child + c, y.child + c});
    }
    return differ + (met != a.nodes.size());
}

}  // namespace

TEST_CASE("a cloud from float coordinates about an origin: the points and errors of one from doubles") {
    const Vec3 origin{512345.5, 4012345.25, 101.5};
    std::vector<Vec3f> coordinates;
    PointSet world;
    for (int i = 0; i < 5000; ++i) {
        const Vec3f c{float(i % 17) * 0.25f, float(i % 13) * 0.5f, float(i % 7)};
        coordinates.push_back(c);
        world.push_back({origin[0] + c[0], origin[1] + c[1], origin[2] + c[2]});
    }
    const PointCloud cloud(coordinates, origin);
    REQUIRE(cloud.size() == world.size());
    std::size_t differ = 0;
    for (std::size_t k = 0; k < cloud.size(); ++k) differ += cloud[k] != world[cloud.input_index(k)];
    CHECK(differ == 0);
    coordinates[77][1] = std::numeric_limits<float>::quiet_NaN();
    CHECK_THROWS_AS(PointCloud(coordinates, origin), InputError);
    CHECK_THROWS_AS(PointCloud({{0, 0, 0}}, {0, std::numeric_limits<double>::infinity(), 0}), InputError);
}

TEST_CASE("the points' tree filed by several processes is the one a process files alone, bit for bit") {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> unit(0, 1);
    std::vector<Cloud> clouds = awkward_clouds();
    PointSet many;  // above the least the processes share (kSharedFilingPoints)
    for (int i = 0; i < 150000; ++i) many.push_back({unit(rng), unit(rng), 0.25 * unit(rng)});
    for (int i = 0; i < 30000; ++i) many.push_back({0.7, 0.1, 0.2});  // a cell far fuller than the rest
    clouds.push_back({"150000 scattered points and 30000 copies of one", many});
    clouds.push_back({"a noisy dense sphere", noisy_dense_sphere()});
    for (const Cloud& c : clouds) {
        const PointCloud alone(c.points);
        const PointTree& a = detail::tree_of(alone);
        for (int processes : {2, 3, 4}) {
            CAPTURE(c.what);
            CAPTURE(processes);
            CHECK(tree_differences(a, detail::tree_of(filed_by(processes, alone))) == 0);
        }
    }
}

TEST_CASE("the outlier rules counted by the processes that filed the points: the points they drop alone") {
    // A dense sphere with uniform strays (some of them near the ranges' edges), scaled
    // after filing as make_shell scales to millimetres.
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> unit(-0.2, 1.2);
    PointSet points = noisy_dense_sphere();
    for (int i = 0; i < 3000; ++i) points.push_back({unit(rng), unit(rng), unit(rng)});
    const OutlierSettings settings;
    const auto lengths = [](const PointCloud&) { return detail::RunLengths{0.004, 0.01}; };
    PointCloud alone(points);
    alone.scale(25.4);
    double link = 0;
    std::size_t clusters = 0;
    const auto dropped_alone = detail::remove_outliers(alone, settings, lengths, link, clusters);
    REQUIRE(dropped_alone.size() > 1000);
    for (int processes : {2, 3}) {
        CAPTURE(processes);
        std::vector<std::pair<std::size_t, Vec3>> dropped;
        const PointCloud filed = filed_by(processes, PointCloud(points), [&](PointCloud& cloud, const detail::RuleQuestions& asked) {
            REQUIRE(asked.short_of);
            REQUIRE(asked.roots_of);
            cloud.scale(25.4);
            double l = 0;
            std::size_t c = 0;
            dropped = detail::remove_outliers(cloud, settings, lengths, l, c, asked);
        });
        CHECK(dropped == dropped_alone);
        CHECK(tree_differences(detail::tree_of(alone), detail::tree_of(filed)) == 0);
        // The rule's own answer, at reaches where many points fall short (the strays, the
        // sphere's thinner places), every point's flag.
        PointCloud scaled(points);
        scaled.scale(25.4);
        for (const double reach : {0.02, 0.05}) {
            const double r2 = reach * reach * 25.4 * 25.4;
            const std::vector<std::uint8_t> want = detail::points_short_of(detail::tree_of(scaled), r2, 9);
            std::vector<std::uint8_t> got;
            filed_by(processes, PointCloud(points), [&](PointCloud& cloud, const detail::RuleQuestions& asked) {
                cloud.scale(25.4);
                got = asked.short_of(detail::tree_of(cloud), r2, 9);
            });
            CHECK(std::count(want.begin(), want.end(), 1) > 1000);
            CHECK(got == want);
        }
    }
}

TEST_CASE("the rules' counts asked again after points were dropped: the whole cloud's answer, every flag") {
    // The others drop what the first dropped between two questions (by input index), and
    // answer by their ranges as they are then; sabotaged (the drops not told), the second
    // answer differs.
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> unit(-0.2, 1.2);
    PointSet points = noisy_dense_sphere();
    for (int i = 0; i < 3000; ++i) points.push_back({unit(rng), unit(rng), unit(rng)});
    for (int processes : {2, 3}) {
        CAPTURE(processes);
        filed_by(processes, PointCloud(points), [&](PointCloud& cloud, const detail::RuleQuestions& asked) {
            REQUIRE(asked.short_of);
            const detail::ShortOf& short_of = asked.short_of;
            cloud.scale(25.4);
            const double r2 = 0.02 * 0.02 * 25.4 * 25.4;
            const std::vector<std::uint8_t> first = short_of(detail::tree_of(cloud), r2, 9);
            CHECK(first == detail::points_short_of(detail::tree_of(cloud), r2, 9));
            {  // a copy is this process's alone: what it drops the others keep
                PointCloud copy = cloud;
                copy.keep(std::vector<std::uint8_t>(copy.size(), 0));
            }
            // Drop every fifth point, near every range's edge too: more fall short.
            std::vector<std::uint8_t> keep(cloud.size());
            for (std::size_t k = 0; k < keep.size(); ++k) keep[k] = k % 5 != 0;
            cloud.keep(keep);
            for (const auto& [r, need] : {std::pair<double, std::size_t>{r2, 9}, {r2 / 4, 9}}) {
                const std::vector<std::uint8_t> want = detail::points_short_of(detail::tree_of(cloud), r, need);
                CAPTURE(need);
                CHECK(std::count(want.begin(), want.end(), 1) > 1000);
                CHECK(short_of(detail::tree_of(cloud), r, need) == want);
            }
        });
    }
}

TEST_CASE("the clusters linked by the processes that filed the points: every root a process finds alone") {
    // Each other links its range's own pairs, the first every other pair (across ranges):
    // every root the same, at links where clusters span the ranges' edges and where most
    // points stand apart; again after points were dropped (the ranges as they are then),
    // and on a grid of points whose whole nodes (finer than the link) lie across the
    // ranges' bounds.
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> unit(-0.2, 1.2);
    PointSet sphere = noisy_dense_sphere();
    for (int i = 0; i < 3000; ++i) sphere.push_back({unit(rng), unit(rng), unit(rng)});
    PointSet grid;
    for (int i = 0; i < 60; ++i)
        for (int j = 0; j < 60; ++j)
            for (int k = 0; k < 40; ++k) grid.push_back({0.01 * i, 0.01 * j, 0.01 * k});
    for (const PointSet* points : {&sphere, &grid})
        for (int processes : {2, 3}) {
            CAPTURE(processes);
            CAPTURE(points->size());
            filed_by(processes, PointCloud(*points), [&](PointCloud& cloud, const detail::RuleQuestions& asked) {
                REQUIRE(asked.roots_of);
                cloud.scale(2);
                for (const double link : {0.0, 0.004, 0.012, 0.03, 0.5}) {
                    CAPTURE(link);
                    const detail::PointTree& t = detail::tree_of(cloud);
                    CHECK(asked.roots_of(t, 2 * link) == detail::cluster_roots(t, 2 * link));
                }
                std::vector<std::uint8_t> keep(cloud.size());
                for (std::size_t k = 0; k < keep.size(); ++k) keep[k] = k % 7 != 3;
                cloud.keep(keep);
                const detail::PointTree& t = detail::tree_of(cloud);
                const detail::PointArray<std::uint32_t> alone = detail::cluster_roots(t, 0.025);
                std::size_t roots = 0;
                for (std::uint32_t k = 0; k < alone.size(); ++k) roots += alone[k] == k;
                if (points == &sphere) CHECK(roots > 1000);  // the strays (the grid is one cluster)
                CHECK(asked.roots_of(t, 0.025) == alone);
            });
        }
}

TEST_CASE("the processes' ranges stay after the rules' counts (for the check) and are given up at a drop no one hears") {
    const PointSet points = noisy_dense_sphere();
    for (int processes : {2, 3}) {
        CAPTURE(processes);
        PointCloud filed = filed_by(processes, PointCloud(points));
        const detail::PointTree& t = detail::tree_of(filed);
        REQUIRE(t.shared_ranges.size() == std::size_t(processes) + 1);
        const double n = double(t.size());
        for (int p = 0; p < processes; ++p)  // about equal
            CHECK(double(t.shared_ranges[std::size_t(p) + 1] - t.shared_ranges[std::size_t(p)]) / n ==
                  doctest::Approx(1.0 / processes).epsilon(0.05));
        CHECK(t.shared_ranges.back() == t.size());
        filed.scale(2);
        CHECK(t.scaled_since == std::vector<double>{2});
        std::vector<std::uint8_t> keep(filed.size(), 1);
        filed.keep(keep);
        CHECK(t.shared_ranges.size() == std::size_t(processes) + 1);
        keep[7] = 0;  // the others are not told any more: their ranges are not these points
        filed.keep(keep);
        CHECK(t.shared_ranges.empty());
        CHECK(t.scaled_since.empty());
    }
}

TEST_CASE("a binary PLY read in parts by several processes gives the tree one process reads and files") {
    const TempDir dir("filing");
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> unit(0, 1);
    PointSet points;
    for (int i = 0; i < 120000; ++i) points.push_back({unit(rng), 2 * unit(rng), 0.5 * unit(rng)});
    for (int i = 0; i < 20000; ++i) points.push_back({0.25, 0.5, 0.125});
    // Float32 records (held as they are), and double ones far from the origin after another
    // element's fixed-size items (an origin chosen from the first records; an offset).
    const std::string floats = dir.file("floats.ply"), doubles = dir.file("doubles.ply");
    write_points(points, floats);
    {
        std::ofstream out(doubles, std::ios::binary);
        out << "ply\nformat binary_little_endian 1.0\nelement camera 3\nproperty float a\nproperty uchar b\n"
            << "element vertex " << points.size() << "\nproperty double x\nproperty double y\nproperty double z\n"
            << "property uchar k\nend_header\n";
        const char camera[15] = {};
        out.write(camera, sizeof camera);
        for (const Vec3& p : points) {
            const double xyz[3] = {p[0] + 6.5e5, p[1] - 5.2e6, p[2] + 300};
            out.write(reinterpret_cast<const char*>(xyz), sizeof xyz);
            out.put(7);
        }
    }
    for (const std::string& path : {floats, doubles}) {
        const PointCloud alone = read_point_cloud(path);
        for (int processes : {2, 3}) {
            CAPTURE(path);
            CAPTURE(processes);
            CHECK(tree_differences(detail::tree_of(alone), detail::tree_of(read_in_parts_by(processes, path))) == 0);
        }
    }
    // Files read whole: text, a gzipped PLY, one cut short; and a file one process cannot
    // see (the first then gives it its part).
    write_points(PointSet(points.begin(), points.begin() + 100000), dir.file("text.xyz"));
    CHECK(detail::points_in_parts(dir.file("text.xyz")) == 0);
    CHECK(detail::points_in_parts(floats) == points.size());
    CHECK(detail::points_in_parts(doubles) == points.size());
    {
        std::ifstream in(floats, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        std::ofstream(dir.file("cut.ply"), std::ios::binary) << bytes.substr(0, bytes.size() - 5);
    }
    CHECK(detail::points_in_parts(dir.file("cut.ply")) == 0);
    CHECK(detail::parts_to_read(nullptr, floats) == 0);
    ThreadProcesses two(2);
    ThreadProcesses::One first(two, 0), second(two, 1);
    std::size_t seen = 1;
    std::thread other([&] { seen = detail::parts_to_read(&second, dir.file("absent.ply")); });
    CHECK(detail::parts_to_read(&first, floats) == 0);
    other.join();
    CHECK(seen == 0);
}

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
        const std::vector<Vec3f> xyz_before(detail::tree_of(cloud).xyz.begin(), detail::tree_of(cloud).xyz.end());
        cloud.keep(flags);
        const PointTree& t = detail::tree_of(cloud);
        REQUIRE(t.size() == kept);
        CHECK(tree_faults(t, kept, false) == 0);
        // The points kept, in their order, each with its coordinates and input place.
        std::size_t at = 0, wrong = 0;
        for (std::size_t k = 0; k < flags.size(); ++k)
            if (flags[k]) {
                wrong += t.input[at] != inputs_before[k] || t.xyz[at] != xyz_before[k];
                ++at;
            }
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

TEST_CASE("kth_nearest's points within: for_each_within's at that distance, in its order, from one search") {
    std::mt19937 rng(6);
    for (const Cloud& c : awkward_clouds()) {
        CAPTURE(c.what);
        const PointCloud cloud(c.points);
        const PointTree& t = detail::tree_of(cloud);
        std::uniform_int_distribution<std::size_t> pick(0, t.size() - 1);
        std::vector<PointTree::Neighbour> within;
        std::size_t wrong = 0, asked = 0;
        for (int q = 0; q < 300; ++q) {
            const std::size_t k = pick(rng), kth = std::size_t(1) << (q % 6);  // 1 to 32
            const double alone = t.kth_nearest(k, kth);
            const double reach = t.kth_nearest(k, kth, &within);
            wrong += alone != reach;
            // As the stray rule asks: within the distance squared again, rounded up.
            const double r_sq = std::nextafter(reach * reach, std::numeric_limits<double>::infinity());
            std::vector<std::uint32_t> expected, got;
            t.for_each_within(t.point(k), r_sq, [&](std::uint32_t j) { expected.push_back(j); });
            for (const PointTree::Neighbour& at : within) {
                wrong += at.dist_sq != PointTree::dist_sq(t.point(k), t.point(at.index));
                if (at.dist_sq < r_sq) got.push_back(at.index);
            }
            wrong += got != expected;
            asked += expected.size();
        }
        CHECK(asked >= 300);
        CHECK(wrong == 0);
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

TEST_CASE("stray points whose lonely points the processes that filed them counted: the rule's answer, every flag") {
    // A flat square of 90,000 points (above the least the processes share) and strays two
    // to four spacings off it, near the ranges' edges too.
    const double spacing = 0.002;
    PointSet points = square(spacing, 0.0, 3);
    std::mt19937 rng(8);
    std::uniform_real_distribution<double> across(0.25, 0.75), off(2, 4);
    for (int i = 0; i < 300; ++i)
        points.push_back({across(rng), across(rng), 0.5 + (i % 2 ? 1 : -1) * off(rng) * spacing});
    const std::vector<std::uint8_t> want = detail::stray_points(detail::tree_of(PointCloud(points)));
    CHECK(std::count(want.begin(), want.end(), 1) > 200);
    for (int processes : {2, 3}) {
        CAPTURE(processes);
        std::vector<std::uint8_t> got;
        filed_by(processes, PointCloud(points), [&](PointCloud& cloud, const detail::RuleQuestions& asked) {
            REQUIRE(asked.short_of);
            got = detail::stray_points(detail::tree_of(cloud), {}, asked.short_of);
        });
        CHECK(got == want);
    }
}

TEST_CASE("stray points: the tests told how far they have come, in order, the same flags; a throw from the teller stops them") {
    // Scan lines: half the points are lonely and tested; strays two to four line spacings off.
    std::mt19937 rng(5);
    PointSet points;
    for (double y = 0.2; y < 0.8; y += 0.004)
        for (double x = 0.2; x < 0.8; x += 0.001) points.push_back({x, y, 0.5});
    std::uniform_real_distribution<double> across(0.25, 0.75), off(2, 4);
    for (int i = 0; i < 100; ++i) points.push_back({across(rng), across(rng), 0.5 + off(rng) * 0.004});
    const PointCloud cloud(points);
    const std::vector<std::uint8_t> want = detail::stray_points(detail::tree_of(cloud));
    CHECK(std::count(want.begin(), want.end(), 1) > 50);
    std::vector<std::size_t> told;
    const std::vector<std::uint8_t> got = detail::stray_points(
        detail::tree_of(cloud), {}, nullptr, nullptr, [&](std::size_t done, std::size_t all) {
            CHECK(all == points.size());
            told.push_back(done);
        });
    CHECK(got == want);
    REQUIRE(told.size() == detail::kToldPieces + 1);
    CHECK(told.front() == 0);
    CHECK(told.back() == points.size());
    CHECK(std::is_sorted(told.begin(), told.end()));
    // Stopped after the first piece: no piece more is told.
    std::size_t calls = 0;
    CHECK_THROWS_AS(detail::stray_points(detail::tree_of(cloud), {}, nullptr, nullptr,
                                         [&](std::size_t done, std::size_t) {
                                             ++calls;
                                             if (done > 0) throw Cancelled("stop");
                                         }),
                    Cancelled);
    CHECK(calls == 2);
}

TEST_CASE("stray points tested by the processes that filed them, each its own range's: every flag of one process's") {
    // Scan lines (points 1 mm apart on lines 4 mm apart, as a car's scanner leaves them):
    // half the points are lonely; strays two to four line spacings off, near the ranges'
    // edges too; scaled after the filing, as to millimetres.
    std::mt19937 rng(12);
    std::normal_distribution<double> gauss(0, 1);
    PointSet points;
    for (double y = 0.2; y < 0.8; y += 0.004)
        for (double x = 0.2; x < 0.8; x += 0.001) points.push_back({x + 0.1e-3 * gauss(rng), y, 0.5 + 0.05e-3 * gauss(rng)});
    std::uniform_real_distribution<double> across(0.25, 0.75), off(2, 4);
    for (int i = 0; i < 300; ++i)
        points.push_back({across(rng), across(rng), 0.5 + (i % 2 ? 1 : -1) * off(rng) * 0.004});
    PointCloud alone(points);
    alone.scale(25.4);
    const std::vector<std::uint8_t> want = detail::stray_points(detail::tree_of(alone));
    CHECK(std::count(want.begin(), want.end(), 1) > 200);
    for (int processes : {2, 3}) {
        CAPTURE(processes);
        std::vector<std::uint8_t> got;
        std::size_t lonely_elsewhere = 0, undecided = 0;
        filed_by(processes, PointCloud(points), [&](PointCloud& cloud, const detail::RuleQuestions& asked) {
            REQUIRE(asked.strays_of);
            cloud.scale(25.4);
            const detail::AskStrays counted = [&](const PointTree& t, const detail::StraySettings& s,
                                                  const std::vector<std::uint8_t>& lonely) {
                detail::StraysElsewhere e = asked.strays_of(t, s, lonely);
                lonely_elsewhere = std::size_t(std::count(lonely.begin() + std::ptrdiff_t(e.here_end), lonely.end(), 1));
                const auto collect = e.collect;
                e.collect = [&undecided, collect](std::vector<std::uint8_t>& stray, std::vector<std::uint32_t>& unsure) {
                    collect(stray, unsure);
                    undecided = unsure.size();
                };
                return e;
            };
            got = detail::stray_points(detail::tree_of(cloud), {}, asked.short_of, counted);
        });
        CHECK(got == want);
        // Most of the others' lonely points decided where they are; a few near a range's edge here.
        CHECK(lonely_elsewhere > 20000);
        CHECK(undecided > 0);
        CHECK(undecided * 10 < lonely_elsewhere);
    }
}

namespace {

// hole_centres over `processes` thread processes: the centres, and for each pass whether
// the others were asked and how many holes they found.
struct SharedHoles {
    PointSet centres;
    std::vector<std::size_t> theirs;  // a pass's holes found by the others; none where not asked
    std::vector<bool> asked;
    std::size_t sought = 0;  // the first pass's points the others looked at
};
SharedHoles shared_hole_centres(const PointCloud& cloud, double least, int processes) {
    ThreadProcesses all(processes);
    const auto each = each_of(all, processes);
    std::vector<std::thread> others;
    for (int p = 1; p < processes; ++p) others.emplace_back([&each, p] { holes_for_root(*each[std::size_t(p)]); });
    SharedHoles out;
    const AskHoles shared = holes_shared(*each[0], out.sought);
    const AskHoles counted = [&](const PointTree& t, double at_least, const PointSet& near, double reach,
                                 std::size_t looked_at) {
        HolesElsewhere e = shared(t, at_least, near, reach, looked_at);
        out.asked.push_back(bool(e.collect));
        out.theirs.push_back(0);
        if (!e.collect) return e;
        const auto collect = e.collect;
        const std::size_t pass = out.theirs.size() - 1;
        e.collect = [&out, pass, collect] {
            std::vector<double> got = collect();
            out.theirs[pass] = got.size() / 4;
            return got;
        };
        return e;
    };
    out.centres = hole_centres(cloud, least, counted);
    holes_done(*each[0]);
    for (std::thread& o : others) o.join();
    return out;
}

}  // namespace

TEST_CASE("a sampling's holes found by several processes, each at its run of the points: one process's centres") {
    // A random sampling of a sphere (its holes many and near every run's ends), scaled
    // after filing as to millimetres.
    PointCloud cloud(shapes::random_by_name("sphere", 20000, 7));
    cloud.scale(25.4);
    const double least = 25.4 * 0.006;
    const PointSet want = hole_centres(cloud, least);
    CHECK(want.size() > 100);
    for (int processes : {2, 3}) {
        CAPTURE(processes);
        const SharedHoles got = shared_hole_centres(cloud, least, processes);
        CHECK(got.centres == want);
        REQUIRE(got.asked.size() >= 2);  // a later pass, near the centres added
        CHECK(got.asked[0]);
        CHECK(got.theirs[0] > 50);  // the others' runs held holes
        CHECK(got.asked[1]);        // a random sampling's later pass looks at many points
        CHECK(got.theirs[1] > 0);
        CHECK(got.sought == cloud.size() - cloud.size() / std::size_t(processes));
    }
    // Where no hole is looked for, the others are told and return.
    ThreadProcesses all(2);
    ThreadProcesses::One root(all, 0), other(all, 1);
    std::thread waiting([&other] { holes_for_root(other); });
    holes_done(root);
    waiting.join();
}

TEST_CASE("a later pass that looks at few points is not shared: the others file no cloud for it; the same centres") {
    // A lattice of 90,000 points with four holes punched: the first pass finds them; the
    // second looks only near their centres, a few hundred points.
    PointSet points;
    const std::array<std::array<double, 2>, 4> punched{{{0.7, 0.8}, {1.6, 0.9}, {2.2, 2.3}, {0.9, 2.0}}};
    for (int i = 0; i < 300; ++i)
        for (int j = 0; j < 300; ++j) {
            const double u = 0.01 * i, v = 0.01 * j;
            const auto in_hole = [&](const std::array<double, 2>& c) { return std::hypot(u - c[0], v - c[1]) < 0.03; };
            if (std::none_of(punched.begin(), punched.end(), in_hole)) points.push_back({u, v, 0.3 * u});
        }
    const PointCloud cloud(points);
    const double least = 0.02;
    const PointSet want = hole_centres(cloud, least);
    CHECK(want.size() >= punched.size());  // a hole may take more than one
    const SharedHoles got = shared_hole_centres(cloud, least, 2);
    CHECK(got.centres == want);
    REQUIRE(got.asked.size() >= 2);
    CHECK(got.asked[0]);
    CHECK_FALSE(got.asked[1]);
}

namespace {

// Whether two trees are the same to the last bit: origin, frame, points, inputs, nodes.
bool same_tree(const PointTree& a, const PointTree& b) {
    if (a.origin != b.origin || a.frame().figures() != b.frame().figures() || a.size() != b.size() ||
        a.nodes.size() != b.nodes.size() || a.numbered != b.numbered || a.inputs_dropped != b.inputs_dropped)
        return false;
    for (std::size_t k = 0; k < a.size(); ++k)
        if (a.xyz[k] != b.xyz[k] || a.input[k] != b.input[k]) return false;
    for (std::size_t i = 0; i < a.nodes.size(); ++i) {
        const PointTree::Node &x = a.nodes[i], &y = b.nodes[i];
        if (x.lo != y.lo || x.hi != y.hi || x.begin != y.begin || x.end != y.end || x.child != y.child ||
            x.children != y.children)
            return false;
    }
    return true;
}

}  // namespace

TEST_CASE("cloud_with: the points and more filed as one cloud afresh would file them, to the last bit") {
    std::mt19937 rng(21);
    std::uniform_real_distribution<double> unit(0, 1);
    const auto random_points = [&](std::size_t n, double lo, double hi, const Vec3& at) {
        PointSet p(n);
        for (Vec3& x : p) x = {at[0] + lo + (hi - lo) * unit(rng), at[1] + lo + (hi - lo) * unit(rng), at[2] + lo + (hi - lo) * unit(rng)};
        return p;
    };
    for (const Vec3 at : {Vec3{0, 0, 0}, Vec3{4.5e5, 5.2e6, 310.25}}) {  // survey coordinates: an origin of their own
        CAPTURE(at[1]);
        // The box's corners first (kept through the drops below, so that the box, the
        // origin and the frame stay: the points then keep their order, merged), duplicates:
        // ties in the keys.
        PointSet base;
        for (int c = 0; c < 8; ++c) base.push_back({at[0] + 10.0 * (c & 1), at[1] + 10.0 * (c >> 1 & 1), at[2] + 10.0 * (c >> 2)});
        const PointSet inner = random_points(20000, 0, 10, at);
        base.insert(base.end(), inner.begin(), inner.end());
        for (int i = 0; i < 50; ++i) base.push_back(base[std::size_t(8 + i)]);
        PointCloud cloud(base);
        const auto check = [&](const PointCloud& c, const PointSet& more) {
            PointSet joined = c.to_point_set();
            joined.insert(joined.end(), more.begin(), more.end());
            const PointCloud want(joined);
            const PointCloud got = detail::cloud_with(c, more);
            CHECK(same_tree(detail::tree_of(got), detail::tree_of(want)));
        };
        PointSet inside = random_points(300, 1, 9, at);
        inside.push_back(base[7]);  // on a point
        check(cloud, inside);
        check(cloud, {});
        check(cloud, random_points(40, -3, 13, at));  // beyond the box: another frame
        // After drops (the ranks skip them), and after scaling as to millimetres.
        std::vector<std::uint8_t> keep(cloud.size(), 1);
        for (std::size_t k = 0; k < keep.size(); k += 7) keep[k] = detail::tree_of(cloud).input[k] < 8;
        cloud.keep(keep);
        check(cloud, inside);
        cloud.scale(25.4);
        PointSet scaled = inside;
        for (Vec3& x : scaled) x = {25.4 * x[0], 25.4 * x[1], 25.4 * x[2]};
        check(cloud, scaled);
    }
}

TEST_CASE("strided_sample: the points of ranks floor(s n / samples) by input index, whatever the tree's order, in it") {
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
                CHECK(std::is_sorted(got.begin(), got.end()));  // in the tree's order
                std::vector<std::uint32_t> inputs, want;
                for (std::size_t s = 0; s < m; ++s) {
                    inputs.push_back(t.input[got[s]]);
                    want.push_back(by_rank[s * n / m]);
                }
                std::sort(inputs.begin(), inputs.end());
                CHECK(inputs == want);
            }
        }
}

TEST_CASE("strided_sample on points numbered as they came, after drops: the same ranks, no pass over the indices") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> unit(0, 1);
    for (const std::size_t n : {std::size_t(9), std::size_t(5000), std::size_t(70001)}) {
        detail::PointArray<Vec3f> xyz(n);
        for (std::size_t i = 0; i < n; ++i) xyz[i] = {unit(rng), unit(rng), unit(rng)};
        PointTree t(xyz, {}, {0, 0, 0});
        CHECK(t.numbering_known());
        // Drops in rounds: the first and last inputs, then a few, then most points.
        for (const double share : {0.0, 0.01, 0.3, 0.9}) {
            std::vector<std::uint8_t> keep(t.size(), 1);
            for (std::size_t k = 0; k < t.size(); ++k) {
                const std::uint32_t i = t.input[k];
                keep[k] = !(i == 0 || i + 1 == n || unit(rng) < share);
            }
            if (t.size() > 2) t.keep_only(keep);
            CAPTURE(n);
            CAPTURE(share);
            REQUIRE(t.numbering_known());
            std::vector<std::uint32_t> by_rank(t.input.begin(), t.input.end());
            std::sort(by_rank.begin(), by_rank.end());
            PointTree unknown = t;  // the same points, their numbering forgotten: the passes over them
            unknown.numbered = 0;
            for (const std::size_t samples : {std::size_t(1), std::size_t(4), std::size_t(997), t.size()}) {
                CAPTURE(samples);
                const std::vector<std::uint32_t> got = detail::strided_sample(t, samples);
                CHECK(got == detail::strided_sample(unknown, samples));
                const std::size_t m = std::min(samples, t.size());
                REQUIRE(got.size() == m);
                std::vector<std::uint32_t> inputs, want;
                for (std::size_t s = 0; s < m; ++s) {
                    inputs.push_back(t.input[got[s]]);
                    want.push_back(by_rank[s * t.size() / m]);
                }
                std::sort(inputs.begin(), inputs.end());
                CHECK(inputs == want);
            }
        }
    }
}

TEST_CASE("the depth guard's search shared by the processes that filed the points: the vertices one process moves") {
    // A dense noisy sphere inside a coarse meshed ball a little wider: the flat triangles
    // and the noise bring thousands of points nearer than the depth. In millimetres and
    // moved after the filing, as make_shell's points are; every point kept, and some left
    // out by a `lone` distance (the others search those too; the first keeps them out).
    const PointSet points = noisy_dense_sphere();
    const double mm = 25.4, h = 0.01 * mm, depth = 0.0105 * mm;
    const Vec3 shift{-10, -10, -10}, c{0.5 * mm + shift[0], 0.5 * mm + shift[1], 0.5 * mm + shift[2]};
    const double r0 = 0.312 * mm;
    const int n = int(std::ceil(2 * (r0 + 3 * h) / h)) + 2;
    const testing::Grid g = testing::make_grid(n, n, n, h, {c[0] - n * h / 2, c[1] - n * h / 2, c[2] - n * h / 2},
                             [&](const Vec3& p, int, int, int) { return std::tanh((r0 - testing::dist(p, c)) / (1.5 * h)); });
    const Mesh ball = extract_dual_isosurface(g.field, g.domain);
    MeshFairing unfaired;
    unfaired.passes = 0;
    for (const double lone : {std::numeric_limits<double>::infinity(), 0.0011 * mm}) {
        CAPTURE(lone);
        PointCloud alone(points);
        alone.scale(mm);
        alone.translate(shift);
        Mesh want = ball;
        detail::KeepDeep deep{depth, h, lone};
        const DepthGuardReport expected = detail::fair_and_keep_deep(want, alone, unfaired, &deep);
        CHECK(expected.near_vertices > 100);
        CHECK(expected.moved_vertices > 100);
        if (std::isfinite(lone)) CHECK(expected.lone_points > 100);
        for (int processes : {2, 3}) {
            CAPTURE(processes);
            ThreadProcesses all(processes);
            const auto each = each_of(all, processes);
            std::vector<std::thread> others;
            for (int p = 1; p < processes; ++p)
                others.emplace_back([&each, p] {
                    TileScheduler& mine = *each[std::size_t(p)];
                    const std::shared_ptr<detail::KeptRange> kept = detail::file_for_root(mine);
                    detail::answer_guard_search(mine, kept.get());
                });
            PointCloud filed = filed_at_first(*each[0], points);
            filed.scale(mm);
            filed.translate(shift);
            Mesh got = ball;
            TileFacts facts;
            DepthGuardReport report;
            {
                detail::GuardSearchShared shared(each[0].get(), filed, facts);
                REQUIRE(shared.elsewhere());
                deep.elsewhere = shared.elsewhere();
                report = detail::fair_and_keep_deep(got, filed, unfaired, &deep);
                deep.elsewhere = nullptr;
                shared.done();
            }
            for (std::thread& o : others) o.join();
            const std::vector<std::size_t>& ranges = detail::tree_of(filed).shared_ranges;
            REQUIRE(ranges.size() == std::size_t(processes) + 1);
            CHECK(facts.guard_points == filed.size() - ranges[1]);
            CHECK(facts.guard_points > points.size() / std::size_t(2 * processes));
            CHECK(report.near_vertices == expected.near_vertices);
            CHECK(report.moved_vertices == expected.moved_vertices);
            CHECK(report.repair_rounds == expected.repair_rounds);
            CHECK(report.shallow_points == expected.shallow_points);
            CHECK(report.lone_points == expected.lone_points);
            CHECK(got.vertices == want.vertices);  // bit for bit
        }
    }
}


TEST_CASE("the tiles' needs and points by the ranges the processes kept: the first's alone, each point in its order") {
    // The dense noisy sphere in tiles of 16 cells with halos of 8 (a quarter of the points
    // near a tile's reach, every tile's points crossing ranges), in millimetres and moved
    // after the filing, as make_shell's points are.
    const PointSet points = noisy_dense_sphere();
    const double mm = 25.4;
    const Vec3 shift{-10, -10, -10};
    Domain whole;
    whole.h = 0.016 * mm;
    whole.nx = whole.ny = whole.nz = 64;
    whole.origin = {shift[0] - 0.01 * mm, shift[1] - 0.01 * mm, shift[2] - 0.01 * mm};
    const std::vector<Tile> tiles = plan_tiles(whole, 16, 8);
    const double reach = 3 * whole.h;
    PointCloud alone(points);
    alone.scale(mm);
    alone.translate(shift);
    const PointTree& t = detail::tree_of(alone);
    const std::vector<TileNeeds> want_needs = needs_of(t, whole, tiles, 16, 8, reach);
    for (int processes : {2, 3}) {
        CAPTURE(processes);
        const std::vector<int> want_owner = owners_of(want_needs, processes);
        ThreadProcesses all(processes);
        const auto each = each_of(all, processes);
        std::vector<detail::PointArray<Vec3f>> got(static_cast<std::size_t>(processes));
        std::vector<std::vector<int>> owners(static_cast<std::size_t>(processes));
        std::vector<std::thread> others;
        for (int p = 1; p < processes; ++p)
            others.emplace_back([&, p] {
                TileScheduler& mine = *each[std::size_t(p)];
                const std::shared_ptr<detail::KeptRange> kept = detail::file_for_root(mine);
                const OwnRange own = told_range(mine, kept.get());
                owners[std::size_t(p)] = owners_of(ranged_needs(mine, own, whole, tiles, 16, 8, reach), processes);
                RangedPointsFacts unused;
                got[std::size_t(p)] = ranged_points(mine, own, whole, tiles, owners[std::size_t(p)], 16, 8, reach, unused);
            });
        PointCloud filed = filed_at_first(*each[0], points);
        filed.scale(mm);
        filed.translate(shift);
        const PointTree& tree = detail::tree_of(filed);
        REQUIRE(tiles_by_ranges(tree, processes));
        const OwnRange own = tell_ranges(*each[0], tree);
        const std::vector<TileNeeds> needs = ranged_needs(*each[0], own, whole, tiles, 16, 8, reach);
        owners[0] = owners_of(needs, processes);
        RangedPointsFacts facts;
        got[0] = ranged_points(*each[0], own, whole, tiles, owners[0], 16, 8, reach, facts);
        for (std::thread& o : others) o.join();
        REQUIRE(needs.size() == want_needs.size());
        for (std::size_t k = 0; k < needs.size(); ++k) {
            CHECK(needs[k].points == want_needs[k].points);
            CHECK(needs[k].core_near == want_needs[k].core_near);
        }
        for (int p = 0; p < processes; ++p) CHECK(owners[std::size_t(p)] == want_owner);
        CHECK(got[0].empty());
        // Each other's points: those the first gives it alone, in its order, to the bit.
        const std::vector<PointRuns> runs = point_runs(tree, whole, tiles, want_owner, processes, 16, 8, reach);
        std::size_t given_all = 0;
        for (int p = 1; p < processes; ++p) {
            const detail::PointArray<float> want = points_in(tree, runs[std::size_t(p)]);
            const detail::PointArray<Vec3f>& have = got[std::size_t(p)];
            REQUIRE(have.size() * 3 == want.size());
            CHECK(std::equal(have.begin(), have.end(), reinterpret_cast<const Vec3f*>(want.data())));
            given_all += have.size();
        }
        CHECK(given_all > points.size() / 4);
        CHECK(facts.given + facts.own == given_all);
        CHECK(facts.own > 0);
        CHECK(facts.given > 0);
    }
}
