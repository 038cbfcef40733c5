// The analytic samplers: points exactly on the surface, no holes wider than the
// spacing, the promised spacing, noise and density, and exact distance functions.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

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
        shapes::by_name("klein-bottle", 0.05);
        FAIL("no exception");
    } catch (const snvr::ParameterError& e) {
        const std::string what = e.what();
        CHECK(what.find("klein-bottle") != std::string::npos);
        for (const std::string& known : shapes::names()) CHECK(what.find(known) != std::string::npos);
    }
    CHECK_THROWS_AS(shapes::sphere(kC, kSize, 0.0), snvr::ParameterError);
    CHECK_THROWS_AS(shapes::cube(kC, -1, 0.1), snvr::ParameterError);
    CHECK_THROWS_AS(shapes::cylinder(kC, 1, 1, std::nan("")), snvr::ParameterError);
}

TEST_CASE("random_by_name: points drawn at random on the surface, uniform by area, by seed") {
    for (const char* name : {"sphere", "torus", "cube", "helicoid"}) {
        CAPTURE(name);
        const PointSet a = shapes::random_by_name(name, 1500, 1);
        REQUIRE(a.size() == 1500);
        const auto exact = shapes::exact_distance_by_name(name, 0.01);
        double farthest = 0;
        for (const Vec3& p : a) farthest = std::max(farthest, std::fabs(exact(p)));
        CHECK(farthest < 1e-9);  // on the surface
        CHECK(shapes::random_by_name(name, 1500, 1) == a);  // the seed decides
        CHECK(shapes::random_by_name(name, 1500, 2) != a);
    }
    // Uniform by area: the sphere's upper half holds half the points (z is uniform on a
    // sphere, Archimedes), within 4 sigma of a binomial count; and no spacing holds them
    // apart (some pair far closer than a blue-noise sampling of as many would allow).
    const PointSet sphere = shapes::random_by_name("sphere", 4000, 7);
    const auto upper = std::count_if(sphere.begin(), sphere.end(), [](const Vec3& p) { return p[2] > 0.5; });
    CHECK(std::abs(double(upper) - 2000.0) < 4 * std::sqrt(1000.0));
    const auto band = std::count_if(sphere.begin(), sphere.end(), [](const Vec3& p) { return std::fabs(p[2] - 0.5) < 0.0875; });
    CHECK(std::abs(double(band) - 1000.0) < 4 * std::sqrt(750.0));  // a quarter of the height, a quarter of the area
    double closest = 1;
    for (std::size_t i = 0; i < sphere.size(); ++i)
        for (std::size_t j = i + 1; j < sphere.size(); ++j) closest = std::min(closest, dist(sphere[i], sphere[j]));
    const double spacing = std::sqrt(4 * M_PI * kSize * kSize / 4000.0);
    CHECK(closest < 0.3 * spacing);
    CHECK_THROWS_AS(shapes::random_by_name("sphere", 0, 1), snvr::ParameterError);
    CHECK_THROWS_AS(shapes::random_by_name("klein-bottle", 10, 1), snvr::ParameterError);
}

// ---- The harder inputs: sheets, Möbius band, helicoid, noisy, varying, torus, LiDAR.

namespace {

// Nearest-neighbour distance of every point: sorted by x, each scan stops once
// the x gap alone exceeds the best so far.
std::vector<double> neighbour_distances(PointSet points) {
    std::sort(points.begin(), points.end());
    std::vector<double> out(points.size(), std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < points.size(); ++i) {
        double& best = out[i];
        for (std::size_t j = i + 1; j < points.size() && points[j][0] - points[i][0] < best; ++j)
            best = std::min(best, dist(points[i], points[j]));
        for (std::size_t j = i; j-- > 0 && points[i][0] - points[j][0] < best;)
            best = std::min(best, dist(points[i], points[j]));
    }
    return out;
}

double median(std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
}

// Offsets a surface point by h along the unit normal n.
Vec3 along(const Vec3& p, const Vec3& n, double h) {
    const double len = std::hypot(n[0], n[1], n[2]);
    return {p[0] + h * n[0] / len, p[1] + h * n[1] / len, p[2] + h * n[2] / len};
}

Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

const double kSpacing = 0.02;

// The by_name defaults, written out: the tests call the samplers directly.
struct NoiseFree {
    std::string name;
    std::function<PointSet(double)> sample;
    std::function<double(const Vec3&)> distance;
};

std::vector<NoiseFree> noise_free() {
    return {
        {"sheets", [](double s) { return shapes::parallel_sheets(kC, 0.7, 0.06, s); },
         [](const Vec3& p) { return shapes::parallel_sheets_distance(p, kC, 0.7, 0.06); }},
        {"mobius", [](double s) { return shapes::mobius_strip(kC, 0.3, 0.25, s); },
         [](const Vec3& p) { return shapes::mobius_strip_distance(p, kC, 0.3, 0.25); }},
        {"helicoid", [](double s) { return shapes::helicoid(kC, 0.35, 0.2, 3, s); },
         [](const Vec3& p) { return shapes::helicoid_distance(p, kC, 0.35, 0.2, 3); }},
        {"torus", [](double s) { return shapes::torus(kC, 0.3, 0.12, s); },
         [](const Vec3& p) { return shapes::torus_distance(p, kC, 0.3, 0.12); }},
        {"noisy-sphere, sigma 0", [](double s) { return shapes::noisy_sphere(kC, kSize, s, 0.0); },
         [](const Vec3& p) { return shapes::sphere_distance(p, kC, kSize); }},
        {"varying-sphere, ratio 1", [](double s) { return shapes::varying_sphere(kC, kSize, s, 1.0); },
         [](const Vec3& p) { return shapes::sphere_distance(p, kC, kSize); }},
        // Lines a spacing apart: the scan becomes a plain grid-like sampling.
        {"lidar, no noise", [](double s) { return shapes::lidar_scan(kC, 0.7, s, s, 0.0); },
         [](const Vec3& p) { return shapes::lidar_distance(p, kC, 0.7); }},
    };
}

}  // namespace

TEST_CASE("new samplers: points on the surface, the promised spacing") {
    for (const NoiseFree& c : noise_free()) {
        CAPTURE(c.name);
        const PointSet points = c.sample(kSpacing);
        REQUIRE(points.size() > 500);
        double worst = 0;
        for (const Vec3& p : points) worst = std::max(worst, c.distance(p));
        CHECK(worst < 1e-9);
        const double m = median(neighbour_distances(points));
        CHECK(m > 0.8 * kSpacing);
        CHECK(m < 1.2 * kSpacing);
    }
}

TEST_CASE("new samplers: no gaps wider than the spacing on the band and the helicoid") {
    // Random surface points from the parametrisations (not uniform in area, which
    // does not matter for a largest gap).
    Rng rng;
    const PointSet mobius = shapes::mobius_strip(kC, 0.3, 0.25, kSpacing);
    const PointSet helix = shapes::helicoid(kC, 0.35, 0.2, 3, kSpacing);
    double worst_mobius = 0, worst_helix = 0;
    for (int n = 0; n < 1000; ++n) {
        double u = rng.uniform(0, 2 * kPi), v = rng.uniform(-0.125, 0.125);
        const Vec3 m{kC[0] + (0.3 + v * std::cos(u / 2)) * std::cos(u), kC[1] + (0.3 + v * std::cos(u / 2)) * std::sin(u),
                     kC[2] + v * std::sin(u / 2)};
        worst_mobius = std::max(worst_mobius, nearest(mobius, m));
        u = rng.uniform(0, 6 * kPi), v = rng.uniform(0, 0.35);
        const Vec3 h{kC[0] + v * std::cos(u), kC[1] + v * std::sin(u), kC[2] + 0.2 * u / (2 * kPi) - 0.3};
        worst_helix = std::max(worst_helix, nearest(helix, h));
    }
    CHECK(worst_mobius <= kSpacing);
    CHECK(worst_helix <= kSpacing);
}

TEST_CASE("lidar scan: dense lines, sparse between them, small range noise") {
    const double s = 0.01;
    const PointSet scan = shapes::lidar_scan(kC, 0.7, s, 4 * s, 0.1 * s, 3);
    // 19 lines 0.7 / 18 apart, each 0.7 to 0.84 long (slopes stay below 0.6).
    CHECK(scan.size() >= 19u * 71);
    CHECK(scan.size() <= 19u * 85);
    const double m = median(neighbour_distances(scan));
    CHECK(m > 0.8 * s);
    CHECK(m < 1.2 * s);
    // Every point lies on one of the lines of constant y (up to the range noise).
    std::vector<std::size_t> per_line(19, 0);
    for (const Vec3& p : scan) {
        const double k = (p[1] - kC[1] + 0.35) / (0.7 / 18);
        CHECK(std::abs(k - std::round(k)) * 0.7 / 18 < 0.5 * s);
        per_line[std::size_t(std::clamp(std::lround(k), 0L, 18L))] += 1;
    }
    for (std::size_t n : per_line) CHECK(n >= 71);
    // Residuals are the range noise projected on the normal: std below sigma.
    double sum2 = 0;
    for (const Vec3& p : scan) sum2 += std::pow(shapes::lidar_distance(p, kC, 0.7), 2);
    const double rms = std::sqrt(sum2 / double(scan.size()));
    CHECK(rms > 0.05 * s);
    CHECK(rms < 0.11 * s);
    // Open: no point outside the terrain's square (beyond noise).
    for (const Vec3& p : scan) CHECK((std::abs(p[0] - kC[0]) <= 0.35 + s && std::abs(p[1] - kC[1]) <= 0.35 + s));
}

TEST_CASE("noisy sphere: residual std is sigma, deterministic with the seed") {
    const double s = 0.01, sigma = 0.005;
    const PointSet noisy = shapes::noisy_sphere(kC, kSize, s, sigma, 7);
    REQUIRE(noisy.size() == shapes::sphere(kC, kSize, s).size());
    double sum = 0, sum2 = 0;
    for (const Vec3& p : noisy) {
        const double residual = dist(p, kC) - kSize;
        sum += residual;
        sum2 += residual * residual;
    }
    const double n = double(noisy.size());
    const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
    CHECK(std::abs(mean) < 0.05 * sigma);
    CHECK(sd == doctest::Approx(sigma).epsilon(0.1));
    CHECK(shapes::noisy_sphere(kC, kSize, s, sigma, 7) == noisy);
    CHECK(shapes::noisy_sphere(kC, kSize, s, sigma, 8) != noisy);
    CHECK(shapes::lidar_scan(kC, 0.7, s, 4 * s, 0.1 * s, 7) == shapes::lidar_scan(kC, 0.7, s, 4 * s, 0.1 * s, 7));
    CHECK(shapes::lidar_scan(kC, 0.7, s, 4 * s, 0.1 * s, 7) != shapes::lidar_scan(kC, 0.7, s, 4 * s, 0.1 * s, 8));
    // By name: sigma 0.3 spacings, seed 1.
    CHECK(shapes::by_name("noisy-sphere", s) == shapes::noisy_sphere(kC, kSize, s, 0.3 * s, 1));
}

TEST_CASE("varying sphere: points per area fall 10x from the top pole to the bottom") {
    const double s = 0.005, ratio = 10;
    const PointSet points = shapes::varying_sphere(kC, kSize, s, ratio);
    for (const Vec3& p : points) CHECK(shapes::sphere_distance(p, kC, kSize) < 1e-12);
    // Caps of equal area (unit height delta) at each pole: the profile exp(-a (1 - z))
    // predicts the ratio of their counts exactly, ratio * exp(-a delta).
    const double delta = 0.1, a = std::log(ratio) / 2;
    PointSet top, bottom;
    for (const Vec3& p : points) {
        const double z = (p[2] - kC[2]) / kSize;
        if (z >= 1 - delta) top.push_back(p);
        if (z <= -1 + delta) bottom.push_back(p);
    }
    REQUIRE(bottom.size() > 100);
    const double counts = double(top.size()) / double(bottom.size());
    CHECK(counts == doctest::Approx(ratio * std::exp(-a * delta)).epsilon(0.05));
    // Spacing near the poles: s at the top, s sqrt(ratio) at the bottom.
    auto median_near = [&](const PointSet& cap) {
        std::vector<double> d;
        for (const Vec3& p : cap) {
            double best = std::numeric_limits<double>::infinity();
            for (const Vec3& q : points)
                if (&q != &p && !(q == p)) best = std::min(best, dist(p, q));
            d.push_back(best);
        }
        return median(d);
    };
    const double dense = median_near(top), sparse = median_near(bottom);
    CHECK(dense == doctest::Approx(s).epsilon(0.2));
    CHECK(sparse == doctest::Approx(s * std::sqrt(ratio)).epsilon(0.2));
    // Density is the inverse square of the spacing: about 10x.
    CHECK(std::pow(sparse / dense, 2) == doctest::Approx(ratio).epsilon(0.3));
    // Ratio 1 is the Fibonacci sphere.
    CHECK(shapes::varying_sphere(kC, kSize, 0.05, 1.0).size() == shapes::sphere(kC, kSize, 0.05).size());
}

TEST_CASE("new distance functions at known points") {
    SUBCASE("sheets") {
        const double size = 2, gap = 0.5;  // squares |x|, |y| <= 1 at z = -+0.25
        CHECK(shapes::parallel_sheets_distance(kC, kC, size, gap) == doctest::Approx(0.25));
        CHECK(shapes::parallel_sheets_distance({0.5, 0.5, 0.75}, kC, size, gap) == 0.0);
        CHECK(shapes::parallel_sheets_distance({0.6, 0.5, 0.65}, kC, size, gap) == doctest::Approx(0.1));
        CHECK(shapes::parallel_sheets_distance({0.5, 0.5, 5.75}, kC, size, gap) == doctest::Approx(5));
        CHECK(shapes::parallel_sheets_distance({2.5, 0.5, 3.75}, kC, size, gap) == doctest::Approx(std::hypot(1, 3)));
        CHECK(shapes::parallel_sheets_distance({2.5, 3.5, 1.25}, kC, size, gap) == doctest::Approx(std::hypot(1, 2, 0.5)));
    }
    SUBCASE("möbius band") {
        const double R = 0.3, w = 0.25;
        // From the centre: the inner edge's nearest point is at u = 0, R - w/2 away.
        CHECK(shapes::mobius_strip_distance(kC, kC, R, w) == doctest::Approx(R - w / 2).epsilon(1e-12));
        // On the centre circle at u = 0 the ruling is along x, the normal along z; the
        // principal curvature radii there are 2R, far beyond these offsets.
        for (double h : {1e-6, 0.01, 0.05})
            CHECK(shapes::mobius_strip_distance({kC[0] + R, kC[1], kC[2] + h}, kC, R, w) ==
                  doctest::Approx(h).epsilon(1e-9));
        // Beyond the outer edge, in the ruling's direction.
        CHECK(shapes::mobius_strip_distance({kC[0] + R + w / 2 + 0.1, kC[1], kC[2]}, kC, R, w) ==
              doctest::Approx(0.1).epsilon(1e-9));
        // On the surface at a general (u, v), and off it along the normal.
        const double u = 2.2, v = -0.07;
        auto x = [&](double uu, double vv) {
            return Vec3{kC[0] + (R + vv * std::cos(uu / 2)) * std::cos(uu), kC[1] + (R + vv * std::cos(uu / 2)) * std::sin(uu),
                        kC[2] + vv * std::sin(uu / 2)};
        };
        const Vec3 p = x(u, v);
        CHECK(shapes::mobius_strip_distance(p, kC, R, w) < 1e-12);
        const double e = 1e-6;
        const Vec3 ahead = x(u + e, v), behind = x(u - e, v);
        const Vec3 xu{(ahead[0] - behind[0]) / (2 * e), (ahead[1] - behind[1]) / (2 * e), (ahead[2] - behind[2]) / (2 * e)};
        const Vec3 xv{std::cos(u / 2) * std::cos(u), std::cos(u / 2) * std::sin(u), std::sin(u / 2)};
        // The finite-difference normal is good to 1e-10, so is the offset point.
        CHECK(shapes::mobius_strip_distance(along(p, cross(xu, xv), 0.02), kC, R, w) ==
              doctest::Approx(0.02).epsilon(1e-7));
    }
    SUBCASE("helicoid") {
        const double radius = 0.35, pitch = 0.2, turns = 3, b = pitch / (2 * kPi);
        CHECK(shapes::helicoid_distance(kC, kC, radius, pitch, turns) == 0.0);  // the axis is on it
        CHECK(shapes::helicoid_distance({kC[0], kC[1], kC[2] + 0.3 + 1}, kC, radius, pitch, turns) ==
              doctest::Approx(1));
        // Along the normal (-b sin u, b cos u, -v) at a middle turn; the curvature
        // radius (b^2 + v^2) / b is 1.3 and the next sheet 0.2 away vertically.
        const double u = 2 * kPi * 1.3, v = 0.2;
        const Vec3 p{kC[0] + v * std::cos(u), kC[1] + v * std::sin(u), kC[2] + b * u - 0.3};
        CHECK(shapes::helicoid_distance(p, kC, radius, pitch, turns) < 1e-12);
        for (double h : {0.01, -0.03})
            CHECK(shapes::helicoid_distance(along(p, {-b * std::sin(u), b * std::cos(u), -v}, h), kC, radius, pitch, turns) ==
                  doctest::Approx(std::abs(h)).epsilon(1e-9));
        // Beyond the rim, radially.
        CHECK(shapes::helicoid_distance({kC[0] + 0.45 * std::cos(u), kC[1] + 0.45 * std::sin(u), p[2]}, kC, radius, pitch,
                                        turns) == doctest::Approx(0.1).epsilon(1e-9));
    }
    SUBCASE("torus") {
        const double R = 0.3, r = 0.12;
        CHECK(shapes::torus_distance(kC, kC, R, r) == doctest::Approx(R - r));
        CHECK(shapes::torus_distance({0.8, 0.5, 0.5}, kC, R, r) == doctest::Approx(r));
        CHECK(shapes::torus_distance({0.5, 0.5 - R - r, 0.5}, kC, R, r) == doctest::Approx(0).epsilon(1e-15));
        CHECK(shapes::torus_distance({0.5, 0.5, 1.5}, kC, R, r) == doctest::Approx(std::hypot(R, 1.0) - r));
    }
    SUBCASE("lidar terrain") {
        const double size = 0.7, half = 0.35;
        auto surface = [&](double x, double y) { return Vec3{kC[0] + x, kC[1] + y, kC[2] + shapes::lidar_height(x, y, size)}; };
        const double e = 1e-6;
        for (const auto& [x, y] : {std::pair{0.1, -0.05}, std::pair{-0.14, -0.1}, std::pair{0.0, 0.2}}) {
            const Vec3 p = surface(x, y);
            CHECK(shapes::lidar_distance(p, kC, size) < 1e-12);
            const double fx = (shapes::lidar_height(x + e, y, size) - shapes::lidar_height(x - e, y, size)) / (2 * e);
            const double fy = (shapes::lidar_height(x, y + e, size) - shapes::lidar_height(x, y - e, size)) / (2 * e);
            for (double h : {0.01, -0.02})
                CHECK(shapes::lidar_distance(along(p, {-fx, -fy, 1}, h), kC, size) == doctest::Approx(std::abs(h)).epsilon(1e-7));
        }
        // Off the open edge x = half, straight out along x: the edge point is nearest.
        const Vec3 edge = surface(half, 0.1);
        CHECK(shapes::lidar_distance({edge[0] + 0.05, edge[1], edge[2]}, kC, size) == doctest::Approx(0.05).epsilon(1e-9));
        // The bumps are real: the terrain is not flat.
        CHECK(std::abs(shapes::lidar_height(-0.14, -0.105, size)) > 0.05);
    }
    SUBCASE("the open half sphere and the cone") {
        CHECK(shapes::half_sphere_distance({0.5, 0.5, 0.4}, kC, kSize) == doctest::Approx(std::hypot(kSize, 0.1)));
        CHECK(shapes::half_sphere_distance({0.5, 0.5, 0.6}, kC, kSize) == doctest::Approx(kSize - 0.1));
        Rng rng;
        for (int n = 0; n < 100; ++n) {
            const Vec3 p{rng.uniform(), rng.uniform(), rng.uniform()};
            CHECK(shapes::two_headed_cone_distance(p, kC, kSize, 0.7) == doctest::Approx(cone_distance(p, kC, kSize, 0.7)));
        }
    }
}

TEST_CASE("new shapes by name, with exact distances") {
    const std::vector<std::string> added = {"sheets", "mobius", "helicoid", "noisy-sphere", "varying-sphere", "torus", "lidar"};
    const std::vector<std::string> all = shapes::names();
    for (const std::string& name : added) CHECK(std::find(all.begin(), all.end(), name) != all.end());
    for (const std::string& name : all) {
        CAPTURE(name);
        const PointSet points = shapes::by_name(name, 0.03);
        REQUIRE(points.size() > 100);
        const auto distance = shapes::exact_distance_by_name(name, 0.03);
        double worst = 0;
        for (const Vec3& p : points) {
            worst = std::max(worst, distance(p));
            for (double v : p) CHECK((v > 0 && v < 1));  // inside the unit box
        }
        const bool noisy = name == "noisy-sphere" || name == "lidar";
        CHECK(worst < (noisy ? 0.03 * 1.5 : 1e-9));
    }
    CHECK(shapes::exact_distance_by_name("torus", 0.03)(kC) == doctest::Approx(0.3 - 0.12));
    CHECK(shapes::exact_distance_by_name("sheets", 0.03)(kC) == doctest::Approx(0.03));
    CHECK(shapes::exact_distance_by_name("noisy-sphere", 0.03)(kC) == doctest::Approx(kSize));
    CHECK_THROWS_AS(shapes::exact_distance_by_name("klein-bottle", 0.03), snvr::ParameterError);
    CHECK_THROWS_AS(shapes::exact_distance_by_name("torus", -1), snvr::ParameterError);
}

TEST_CASE("new samplers refuse bad arguments") {
    using snvr::ParameterError;
    CHECK_THROWS_AS(shapes::parallel_sheets(kC, 0.7, 0.06, -0.01), ParameterError);
    CHECK_THROWS_AS(shapes::parallel_sheets(kC, 0.7, 0.0, 0.01), ParameterError);
    CHECK_THROWS_AS(shapes::mobius_strip(kC, 0.3, 0.31, 0.01), ParameterError);  // width > R
    CHECK_THROWS_AS(shapes::mobius_strip(kC, 0.3, -0.1, 0.01), ParameterError);
    CHECK_THROWS_AS(shapes::mobius_strip_distance(kC, kC, 0.3, 0.4), ParameterError);
    CHECK_THROWS_AS(shapes::helicoid(kC, 0.35, 0.0, 3, 0.01), ParameterError);
    CHECK_THROWS_AS(shapes::helicoid(kC, 0.35, 0.2, -1, 0.01), ParameterError);
    CHECK_THROWS_AS(shapes::noisy_sphere(kC, kSize, 0.01, -0.1), ParameterError);
    CHECK_THROWS_AS(shapes::noisy_sphere(kC, kSize, -0.01, 0.1), ParameterError);
    CHECK_THROWS_AS(shapes::varying_sphere(kC, kSize, 0.01, 0.5), ParameterError);
    CHECK_THROWS_AS(shapes::varying_sphere(kC, kSize, 0.01, std::nan("")), ParameterError);
    CHECK_THROWS_AS(shapes::torus(kC, 0.3, 0.3, 0.01), ParameterError);  // horn torus
    CHECK_THROWS_AS(shapes::torus(kC, 0.3, 0.1, 0.0), ParameterError);
    CHECK_THROWS_AS(shapes::lidar_scan(kC, 0.7, 0.01, 0.0, 0.001), ParameterError);
    CHECK_THROWS_AS(shapes::lidar_scan(kC, 0.7, 0.01, 0.04, -0.001), ParameterError);
    CHECK_THROWS_AS(shapes::lidar_scan({0, std::nan(""), 0}, 0.7, 0.01, 0.04, 0.001), ParameterError);
    CHECK_THROWS_AS(shapes::by_name("mobius", -0.01), ParameterError);
    CHECK_THROWS_AS(shapes::by_name("lidar", 0.0), ParameterError);
    CHECK_THROWS_AS(shapes::torus(kC, 0.3, 0.1, 1e-6), snvr::ResourceError);  // 7e10 points
}

TEST_CASE("numerical distances against brute force over a fine parameter grid") {
    // The searches must find the global minimum: never above the brute-force
    // minimum, and below it by no more than the grid's resolution.
    Rng rng;
    struct Surface {
        std::string name;
        std::function<Vec3(double, double)> point;  // (s, t) in [0, 1]^2
        std::function<double(const Vec3&)> distance;
    };
    const double R = 0.3, w = 0.25, radius = 0.35, pitch = 0.2, turns = 3;
    const std::vector<Surface> surfaces = {
        {"mobius",
         [&](double s, double t) {
             const double u = 2 * kPi * s, v = w * (t - 0.5);
             return Vec3{kC[0] + (R + v * std::cos(u / 2)) * std::cos(u), kC[1] + (R + v * std::cos(u / 2)) * std::sin(u),
                         kC[2] + v * std::sin(u / 2)};
         },
         [&](const Vec3& p) { return shapes::mobius_strip_distance(p, kC, R, w); }},
        {"helicoid",
         [&](double s, double t) {
             const double u = 2 * kPi * turns * s, v = radius * t;
             return Vec3{kC[0] + v * std::cos(u), kC[1] + v * std::sin(u), kC[2] + pitch * u / (2 * kPi) - pitch * turns / 2};
         },
         [&](const Vec3& p) { return shapes::helicoid_distance(p, kC, radius, pitch, turns); }},
        {"lidar",
         [&](double s, double t) {
             const double x = 0.7 * (s - 0.5), y = 0.7 * (t - 0.5);
             return Vec3{kC[0] + x, kC[1] + y, kC[2] + shapes::lidar_height(x, y, 0.7)};
         },
         [&](const Vec3& p) { return shapes::lidar_distance(p, kC, 0.7); }},
    };
    const long ns = 1200, nt = 120;
    for (const Surface& surface : surfaces) {
        CAPTURE(surface.name);
        PointSet grid;
        for (long i = 0; i <= ns; ++i)
            for (long j = 0; j <= nt; ++j) grid.push_back(surface.point(double(i) / ns, double(j) / nt));
        for (int n = 0; n < 40; ++n) {
            // Half near the surface, half anywhere in the unit box.
            Vec3 q{rng.uniform(), rng.uniform(), rng.uniform()};
            if (n % 2 == 0) {
                const Vec3 on = surface.point(rng.uniform(), rng.uniform());
                for (int a = 0; a < 3; ++a) q[a] = on[a] + rng.uniform(-0.03, 0.03);
            }
            const double brute = nearest(grid, q), found = surface.distance(q);
            CHECK(found <= brute + 1e-12);
            CHECK(found >= brute - 0.003);
        }
    }
}
