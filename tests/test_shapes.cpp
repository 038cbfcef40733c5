// The analytic samplers: points exactly on the surface, no holes wider than the
// spacing, and exact distance functions.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>

#include "snvr/error.hpp"
#include "snvr/shapes.hpp"

using snvr::PointSet;
using snvr::Vec3;
namespace shapes = snvr::shapes;

namespace {

constexpr double kPi = 3.14159265358979323846;
const Vec3 kC{0.5, 0.5, 0.5};
constexpr double kSize = 0.35;

double dist(const Vec3& a, const Vec3& b) { return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]); }

double nearest(const PointSet& points, const Vec3& q) {
    double best = std::numeric_limits<double>::infinity();
    for (const Vec3& p : points) best = std::min(best, dist(p, q));
    return best;
}

double min_pair_distance(const PointSet& points) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < points.size(); ++i)
        for (std::size_t j = i + 1; j < points.size(); ++j) best = std::min(best, dist(points[i], points[j]));
    return best;
}

// Distance to the two-headed cone (not in the API): the cone |z - c.z| = a (1 - rho / r).
double cone_distance(const Vec3& p, const Vec3& c, double r, double ht) {
    const double a = ht / 2;
    const double rho = std::hypot(p[0] - c[0], p[1] - c[1]);
    const double z = std::abs(p[2] - c[2]);
    // Nearest point on the 2D segment from (r, 0) to (0, a).
    const double ex = -r, ey = a;
    const double t = std::clamp(((rho - r) * ex + z * ey) / (ex * ex + ey * ey), 0.0, 1.0);
    return std::hypot(rho - (r + t * ex), z - t * ey);
}

// Independent uniform-ish random points on each surface (area-weighted pieces).
struct Rng {
    std::mt19937_64 gen{12345};
    double uniform(double lo = 0, double hi = 1) { return std::uniform_real_distribution<double>(lo, hi)(gen); }
    Vec3 on_sphere(const Vec3& c, double r, bool upper_only) {
        const double z = uniform(upper_only ? 0.0 : -1.0, 1.0), theta = uniform(0, 2 * kPi);
        const double rho = std::sqrt(1 - z * z);
        return {c[0] + r * rho * std::cos(theta), c[1] + r * rho * std::sin(theta), c[2] + r * z};
    }
    Vec3 on_cube(const Vec3& c, double s) {
        Vec3 p{c[0] + uniform(-s / 2, s / 2), c[1] + uniform(-s / 2, s / 2), c[2] + uniform(-s / 2, s / 2)};
        const int axis = int(uniform(0, 3)) % 3;
        p[axis] = c[axis] + (uniform() < 0.5 ? -s / 2 : s / 2);
        return p;
    }
    Vec3 on_cylinder(const Vec3& c, double r, double ht) {
        const double side = 2 * kPi * r * ht, cap = kPi * r * r;
        const double theta = uniform(0, 2 * kPi);
        const double pick = uniform(0, side + 2 * cap);
        if (pick < side) return {c[0] + r * std::cos(theta), c[1] + r * std::sin(theta), c[2] + uniform(-ht / 2, ht / 2)};
        const double rho = r * std::sqrt(uniform());
        const double z = c[2] + (pick < side + cap ? -ht / 2 : ht / 2);
        return {c[0] + rho * std::cos(theta), c[1] + rho * std::sin(theta), z};
    }
    Vec3 on_cone(const Vec3& c, double r, double ht) {
        // Area density grows linearly with rho on a cone: rho = r sqrt(u).
        const double rho = r * std::sqrt(uniform()), theta = uniform(0, 2 * kPi);
        const double z = ht / 2 * (1 - rho / r) * (uniform() < 0.5 ? -1 : 1);
        return {c[0] + rho * std::cos(theta), c[1] + rho * std::sin(theta), c[2] + z};
    }
};

struct Case {
    std::string name;
    std::function<PointSet(double)> sample;
    std::function<double(const Vec3&)> distance;
    std::function<Vec3(Rng&)> random_point;
};

std::vector<Case> cases() {
    return {
        {"sphere", [](double s) { return shapes::sphere(kC, kSize, s); },
         [](const Vec3& p) { return shapes::sphere_distance(p, kC, kSize); },
         [](Rng& g) { return g.on_sphere(kC, kSize, false); }},
        {"half-sphere", [](double s) { return shapes::half_sphere(kC, kSize, s); },
         [](const Vec3& p) { return shapes::sphere_distance(p, kC, kSize); },
         [](Rng& g) { return g.on_sphere(kC, kSize, true); }},
        {"cube", [](double s) { return shapes::cube(kC, kSize, s); },
         [](const Vec3& p) { return shapes::cube_distance(p, kC, kSize); },
         [](Rng& g) { return g.on_cube(kC, kSize); }},
        {"cylinder", [](double s) { return shapes::cylinder(kC, kSize, kSize, s); },
         [](const Vec3& p) { return shapes::cylinder_distance(p, kC, kSize, kSize); },
         [](Rng& g) { return g.on_cylinder(kC, kSize, kSize); }},
        {"cone", [](double s) { return shapes::two_headed_cone(kC, kSize, 2 * kSize, s); },
         [](const Vec3& p) { return cone_distance(p, kC, kSize, 2 * kSize); },
         [](Rng& g) { return g.on_cone(kC, kSize, 2 * kSize); }},
    };
}

}  // namespace

TEST_CASE("sampled points lie on their surface") {
    for (const Case& c : cases())
        for (double spacing : {0.1, 0.05, 0.031, 0.01}) {
            CAPTURE(c.name);
            CAPTURE(spacing);
            const PointSet points = c.sample(spacing);
            REQUIRE(!points.empty());
            double worst = 0;
            for (const Vec3& p : points) worst = std::max(worst, c.distance(p));
            CHECK(worst < 1e-12);
        }
}

TEST_CASE("samples cover the surface without gaps wider than the spacing") {
    Rng rng;
    for (const Case& c : cases())
        for (double spacing : {0.1, 0.05, 0.031}) {
            CAPTURE(c.name);
            CAPTURE(spacing);
            const PointSet points = c.sample(spacing);
            double worst = 0;
            for (int n = 0; n < 2000; ++n) {
                const Vec3 q = c.random_point(rng);
                REQUIRE(c.distance(q) < 1e-12);  // the generator itself is on the surface
                worst = std::max(worst, nearest(points, q));
            }
            CHECK(worst <= spacing);
            // Roughly uniform, and no duplicates (shared edges, rims, apexes and the
            // base circle appear once).
            CHECK(min_pair_distance(points) > 0.5 * spacing);
        }
}

TEST_CASE("point counts follow the spacing") {
    const double s = 0.05;
    CHECK(shapes::sphere(kC, kSize, s).size() == std::size_t(std::ceil(4 * kPi * kSize * kSize / (s * s))));
    CHECK(shapes::sphere(kC, 1e-3, 1.0).size() == 1);  // at least one point
    // Half of the sphere's lattice, from the same density.
    const double full = double(shapes::sphere(kC, kSize, s).size());
    CHECK(std::abs(double(shapes::half_sphere(kC, kSize, s).size()) - full / 2) <= 1);
    for (const Vec3& p : shapes::half_sphere(kC, kSize, s)) CHECK(p[2] >= kC[2]);
    // Cube 0.35 at 0.05: 7 intervals per edge, 8^3 - 6^3 surface lattice points.
    CHECK(shapes::cube(kC, kSize, s).size() == 8 * 8 * 8 - 6 * 6 * 6);
    // Densities of the others are within a factor of the area / spacing^2.
    const double cyl_area = 2 * kPi * kSize * kSize + 2 * kPi * kSize * kSize;
    const double cyl = double(shapes::cylinder(kC, kSize, kSize, s).size());
    CHECK(cyl > cyl_area / (s * s));
    CHECK(cyl < 2 * cyl_area / (s * s));
}

TEST_CASE("cube corners and cone apexes are sampled") {
    const PointSet cube = shapes::cube(kC, kSize, 0.04);
    for (double x : {-1.0, 1.0})
        for (double y : {-1.0, 1.0})
            for (double z : {-1.0, 1.0})
                CHECK(nearest(cube, {kC[0] + x * kSize / 2, kC[1] + y * kSize / 2, kC[2] + z * kSize / 2}) == 0.0);
    const PointSet cone = shapes::two_headed_cone(kC, kSize, 2 * kSize, 0.04);
    CHECK(nearest(cone, {kC[0], kC[1], kC[2] + kSize}) == 0.0);
    CHECK(nearest(cone, {kC[0], kC[1], kC[2] - kSize}) == 0.0);
}

TEST_CASE("distance functions at known points") {
    const Vec3 c{1, 2, 3};
    SUBCASE("sphere") {
        CHECK(shapes::sphere_distance(c, c, 2) == doctest::Approx(2));
        CHECK(shapes::sphere_distance({1, 2, 8}, c, 2) == doctest::Approx(3));
        CHECK(shapes::sphere_distance({1, 3, 3}, c, 2) == doctest::Approx(1));
        CHECK(shapes::sphere_distance({3, 2, 3}, c, 2) == 0.0);
    }
    SUBCASE("cube") {
        const double s = 2;  // faces at c +- 1
        CHECK(shapes::cube_distance(c, c, s) == doctest::Approx(1));
        CHECK(shapes::cube_distance({2, 3, 4}, c, s) == 0.0);                          // corner
        CHECK(shapes::cube_distance({1.5, 2, 3}, c, s) == doctest::Approx(0.5));       // inside, nearest face x
        CHECK(shapes::cube_distance({1, 2, 6}, c, s) == doctest::Approx(2));           // above a face
        CHECK(shapes::cube_distance({3, 4, 3}, c, s) == doctest::Approx(std::sqrt(2)));  // beyond an edge
        CHECK(shapes::cube_distance({3, 5, 5}, c, s) == doctest::Approx(std::sqrt(1 + 4 + 1)));  // corner region
    }
    SUBCASE("cylinder") {
        const double r = 2, ht = 6;  // caps at z = 0 and 6
        CHECK(shapes::cylinder_distance(c, c, r, ht) == doctest::Approx(2));          // nearer the side
        CHECK(shapes::cylinder_distance(c, c, 5, ht) == doctest::Approx(3));          // nearer the caps
        CHECK(shapes::cylinder_distance({1, 2, 10}, c, r, ht) == doctest::Approx(4));  // on the axis above
        CHECK(shapes::cylinder_distance({1, 2, 5.5}, c, r, ht) == doctest::Approx(0.5));  // on the axis inside
        CHECK(shapes::cylinder_distance({4, 2, 3}, c, r, ht) == doctest::Approx(1));   // outside the side
        CHECK(shapes::cylinder_distance({1 + 2 + 3, 2, 6 + 4}, c, r, ht) == doctest::Approx(5));  // beyond the rim
        CHECK(shapes::cylinder_distance({3, 2, 6}, c, r, ht) == 0.0);                  // on the rim
        CHECK(shapes::cylinder_distance({2, 2, 0}, c, r, ht) == 0.0);                  // on a cap
    }
}

TEST_CASE("by_name") {
    CHECK(shapes::by_name("sphere", 0.05).size() == shapes::sphere(kC, kSize, 0.05).size());
    CHECK(shapes::by_name("cube", 0.05).size() == shapes::cube(kC, kSize, 0.05).size());
    CHECK(shapes::by_name("cylinder", 0.05).size() == shapes::cylinder(kC, kSize, kSize, 0.05).size());
    CHECK(shapes::by_name("half-sphere", 0.05).size() == shapes::half_sphere(kC, kSize, 0.05).size());
    CHECK(shapes::by_name("cone", 0.05).size() == shapes::two_headed_cone(kC, kSize, 0.7, 0.05).size());
    for (const Vec3& p : shapes::by_name("cone", 0.05))
        for (double v : p) CHECK((v >= 0.15 - 1e-12 && v <= 0.85 + 1e-12));
    try {
        shapes::by_name("torus", 0.05);
        FAIL("no exception");
    } catch (const snvr::ParameterError& e) {
        const std::string what = e.what();
        CHECK(what.find("torus") != std::string::npos);
        for (const char* known : {"sphere", "cube", "cylinder", "half-sphere", "cone"})
            CHECK(what.find(known) != std::string::npos);
    }
    CHECK_THROWS_AS(shapes::sphere(kC, kSize, 0.0), snvr::ParameterError);
    CHECK_THROWS_AS(shapes::cube(kC, -1, 0.1), snvr::ParameterError);
    CHECK_THROWS_AS(shapes::cylinder(kC, 1, 1, std::nan("")), snvr::ParameterError);
}
