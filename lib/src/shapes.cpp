// Point samplers and exact distances of the paper's analytic test shapes.
#include "snvr/shapes.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

#include "snvr/error.hpp"

namespace snvr::shapes {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Refuse absurd requests (a tiny spacing) before allocating: 2e8 points is 4.8 GB.
constexpr double kMaxPoints = 2e8;

void require_positive(const char* what, double value) {
    if (!(std::isfinite(value) && value > 0))
        throw ParameterError("shapes: " + std::string(what) + " must be positive and finite, got " +
                             std::to_string(value));
}

void require_finite(const Vec3& c) {
    for (double v : c)
        if (!std::isfinite(v)) throw ParameterError("shapes: centre must be finite");
}

void require_count(double estimate) {
    if (!(estimate <= kMaxPoints))
        throw ResourceError("shapes: spacing too small: about " + std::to_string(estimate) +
                            " points requested (limit " + std::to_string(kMaxPoints) + ")");
}

// Number of intervals of at most `spacing` that cover `length` (at least 1).
long intervals(double length, double spacing) {
    return std::max(1L, static_cast<long>(std::ceil(length / spacing - 1e-9)));
}

// Appends a horizontal circle of radius rho at height z around c, with a point count
// that keeps the arc between neighbours at most `spacing`; rho == 0 gives one point.
// Odd rings are turned by half a step so neighbouring rings interleave.
void add_ring(PointSet& out, const Vec3& c, double rho, double z, double spacing, long ring) {
    if (rho == 0) {
        out.push_back({c[0], c[1], z});
        return;
    }
    const long m = intervals(2 * kPi * rho, spacing);
    const double shift = (ring % 2) ? 0.5 : 0.0;
    for (long q = 0; q < m; ++q) {
        const double theta = 2 * kPi * (double(q) + shift) / double(m);
        out.push_back({c[0] + rho * std::cos(theta), c[1] + rho * std::sin(theta), z});
    }
}

// Position t in [0, 1] along [lo, hi] that hits both ends exactly.
double lerp(double lo, double hi, long j, long n) {
    if (j == 0) return lo;
    if (j == n) return hi;
    return lo + (hi - lo) * (double(j) / double(n));
}

// Fibonacci lattice on the sphere, keeping the points whose unit z passes `keep`.
template <class Keep>
PointSet fibonacci(const Vec3& c, double r, double spacing, Keep keep) {
    require_finite(c);
    require_positive("radius", r);
    require_positive("spacing", spacing);
    const double estimate = std::ceil(4 * kPi * r * r / (spacing * spacing));
    require_count(estimate);
    const long n = std::max(1L, static_cast<long>(estimate));
    const double golden = kPi * (3 - std::sqrt(5.0));
    PointSet out;
    out.reserve(std::size_t(n));
    for (long i = 0; i < n; ++i) {
        const double z = 1 - (2 * double(i) + 1) / double(n);
        if (!keep(z)) continue;
        const double rho = std::sqrt(std::max(0.0, 1 - z * z));
        const double theta = golden * double(i);
        out.push_back({c[0] + r * rho * std::cos(theta), c[1] + r * rho * std::sin(theta), c[2] + r * z});
    }
    return out;
}

// The arguments shared by the cylinder and the cone.
void require_solid_of_revolution(const Vec3& c, double r, double ht, double spacing) {
    require_finite(c);
    require_positive("radius", r);
    require_positive("height", ht);
    require_positive("spacing", spacing);
}

}  // namespace

PointSet sphere(const Vec3& c, double r, double spacing) {
    return fibonacci(c, r, spacing, [](double) { return true; });
}

PointSet half_sphere(const Vec3& c, double r, double spacing) {
    return fibonacci(c, r, spacing, [](double z) { return z >= 0; });
}

PointSet cube(const Vec3& c, double s, double spacing) {
    require_finite(c);
    require_positive("side", s);
    require_positive("spacing", spacing);
    const double per_edge = std::ceil(s / spacing) + 1;
    require_count(6 * per_edge * per_edge);
    const long n = intervals(s, spacing);
    const double h = s / 2;
    PointSet out;
    out.reserve(std::size_t((n + 1) * (n + 1) * (n + 1) - (n - 1) * (n - 1) * (n - 1)));
    // The lattice points of the (n+1)^3 grid with at least one index on a face:
    // every face is a full grid and shared edges and corners appear once.
    for (long k = 0; k <= n; ++k)
        for (long j = 0; j <= n; ++j)
            for (long i = 0; i <= n; ++i) {
                const bool on_face = i == 0 || i == n || j == 0 || j == n || k == 0 || k == n;
                if (!on_face) continue;
                out.push_back({lerp(c[0] - h, c[0] + h, i, n), lerp(c[1] - h, c[1] + h, j, n),
                               lerp(c[2] - h, c[2] + h, k, n)});
            }
    return out;
}

PointSet cylinder(const Vec3& c, double r, double ht, double spacing) {
    require_solid_of_revolution(c, r, ht, spacing);
    require_count((2 * kPi * r * ht + 2 * kPi * r * r) / (spacing * spacing) * 2 + 16);
    const long nz = intervals(ht, spacing);
    const long nr = intervals(r, spacing);
    const double bottom = c[2] - ht / 2, top = c[2] + ht / 2;
    PointSet out;
    // Side, rims included.
    for (long k = 0; k <= nz; ++k) add_ring(out, c, r, lerp(bottom, top, k, nz), spacing, k);
    // Caps: concentric rings inside the rim (which the side already holds), centre first.
    for (double z : {bottom, top})
        for (long j = 0; j < nr; ++j) add_ring(out, c, r * double(j) / double(nr), z, spacing, j + 1);
    return out;
}

PointSet two_headed_cone(const Vec3& c, double r, double ht, double spacing) {
    require_solid_of_revolution(c, r, ht, spacing);
    const double a = ht / 2;
    const double slant = std::hypot(r, a);
    require_count(2 * kPi * r * slant / (spacing * spacing) * 2 + 16);
    // Rings equally spaced along the slant; the shared base circle once, apexes last.
    const long n = intervals(slant, spacing);
    PointSet out;
    add_ring(out, c, r, c[2], spacing, 0);
    for (double sign : {1.0, -1.0})
        for (long j = 1; j <= n; ++j) {
            const double t = double(j) / double(n);
            const double rho = j == n ? 0.0 : r * (1 - t);
            add_ring(out, c, rho, c[2] + sign * lerp(0, a, j, n), spacing, j);
        }
    return out;
}

double sphere_distance(const Vec3& p, const Vec3& c, double r) {
    return std::abs(std::hypot(p[0] - c[0], p[1] - c[1], p[2] - c[2]) - r);
}

double cube_distance(const Vec3& p, const Vec3& c, double s) {
    // q_i > 0: outside the slab of axis i by q_i.
    double q[3], outside2 = 0, largest = -INFINITY;
    for (int a = 0; a < 3; ++a) {
        q[a] = std::abs(p[a] - c[a]) - s / 2;
        outside2 += q[a] > 0 ? q[a] * q[a] : 0;
        largest = std::max(largest, q[a]);
    }
    // Inside, the nearest face is the one with the least clearance.
    return largest > 0 ? std::sqrt(outside2) : -largest;
}

double cylinder_distance(const Vec3& p, const Vec3& c, double r, double ht) {
    // The same as the box, in the (radius, z) half-plane.
    const double dr = std::hypot(p[0] - c[0], p[1] - c[1]) - r;
    const double dz = std::abs(p[2] - c[2]) - ht / 2;
    if (dr <= 0 && dz <= 0) return -std::max(dr, dz);
    return std::hypot(std::max(dr, 0.0), std::max(dz, 0.0));
}

PointSet by_name(const std::string& name, double spacing) {
    const Vec3 c{0.5, 0.5, 0.5};
    const double size = 0.35;
    if (name == "sphere") return sphere(c, size, spacing);
    if (name == "cube") return cube(c, size, spacing);
    if (name == "cylinder") return cylinder(c, size, size, spacing);
    if (name == "half-sphere") return half_sphere(c, size, spacing);
    if (name == "cone") return two_headed_cone(c, size, 2 * size, spacing);
    throw ParameterError("unknown shape '" + name +
                         "' (known: sphere, cube, cylinder, half-sphere, cone)");
}

}  // namespace snvr::shapes
