// The check's point depths (PointDepths: groups, runs, tangent bounds) against brute
// force over every triangle: the same points inside, the same least depth to the bit,
// the same depths for the percentile.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "check/point_depths.hpp"
#include "check/walls.hpp"
#include "mesh/triangle_grid.hpp"
#include "geometry/point_tree.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh.hpp"
#include "snvr/quality.hpp"
#include "snvr/shell.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/shapes.hpp"
#include "snvr/tiles.hpp"

using namespace snvr;

namespace {

struct Brute {
    std::size_t inside = 0;
    double depth_min = std::numeric_limits<double>::infinity();
    std::vector<double> depths;  // signed, negative outside, sorted
};

Brute brute_force(const Mesh& mesh, const PointCloud& cloud) {
    Brute b;
    const auto& V = mesh.vertices;
    for (std::size_t k = 0; k < cloud.size(); ++k) {
        const Vec3 p = cloud[k];
        double d2 = std::numeric_limits<double>::infinity();
        for (const auto& t : mesh.triangles) d2 = std::min(d2, point_triangle_dist_sq(p, V[t[0]], V[t[1]], V[t[2]]));
        const double d = std::sqrt(d2);
        const bool inside = count_points_inside(mesh, {p}) == 1;
        b.inside += inside;
        if (inside) b.depth_min = std::min(b.depth_min, d);
        b.depths.push_back(inside ? d : -d);
    }
    std::sort(b.depths.begin(), b.depths.end());
    return b;
}

// Both passes over all the groups at once; the figures, their depths sorted.
detail::PointDepths::Figures both_passes(detail::PointDepths& depths) {
    depths.bound(0, depths.groups());
    depths.settle(0, depths.groups(), depths.shallowest());
    detail::PointDepths::Figures f = depths.figures();
    std::sort(f.depths.begin(), f.depths.end());
    return f;
}

// A thin shell around a sphere, from the library itself: its mesh, voxel and offset.
struct ThinShell {
    Mesh mesh;
    double h = 0, l = 0;
};
ThinShell thin_shell(int resolution = 40) {
    const PointSet seeds = shapes::sphere({0.5, 0.5, 0.5}, 0.3, 0.02);
    Parameters p;
    p.resolution = resolution;
    p.device = "openmp";
    const Result r = reconstruct(seeds, p);
    return {shell_mesh(r, seeds), r.domain.h, r.offset};
}

}  // namespace

TEST_CASE("point depths: groups, runs and bounds give brute force's figures, dense and sparse") {
    const ThinShell shell = thin_shell();
    const Mesh& mesh = shell.mesh;
    const double h = shell.h, l = shell.l;
    REQUIRE(mesh.triangles.size() > 1000);
    // Points: a dense cap (runs of groups share their searches), the sphere sparsely
    // (groups of a point or two), spread across the wall and some beyond it, and some
    // on the shell's surface itself.
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> unit(0, 1);
    PointSet points;
    const auto at = [&](double theta, double phi, double radius) {
        return Vec3{0.5 + radius * std::sin(theta) * std::cos(phi), 0.5 + radius * std::sin(theta) * std::sin(phi),
                    0.5 + radius * std::cos(theta)};
    };
    for (int n = 0; n < 6000; ++n)  // within 0.3 rad of the pole: some 40 a voxel of surface
        points.push_back(at(0.3 * std::sqrt(unit(rng)), 2 * M_PI * unit(rng), 0.3 + 0.9 * l * (2 * unit(rng) - 1)));
    for (int n = 0; n < 1500; ++n)
        points.push_back(at(std::acos(2 * unit(rng) - 1), 2 * M_PI * unit(rng), 0.3 + 1.3 * l * (2 * unit(rng) - 1)));
    for (int n = 0; n < 50; ++n) points.push_back(mesh.vertices[std::size_t(unit(rng) * double(mesh.vertices.size()))]);
    const PointCloud cloud(points);
    const Brute b = brute_force(mesh, cloud);
    REQUIRE(b.inside > 0);
    REQUIRE(b.inside < cloud.size());

    for (int threads_like : {1, 4}) {  // one pass over all groups, or in chunks
        CAPTURE(threads_like);
        const TriangleGrid grid(mesh);
        detail::PointDepths depths(mesh, grid, detail::tree_of(cloud), h, false, false);
        const std::size_t g = depths.groups(), step = (g + std::size_t(threads_like) - 1) / std::size_t(threads_like);
        for (std::size_t first = 0; first < g; first += step) depths.bound(first, std::min(g, first + step));
        const double shallowest = depths.shallowest();
        for (std::size_t first = 0; first < g; first += step) depths.settle(first, std::min(g, first + step), shallowest);
        detail::PointDepths::Figures f = depths.figures();
        CHECK(f.inside == b.inside);
        CHECK(f.depth_min == b.depth_min);
        std::sort(f.depths.begin(), f.depths.end());
        CHECK(f.depths == b.depths);  // every point sampled below 2^18 points
    }
    // Every point measured (measure_quality's way): the same.
    const TriangleGrid grid(mesh);
    detail::PointDepths every(mesh, grid, detail::tree_of(cloud), h, true, false);
    const detail::PointDepths::Figures f = both_passes(every);
    CHECK(f.inside == b.inside);
    CHECK(f.depth_min == b.depth_min);
}

TEST_CASE("point depths: triangle frames made again where the search keeps another in their slot") {
    // The search keeps the frames of the triangles it gathered lately, a slot each by a
    // hash: patches of points all round a finer shell gather thousands of triangles, and
    // two of them share a slot some tens of times (the frame made again each time).
    const ThinShell shell = thin_shell(80);
    const Mesh& mesh = shell.mesh;
    REQUIRE(mesh.triangles.size() > 20000);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> unit(0, 1);
    PointSet points;
    for (int patch = 0; patch < 60; ++patch) {  // runs of groups, which gather in lanes
        const double theta = std::acos(2 * unit(rng) - 1), phi = 2 * M_PI * unit(rng);
        const double depth = 1.2 * shell.l * (2 * unit(rng) - 1), across = 0.5 * shell.h / 0.3;  // half a voxel
        for (int n = 0; n < 24; ++n) {
            const double t = theta + across * (unit(rng) - 0.5), f = phi + across * (unit(rng) - 0.5);
            const double radius = 0.3 + depth + 0.5 * shell.h * (unit(rng) - 0.5);
            points.push_back({0.5 + radius * std::sin(t) * std::cos(f), 0.5 + radius * std::sin(t) * std::sin(f),
                              0.5 + radius * std::cos(t)});
        }
    }
    const PointCloud cloud(points);
    const Brute b = brute_force(mesh, cloud);
    REQUIRE(b.inside > 0);
    REQUIRE(b.inside < cloud.size());
    const TriangleGrid grid(mesh);
    detail::PointDepths depths(mesh, grid, detail::tree_of(cloud), shell.h, true, false);
    const detail::PointDepths::Figures f = both_passes(depths);
    CHECK(f.inside == b.inside);
    CHECK(f.depth_min == b.depth_min);
    CHECK(f.depths == b.depths);
}

TEST_CASE("point depths: points split between shares of the mesh (another process's check) give the whole's") {
    const ThinShell shell = thin_shell();
    const Mesh& mesh = shell.mesh;
    const double h = shell.h, l = shell.l;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> unit(0, 1);
    PointSet points;
    for (int n = 0; n < 4000; ++n) {  // across the wall and beyond it, all round
        const double theta = std::acos(2 * unit(rng) - 1), phi = 2 * M_PI * unit(rng);
        const double radius = 0.3 + 1.5 * l * (2 * unit(rng) - 1);
        points.push_back({0.5 + radius * std::sin(theta) * std::cos(phi),
                          0.5 + radius * std::sin(theta) * std::sin(phi), 0.5 + radius * std::cos(theta)});
    }
    for (int n = 0; n < 2; ++n) points.push_back({0.5, 0.5, 0.5});  // far from every triangle
    const PointCloud cloud(points);
    const Brute b = brute_force(mesh, cloud);
    double longest = 0;
    for (const auto& t : mesh.triangles)
        for (int c = 0; c < 3; ++c)
            for (int a = 0; a < 3; ++a)
                longest = std::max(longest, std::fabs(mesh.vertices[t[c]][a] - mesh.vertices[t[(c + 1) % 3]][a]));
    // Two shares, the points split at x = 0.5; each with the triangles within reach of its
    // side (as the root makes them). A narrow reach leaves more for the whole mesh to decide.
    for (double reach : {4 * l + 2 * h, 0.5 * l}) {
        CAPTURE(reach);
        std::size_t inside = 0, unresolved = 0;
        double least = std::numeric_limits<double>::infinity();
        const TriangleGrid grid(mesh);
        for (int side = 0; side < 2; ++side) {
            const auto mine = [&](double x) { return side == 0 ? x < 0.5 : x >= 0.5; };
            const double widened = reach + longest + 3 * h;
            const auto near = [&](const Vec3& v) { return side == 0 ? v[0] < 0.5 + widened : v[0] >= 0.5 - widened; };
            CheckShare share;
            share.reach = reach;
            share.voxel = h;
            std::vector<std::uint32_t> local(mesh.vertices.size(), std::uint32_t(-1));
            for (const auto& t : mesh.triangles) {
                if (!near(mesh.vertices[t[0]]) && !near(mesh.vertices[t[1]]) && !near(mesh.vertices[t[2]])) continue;
                std::array<std::uint32_t, 3> tri;
                for (int c = 0; c < 3; ++c) {
                    if (local[t[c]] == std::uint32_t(-1)) {
                        local[t[c]] = std::uint32_t(share.vertices.size());
                        share.vertices.push_back(mesh.vertices[t[c]]);
                    }
                    tri[c] = local[t[c]];
                }
                share.triangles.push_back(tri);
            }
            std::vector<Vec3> given;
            for (std::size_t k = 0; k < cloud.size(); ++k)
                if (mine(cloud[k][0])) {
                    given.push_back(cloud[k]);
                    for (int a = 0; a < 3; ++a) share.points.push_back(float(cloud[k][a]));
                }
            const CheckShareFigures f = measure_check_share(share);
            CHECK(f.walls.empty());
            inside += f.points_inside;
            least = std::min(least, f.depth_min);
            unresolved += f.unresolved.size();
            // The rest as the whole mesh decides them (the root's part).
            for (std::uint32_t k : f.unresolved) {
                REQUIRE(k < given.size());
                const bool in = count_points_inside(mesh, {given[k]}) == 1;
                if (!in) continue;
                ++inside;
                least = std::min(least, std::sqrt(grid.closest(given[k]).dist_sq));
            }
        }
        CHECK(inside == b.inside);
        CHECK(least == b.depth_min);
        CHECK(unresolved >= 2);  // the centre's points lie beyond any reach
        if (reach < l) CHECK(unresolved > 100);
    }
}

namespace {

// Scan lines round the thin shell's sphere: circles of latitude 3 voxels apart, a point
// every 0.3 voxels along each, within the wall (the tree's leaves run along the lines,
// many voxels long).
PointSet scan_lines(double h, double l) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> unit(-1, 1);
    PointSet points;
    for (double theta = 0.2; theta < M_PI - 0.2; theta += 3 * h / 0.3)
        for (double phi = 0; phi < 2 * M_PI; phi += 0.3 * h / (0.3 * std::sin(theta))) {
            const double radius = 0.3 + 0.5 * l * unit(rng);
            points.push_back({0.5 + radius * std::sin(theta) * std::cos(phi), 0.5 + radius * std::sin(theta) * std::sin(phi),
                              0.5 + radius * std::cos(theta)});
        }
    return points;
}

double half_diagonal(const detail::PointDepths::Span& s) {
    return 0.5 * std::sqrt(detail::PointTree::dist_sq(s.lo, s.hi));
}

}  // namespace

TEST_CASE("point depths: a sparse scan's wide groups cut narrower: the same points, the same figures") {
    const ThinShell shell = thin_shell();
    const Mesh& mesh = shell.mesh;
    const double h = shell.h, l = shell.l;
    const PointCloud cloud(scan_lines(h, l));
    const detail::PointTree& tree = detail::tree_of(cloud);
    std::vector<detail::PointDepths::Span> spans = detail::PointDepths::group_spans(tree, h, false);
    // Every fifth group sampled (left whole), the rest not.
    for (std::size_t g = 0; g < spans.size(); ++g) spans[g].sampled = g % 5 == 0;
    std::size_t wide = 0;
    for (const auto& s : spans) wide += !s.sampled && half_diagonal(s) > h;
    REQUIRE(wide > 20);
    const std::vector<detail::PointDepths::Span> cut = detail::PointDepths::narrowed(tree, h, h, spans);
    CHECK(cut.size() > spans.size() + wide);
    // The same points in order, each sampled group as it was, every other one narrow and
    // holding its points in its box.
    std::size_t at = 0, next = 0;
    for (const auto& s : cut) {
        REQUIRE(s.begin == next);
        REQUIRE(s.end > s.begin);
        next = s.end;
        while (spans[at].end < s.end) ++at;
        CHECK(s.sampled == spans[at].sampled);
        if (s.sampled) {
            CHECK(s.begin == spans[at].begin);
            CHECK(s.end == spans[at].end);
            continue;
        }
        if (half_diagonal(spans[at]) <= h) {  // left whole
            CHECK(s.begin == spans[at].begin);
            CHECK(s.end == spans[at].end);
        } else {
            CHECK(half_diagonal(s) <= 0.75 * h);
        }
        const detail::PointDepths::Span box = detail::PointDepths::span_of(tree, s.begin, s.end);
        CHECK(box.lo == s.lo);
        CHECK(box.hi == s.hi);
    }
    CHECK(next == tree.size());
    // Measured in either grouping: brute force's figures, and the sampled groups' depths.
    const Brute b = brute_force(mesh, cloud);
    REQUIRE(b.inside > 1000);
    const TriangleGrid grid(mesh);
    std::vector<double> sampled[2];
    for (int narrow = 0; narrow < 2; ++narrow) {
        CAPTURE(narrow);
        detail::PointDepths depths(mesh, grid, tree, h, narrow ? cut : spans, false, false, nullptr);
        const detail::PointDepths::Figures f = both_passes(depths);
        CHECK(f.inside == b.inside);
        CHECK(f.depth_min == b.depth_min);
        sampled[narrow] = f.depths;
    }
    CHECK(!sampled[0].empty());
    CHECK(sampled[0] == sampled[1]);
}

TEST_CASE("point depths: another process's points measured in the groups the root dealt") {
    const ThinShell shell = thin_shell();
    const Mesh& mesh = shell.mesh;
    const double h = shell.h, l = shell.l;
    PointSet points = scan_lines(h, l);
    points.push_back({0.5, 0.5, 0.5});  // beyond the share's reach: its group is left to the root
    const PointCloud cloud(points);
    const detail::PointTree& tree = detail::tree_of(cloud);
    const Brute b = brute_force(mesh, cloud);
    const TriangleGrid grid(mesh);
    // The whole mesh, and every point given in the root's order and frame (kept so here).
    const auto share_of = [&](std::vector<std::uint32_t> groups) {
        CheckShare share;
        share.vertices = mesh.vertices;
        share.triangles = mesh.triangles;
        share.reach = 2 * l;  // the wall's points are within it, not the centre
        share.voxel = h;
        share.origin = tree.origin;
        share.points_frame = tree.frame().figures();
        for (std::size_t k = 0; k < tree.size(); ++k)
            for (int a = 0; a < 3; ++a) share.points.push_back(tree.xyz[k][std::size_t(a)]);
        share.point_groups = std::move(groups);
        return share;
    };
    // Measured in groups, those left undecided as the whole mesh decides them.
    const auto measured = [&](const CheckShareFigures& f, std::size_t& inside, double& least) {
        inside = f.points_inside;
        least = f.depth_min;
        for (std::uint32_t k : f.unresolved) {
            REQUIRE(k < tree.size());
            const Vec3 p = tree.point(k);
            if (count_points_inside(mesh, {p}) != 1) continue;
            ++inside;
            least = std::min(least, std::sqrt(grid.closest(p).dist_sq));
        }
    };
    std::vector<detail::PointDepths::Span> spans = detail::PointDepths::group_spans(tree, h, false);
    for (auto& s : spans) s.sampled = false;
    std::vector<std::uint32_t> narrow;
    for (const auto& s : detail::PointDepths::narrowed(tree, h, h, spans)) narrow.push_back(s.end - s.begin);
    const CheckShareFigures by_groups = measure_check_share(share_of(narrow));
    std::size_t inside = 0;
    double least = 0;
    measured(by_groups, inside, least);
    CHECK(inside == b.inside);
    CHECK(least == b.depth_min);
    CHECK(by_groups.unresolved.size() < tree.size() / 3);
    // One group of every point: the centre's search reaches beyond the share's reach, so
    // all are left to the root (the groups given are the ones measured, not the leaves).
    const CheckShareFigures whole = measure_check_share(share_of({std::uint32_t(tree.size())}));
    CHECK(whole.unresolved.size() == tree.size());
    measured(whole, inside, least);
    CHECK(inside == b.inside);
    CHECK(least == b.depth_min);
    // Groups that do not count the points given: refused.
    CHECK_THROWS_AS(measure_check_share(share_of({std::uint32_t(tree.size() - 1)})), InputError);
    CHECK_THROWS_AS(measure_check_share(share_of({0, std::uint32_t(tree.size())})), InputError);
}

TEST_CASE("the check tells how far its walls and depths have come, and stops when told to") {
    const ThinShell shell = thin_shell();
    const PointCloud cloud(scan_lines(shell.h, shell.l));
    for (bool surface : {false, true}) {
        CAPTURE(surface);
        const MeshQuality whole = surface ? measure_quality(shell.mesh, cloud, shell.l, shell.h)
                                          : measure_shell(shell.mesh, cloud, shell.l, shell.h);
        std::vector<std::array<std::size_t, 2>> calls;
        const MeshQuality told = detail::measure_told(shell.mesh, cloud, shell.l, shell.h, surface,
                                                      [&](std::size_t done, std::size_t all) { calls.push_back({done, all}); });
        // Between every round, rising from none to all; the same figures as untold.
        REQUIRE(calls.size() == std::size_t(2 * detail::kCheckRounds + 1));
        CHECK(calls.front()[0] == 0);
        CHECK(calls.back()[0] == calls.back()[1]);
        const TriangleGrid grid(shell.mesh);
        const detail::PointDepths groups(shell.mesh, grid, detail::tree_of(cloud), shell.h, surface, surface);
        CHECK(calls.back()[1] == whole.vertices + 2 * groups.groups());  // a vertex's wall, a group's passes
        for (std::size_t c = 1; c < calls.size(); ++c) {
            CHECK(calls[c][1] == calls[0][1]);
            CHECK(calls[c][0] >= calls[c - 1][0]);
        }
        CHECK(told.points_inside == whole.points_inside);
        CHECK(told.depth_min == whole.depth_min);
        CHECK(told.depth_p01 == whole.depth_p01);
        CHECK(told.wall_min == whole.wall_min);
        CHECK(told.wall_p01 == whole.wall_p01);
        CHECK(told.wall_misses == whole.wall_misses);
        CHECK(told.genus == whole.genus);
        if (surface) CHECK(told.offset_rms == whole.offset_rms);
        // A throw from the teller (after the first round) stops the check: told no more.
        std::size_t heard = 0;
        struct Stop {};
        CHECK_THROWS_AS(detail::measure_told(shell.mesh, cloud, shell.l, shell.h, surface,
                                             [&](std::size_t, std::size_t) {
                                                 if (++heard == 2) throw Stop{};
                                             }),
                        Stop);
        CHECK(heard == 2);
    }
}
