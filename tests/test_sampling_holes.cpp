// Points added on the surface (geometry/added_points): a sampling's holes found where
// they are, not at a surface's boundary; a random sampling told from a spaced one and
// from a scan; the shells of random samplings closed by points at the holes' centres;
// and sparse samplings smooth at their own scale by points between them, at the defaults.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "geometry/local_plane.hpp"
#include "geometry/point_tree.hpp"
#include "geometry/sampling_gap.hpp"
#include "geometry/sampling_holes.hpp"
#include "snvr/snvr.hpp"
#include "snvr/shapes.hpp"

using namespace snvr;

namespace {

// A square lattice of side 1, spacing 0.02, in a tilted plane through (0.5, 0.5, 0.5),
// less the points within `hole` of that centre.
PointSet lattice(double hole) {
    PointSet points;
    for (int i = 0; i <= 50; ++i)
        for (int j = 0; j <= 50; ++j) {
            const double u = 0.02 * i - 0.5, v = 0.02 * j - 0.5;
            if (u * u + v * v < hole * hole) continue;
            points.push_back({0.5 + 0.8 * u, 0.5 + v, 0.5 + 0.6 * u});
        }
    return points;
}

Shell shell_of(const PointSet& points, int resolution, bool add_points = true) {
    ShellSettings s;
    s.params.resolution = resolution;
    s.params.device = "openmp";
    s.params.add_points = add_points;
    return make_shell(points, s);
}

}  // namespace

TEST_CASE("hole_centres: a hole in a lattice is found at its centre; a lattice's own cells and its edges are not holes") {
    // Five points gone: an empty disc of radius 0.028 (to the diagonal neighbours).
    const PointCloud holed(lattice(0.025));
    const PointSet centres = hole_centres(holed, 0.022);
    REQUIRE(centres.size() == 1);
    CHECK(std::hypot(centres[0][0] - 0.5, centres[0][1] - 0.5, centres[0][2] - 0.5) < 0.003);
    CHECK(hole_centres(holed, 0.03).empty());  // none as wide as that
    // Whole: the lattice's squares (radius 0.014) are narrower, and its edges and corners,
    // open to one side, are no holes at all.
    CHECK(hole_centres(PointCloud(lattice(0)), 0.015).empty());
}

TEST_CASE("hole_centres tells how far each pass has looked, between parts of its search; a cancel there stops it") {
    // Enough points for three parts of a pass (a part is at least 4,096 points).
    const PointCloud cloud(shapes::random_by_name("sphere", 10000, 3));
    const double least = 0.0085;
    const PointSet want = hole_centres(cloud, least);
    CHECK(want.size() > 50);
    struct Told {
        std::size_t done, all;
        int pass;
    };
    std::vector<Told> told;
    const PointSet got =
        hole_centres(cloud, least, nullptr, [&told](std::size_t done, std::size_t all, int pass) {
            told.push_back({done, all, pass});
        });
    CHECK(got == want);  // told or not, the same centres
    REQUIRE(told.size() >= 3);
    CHECK(told[0].done == 0);
    CHECK(told[0].all == cloud.size());
    CHECK(told[0].pass == 1);
    std::size_t within = 0;  // lines between a pass's start and end
    for (std::size_t k = 1; k < told.size(); ++k) {
        CAPTURE(k);
        const Told& a = told[k - 1];
        const Told& b = told[k];
        if (b.done == 0) {  // a new pass, after the last one ended
            CHECK(a.done == a.all);
            CHECK(b.pass == a.pass + 1);
        } else {
            CHECK(b.pass == a.pass);
            CHECK(b.all == a.all);
            CHECK(b.done > a.done);
            within += b.done < b.all;
        }
    }
    CHECK(told.back().done == told.back().all);
    CHECK(told.back().pass >= 2);  // a later pass near the centres added
    CHECK(within >= 1);
    // A cancel from the callback leaves the search there.
    int calls = 0;
    CHECK_THROWS_AS(hole_centres(cloud, least, nullptr,
                                 [&calls](std::size_t done, std::size_t, int) {
                                     ++calls;
                                     if (done > 0) throw Cancelled("cancelled in the holes' search");
                                 }),
                    Cancelled);
    CHECK(calls == 2);
}

TEST_CASE("local_patch: a point of another sheet among the nearest does not tilt the plane refitted") {
    // A point on a sheet's rim (z = 0, x <= 0), its nearest 19 on that sheet, the 20th on
    // the next turn 0.2 below: the plane of all 20 leans 35 degrees; the plane of the
    // nearest 8, fitted again to all that stand near it, is the sheet's.
    PointSet points{{0, 0, 0}, {0.005, 0.01, -0.2}};
    for (int i = 0; i < 19; ++i) {
        const double a = M_PI / 2 + M_PI * (i + 0.5) / 19, r = 0.04 + 0.13 * double(i % 5) / 4;
        points.push_back({r * std::cos(a), r * std::sin(a), 0.0});
    }
    const PointCloud cloud(points);
    const auto& tree = detail::tree_of(cloud);
    const std::uint32_t k = tree.nearest({0, 0, 0}).index;
    const double tilted = std::fabs(detail::local_patch(tree, k, 20, 20, 0.5).normal[2]);
    const double refitted = std::fabs(detail::local_patch(tree, k, 20, 8, 0.5, 2).normal[2]);
    CHECK(tilted < std::cos(10 * M_PI / 180));
    CHECK(refitted > std::cos(0.5 * M_PI / 180));
}

TEST_CASE("share_bordering_holes: random samplings above HoleRules::random_share, spaced ones and a scan below") {
    for (const char* shape : {"sphere", "torus", "helicoid"}) {
        CAPTURE(shape);
        const PointCloud random(shapes::random_by_name(shape, 1500, 1));
        const auto& tree = detail::tree_of(random);
        CHECK(share_bordering_holes(tree, sampling_gap(tree)) >= 1.5 * HoleRules::random_share);
        const PointCloud spaced(shapes::by_name(shape, 0.03));
        const auto& spaced_tree = detail::tree_of(spaced);
        CHECK(share_bordering_holes(spaced_tree, sampling_gap(spaced_tree)) < 0.5 * HoleRules::random_share);
    }
    // Scans hold a few holes (missing patches, a ragged open base): not a random sampling.
    for (const char* scan : {"bunny.ply", "igea.ply", "armadillo.ply"}) {
        const std::string path = std::string(SNVR_DATA_DIR) + "/" + scan;
        if (!std::filesystem::exists(path)) continue;  // the scans sit beside the checkout
        CAPTURE(scan);
        const PointCloud points = read_point_cloud(path);
        const auto& tree = detail::tree_of(points);
        CHECK(share_bordering_holes(tree, sampling_gap(tree)) < 0.6 * HoleRules::random_share);
    }
}

TEST_CASE("random samplings at the defaults: closed where the points are, every point deep inside") {
    struct Case {
        const char* shape;
        std::size_t points;
        std::uint64_t seed;
        long genus;               // of the whole mesh: a closed surface's two walls each have its genus
        std::size_t components;   // a closed surface: the outer wall and the cavity's
    };
    for (const Case& c : {Case{"sphere", 1500, 1, 0, 2}, Case{"sphere", 5000, 2, 0, 2}, Case{"torus", 1500, 3, 2, 2},
                          Case{"helicoid", 1500, 4, 0, 1}, Case{"cube", 1500, 5, 0, 2}})
        for (int resolution : {64, 128}) {
            CAPTURE(c.shape);
            CAPTURE(c.seed);
            CAPTURE(resolution);
            const PointSet points = shapes::random_by_name(c.shape, c.points, c.seed);
            const Shell s = shell_of(points, resolution);
            CHECK(s.run.hole_share >= HoleRules::random_share);
            CHECK(s.quality.solids == 1);
            CHECK(s.quality.components == c.components);
            CHECK(s.quality.genus == c.genus);
            CHECK(s.quality.points_inside == s.points);  // those the outlier rules kept
            CHECK(s.quality.depth_min >= 0.8 - 1e-3);
        }
    // Without the points at the holes the walls are holed through (genus 27 at 256).
    const Shell holed = shell_of(shapes::random_by_name("sphere", 1500, 1), 128, false);
    CHECK(holed.run.hole_fills == 0);
    CHECK(holed.quality.genus > 0);
}

TEST_CASE("spaced samplings and scans: no points added, the shell as before") {
    const Shell spaced = shell_of(shapes::by_name("sphere", 0.04), 64);
    CHECK(spaced.run.hole_share < HoleRules::random_share);
    CHECK(spaced.run.hole_fills == 0);
    // A line scan: dense along its lines, 4 spacings between them, every point borders a
    // hole wider than the gap; without points between the lines the strip falls apart.
    const PointSet lines = shapes::lidar_scan({0.5, 0.5, 0.5}, 0.7, 0.01, 0.04, 0.001);
    const Shell scan = shell_of(lines, 128);
    CHECK(scan.run.hole_fills > 0);
    CHECK(scan.quality.solids == 1);
    CHECK(scan.quality.genus == 0);
    CHECK(scan.quality.points_inside == scan.points);
    CHECK(shell_of(lines, 128, false).quality.solids > 1);
}

TEST_CASE("a sparse sampling at the defaults: each wall within 0.03 l RMS of its exact offset sphere, no balls") {
    // The sampler's sphere 0.04 apart (963 points, radius 0.35): the gap sets the offset.
    const PointSet points = shapes::by_name("sphere", 0.04);
    const double r = 0.35;
    for (int resolution : {128}) {  // 256 and 512: bench/RESULTS.md
        CAPTURE(resolution);
        for (bool add : {true, false}) {
            CAPTURE(add);
            const Shell s = shell_of(points, resolution, add);
            const double l = s.run.offset;
            CHECK(s.run.offset > 2.5 * s.run.domain.h);  // the sampling set it
            CHECK((s.run.upsampled > 0) == add);
            // Each wall's RMS and largest distance to its exact sphere (r + l, r - l).
            double sum[2] = {0, 0}, most[2] = {0, 0};
            std::size_t count[2] = {0, 0};
            for (const Vec3& v : s.mesh.vertices) {
                const double radius = std::hypot(v[0] - 0.5, v[1] - 0.5, v[2] - 0.5);
                const int wall = radius > r ? 0 : 1;
                const double e = std::fabs(radius - (wall == 0 ? r + l : r - l)) / l;
                sum[wall] += e * e;
                most[wall] = std::max(most[wall], e);
                ++count[wall];
            }
            const double outer = std::sqrt(sum[0] / double(count[0])), inner = std::sqrt(sum[1] / double(count[1]));
            std::printf("sparse sphere at %d, points %s: outer RMS %.4f max %.4f, inner RMS %.4f max %.4f (x l)\n",
                        resolution, add ? "added" : "as given", outer, most[0], inner, most[1]);
            if (add) {
                CHECK(outer <= 0.03);
                CHECK(inner <= 0.03);
                CHECK(most[0] <= 0.06);  // no ball stands out
                CHECK(most[1] <= 0.06);
            } else {
                CHECK(outer > 0.08);  // the grapes
            }
            CHECK(s.quality.genus == 0);
            CHECK(s.quality.components == 2);
            CHECK(s.quality.points_inside == s.points);
            CHECK(s.quality.depth_min >= 0.8 - 1e-3);
        }
    }
}

TEST_CASE("a sparse open surface: its boundary does not grow, its offset and pieces stay") {
    const PointSet points = shapes::by_name("half-sphere", 0.04);
    const Shell added = shell_of(points, 128), given = shell_of(points, 128, false);
    CHECK(added.run.upsampled > 0);
    CHECK(added.run.offset == given.run.offset);
    CHECK(added.quality.solids == 1);
    CHECK(added.quality.genus == 0);
    CHECK(added.quality.points_inside == added.points);
    // The rim (z = 0.5) grows by at most a tenth of the offset beyond where the points' balls end.
    double lowest_added = 1, lowest_given = 1;
    for (const Vec3& v : added.mesh.vertices) lowest_added = std::min(lowest_added, v[2]);
    for (const Vec3& v : given.mesh.vertices) lowest_given = std::min(lowest_given, v[2]);
    CHECK(lowest_added >= lowest_given - 0.1 * added.run.offset);
}

TEST_CASE("a twisted surface sparse against its turns: one solid of genus 0, no point added off it") {
    // 500 random points on the helicoid: its turns 0.2 apart, each point's nearest 20
    // reach 0.13-0.2 (a point of the next turn among them at the rim), and near the axis
    // the sheet turns half round within a hole's neighbours. Seed 2 is a random sampling
    // (points at its holes); seed 9 is not (4% share missed), so it has points between
    // alone. Before the planes refitted to one sheet and the centres held to their rims
    // both had genus 1-2 at every grid.
    for (std::uint64_t seed : {2, 9}) {
        const PointSet points = shapes::random_by_name("helicoid", 500, seed);
        for (int resolution : {64, 128}) {
            CAPTURE(seed);
            CAPTURE(resolution);
            const Shell s = shell_of(points, resolution);
            CHECK(s.run.upsampled > 0);
            CHECK((s.run.hole_fills > 0) == (seed == 2));
            CHECK(s.quality.solids == 1);
            CHECK(s.quality.components == 1);
            CHECK(s.quality.genus == 0);
            CHECK(s.quality.points_inside == s.points);
            CHECK(s.quality.depth_min >= 0.8 - 1e-3);
        }
    }
}
