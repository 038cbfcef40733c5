// Point samplers and exact distances of the paper's analytic test shapes and of
// the harder inputs for judging reconstruction quality.
#include "snvr/shapes.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>
#include <string>
#include <utility>
#include <vector>

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

// Intervals per edge of a square lattice of side `size`, after checking spacing and
// refusing `squares` such lattices if they would hold too many points.
long square_intervals(double size, double spacing, double squares) {
    require_positive("spacing", spacing);
    const double per_edge = std::ceil(size / spacing) + 1;
    require_count(squares * per_edge * per_edge);
    return intervals(size, spacing);
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

// Golden-angle spiral of `estimate` points (at least one) on the sphere (c, r): point
// i of n at unit height height(i, n), kept when that height passes `keep`. The plain
// and the varying-density spheres differ only in the heights.
template <class Height, class Keep>
PointSet golden_spiral(const Vec3& c, double r, double estimate, Height height, Keep keep) {
    require_count(estimate);
    const long n = std::max(1L, static_cast<long>(estimate));
    const double golden = kPi * (3 - std::sqrt(5.0));
    PointSet out;
    out.reserve(std::size_t(n));
    for (long i = 0; i < n; ++i) {
        const double z = height(i, n);
        if (!keep(z)) continue;
        const double rho = std::sqrt(std::max(0.0, 1 - z * z));
        const double theta = golden * double(i);
        out.push_back({c[0] + r * rho * std::cos(theta), c[1] + r * rho * std::sin(theta), c[2] + r * z});
    }
    return out;
}

// Fibonacci lattice on the sphere, keeping the points whose unit z passes `keep`.
template <class Keep>
PointSet fibonacci(const Vec3& c, double r, double spacing, Keep keep) {
    require_finite(c);
    require_positive("radius", r);
    require_positive("spacing", spacing);
    const double estimate = std::ceil(4 * kPi * r * r / (spacing * spacing));
    return golden_spiral(
        c, r, estimate, [](long i, long n) { return 1 - (2 * double(i) + 1) / double(n); }, keep);
}

// The arguments shared by the cylinder and the cone.
void require_solid_of_revolution(const Vec3& c, double r, double ht, double spacing) {
    require_finite(c);
    require_positive("radius", r);
    require_positive("height", ht);
    require_positive("spacing", spacing);
}

void require_non_negative(const char* what, double value) {
    if (!(std::isfinite(value) && value >= 0))
        throw ParameterError("shapes: " + std::string(what) + " must be non-negative and finite, got " +
                             std::to_string(value));
}

Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double norm(const Vec3& a) { return std::hypot(a[0], a[1], a[2]); }

// Normal deviates by Box-Muller from mt19937_64's raw bits: std::normal_distribution
// differs between standard libraries, and the samples must not.
class Gaussian {
public:
    explicit Gaussian(std::uint64_t seed) : gen_(seed) {}
    double operator()() {
        if (has_spare_) {
            has_spare_ = false;
            return spare_;
        }
        const double radius = std::sqrt(-2 * std::log(uniform_open()));
        const double angle = 2 * kPi * uniform_open();
        spare_ = radius * std::sin(angle);
        has_spare_ = true;
        return radius * std::cos(angle);
    }

private:
    double uniform_open() { return (double(gen_() >> 11) + 0.5) * 0x1p-53; }  // in (0, 1)
    std::mt19937_64 gen_;
    double spare_ = 0;
    bool has_spare_ = false;
};

// Parameters of the curve point(t), t in [t0, t1], equally spaced in arc length
// with steps of at most `spacing`; a closed curve (point(t1) == point(t0)) leaves
// out t1. Lengths come from a polyline 16 times finer than the output.
template <class Curve>
std::vector<double> arc_length_params(const Curve& point, double t0, double t1, double spacing, bool closed) {
    std::vector<double> cumulative;
    auto tabulate = [&](long segments) {
        cumulative.assign(std::size_t(segments + 1), 0.0);
        Vec3 prev = point(t0);
        for (long i = 1; i <= segments; ++i) {
            const Vec3 cur = point(lerp(t0, t1, i, segments));
            cumulative[std::size_t(i)] = cumulative[std::size_t(i - 1)] + norm(sub(cur, prev));
            prev = cur;
        }
        return cumulative.back();
    };
    const long coarse = 1024;
    const long m0 = intervals(tabulate(coarse), spacing);
    const long segments = std::max(coarse, 16 * m0);
    const double length = tabulate(segments);
    const long m = intervals(length, spacing);
    std::vector<double> out;
    out.reserve(std::size_t(m + 1));
    long j = 0;
    for (long i = 0; i <= (closed ? m - 1 : m); ++i) {
        if (i == 0 || i == m) {
            out.push_back(i == 0 ? t0 : t1);
            continue;
        }
        const double s = length * double(i) / double(m);
        while (j + 1 < segments && cumulative[std::size_t(j + 1)] < s) ++j;
        const double a = cumulative[std::size_t(j)], b = cumulative[std::size_t(j + 1)];
        const double frac = b > a ? std::clamp((s - a) / (b - a), 0.0, 1.0) : 0.0;
        out.push_back(t0 + (t1 - t0) * ((double(j) + frac) / double(segments)));
    }
    return out;
}

// Minimum of f over [a, b] by golden section, down to rounding in the argument.
template <class F>
double golden_min(const F& f, double a, double b) {
    const double inv_phi = (std::sqrt(5.0) - 1) / 2;
    double x1 = b - inv_phi * (b - a), x2 = a + inv_phi * (b - a);
    double f1 = f(x1), f2 = f(x2);
    for (int it = 0; it < 200 && b - a > 1e-15 * (std::abs(a) + std::abs(b)); ++it) {
        if (f1 <= f2) {
            b = x2, x2 = x1, f2 = f1;
            x1 = b - inv_phi * (b - a), f1 = f(x1);
        } else {
            a = x1, x1 = x2, f1 = f2;
            x2 = a + inv_phi * (b - a), f2 = f(x2);
        }
    }
    return std::min(f1, f2);
}

// A ruling of a ruled surface: the line base + v dir, |dir| = 1.
struct Ruling {
    Vec3 base, dir;
};

// Distance from p to the ruled surface x(u, v) = base(u) + v dir(u), u in [u0, u1]
// (periodic or not), v in [v0, v1]. For a fixed u the nearest v is a clamped
// projection, so only g(u), the distance to one ruling, needs minimising over u.
// g is Lipschitz with the largest |dx/du|, `lipschitz`: a sampled local minimum
// hides nothing deeper than lipschitz * h below itself, so the sampled minima that
// could still beat the best are refined by golden section over their neighbours.
template <class Rulings>
double ruled_distance(const Vec3& p, const Rulings& ruling, double u0, double u1, bool periodic, double v0,
                      double v1, double lipschitz, long samples) {
    auto g = [&](double u) {
        const Ruling r = ruling(u);
        const Vec3 w = sub(p, r.base);
        const double t = std::clamp(dot(w, r.dir), v0, v1);
        return norm({w[0] - t * r.dir[0], w[1] - t * r.dir[1], w[2] - t * r.dir[2]});
    };
    const long n = samples;
    const double h = (u1 - u0) / double(n);
    const long count = periodic ? n : n + 1;  // u1 repeats u0 on a periodic range
    std::vector<double> value(static_cast<std::size_t>(count));
    for (long i = 0; i < count; ++i) value[std::size_t(i)] = g(lerp(u0, u1, i, n));
    double best = *std::min_element(value.begin(), value.end());
    std::vector<std::pair<double, long>> minima;
    for (long i = 0; i < count; ++i) {
        const long prev = periodic ? (i + count - 1) % count : i - 1;
        const long next = periodic ? (i + 1) % count : i + 1;
        const double here = value[std::size_t(i)];
        if ((prev < 0 || here <= value[std::size_t(prev)]) && (next >= count || here <= value[std::size_t(next)]))
            minima.push_back({here, i});
    }
    std::sort(minima.begin(), minima.end());
    for (const auto& [here, i] : minima) {
        if (here - lipschitz * h >= best) break;  // sorted: no later one can win either
        double a = u0 + double(i - 1) * h, b = u0 + double(i + 1) * h;
        if (!periodic) a = std::max(a, u0), b = std::min(b, u1);
        best = std::min(best, golden_min(g, a, b));
    }
    return best;
}

Ruling mobius_ruling(const Vec3& c, double R, double u) {
    // The half angle's sine and cosine give the whole angle's: half the calls to the
    // trigonometric functions, which dominate the distance search.
    const double ch = std::cos(u / 2), sh = std::sin(u / 2);
    const double cu = 1 - 2 * sh * sh, su = 2 * sh * ch;
    return {{c[0] + R * cu, c[1] + R * su, c[2]}, {ch * cu, ch * su, sh}};
}

Ruling helicoid_ruling(const Vec3& c, double pitch, double turns, double u) {
    const double rise = pitch / (2 * kPi);
    return {{c[0], c[1], c[2] + rise * u - pitch * turns / 2}, {std::cos(u), std::sin(u), 0.0}};
}

void require_mobius(const Vec3& c, double R, double width) {
    require_finite(c);
    require_positive("radius", R);
    require_positive("width", width);
    // Wider rulings reach the axis and the band would cut through itself.
    if (width > R)
        throw ParameterError("shapes: Mobius strip width " + std::to_string(width) + " must not exceed R " +
                             std::to_string(R));
}

void require_helicoid(const Vec3& c, double radius, double pitch, double turns) {
    require_finite(c);
    require_positive("radius", radius);
    require_positive("pitch", pitch);
    require_positive("turns", turns);
}

void require_torus(const Vec3& c, double R, double r) {
    require_finite(c);
    require_positive("radius", R);
    require_positive("tube radius", r);
    if (!(r < R))  // a horn or spindle torus touches or cuts itself
        throw ParameterError("shapes: torus tube radius " + std::to_string(r) + " must be below R " +
                             std::to_string(R));
}

// The terrain of lidar_scan as Gaussian bumps (negative: dips), in units of its side.
struct Bump {
    double x, y, height, width;
};
constexpr Bump kBumps[] = {{-0.20, -0.15, 0.10, 0.15},
                           {0.22, 0.10, 0.08, 0.12},
                           {0.00, 0.28, -0.06, 0.10},
                           {-0.25, 0.25, 0.05, 0.08},
                           {0.15, -0.30, -0.07, 0.13}};

// Height and its first and second derivatives at (x, y), relative to the centre.
struct Terrain {
    double f = 0, fx = 0, fy = 0, fxx = 0, fxy = 0, fyy = 0;
};

Terrain terrain(double x, double y, double size) {
    Terrain t;
    for (const Bump& b : kBumps) {
        const double dx = x - b.x * size, dy = y - b.y * size, w2 = b.width * size * b.width * size;
        const double e = b.height * size * std::exp(-(dx * dx + dy * dy) / (2 * w2));
        t.f += e;
        t.fx -= e * dx / w2;
        t.fy -= e * dy / w2;
        t.fxx += e * (dx * dx / w2 - 1) / w2;
        t.fxy += e * dx * dy / (w2 * w2);
        t.fyy += e * (dy * dy / w2 - 1) / w2;
    }
    return t;
}

// Half the squared distance from q (relative to the centre) to the nearest point
// of the terrain near (x, y), by Newton's method on (x, y) kept in the square: a
// coordinate on the edge whose gradient points out of the square stays there.
double terrain_newton(const Vec3& q, double x, double y, double size) {
    const double half = size / 2;
    auto energy = [&](double px, double py) {
        const double dz = q[2] - terrain(px, py, size).f;
        return ((q[0] - px) * (q[0] - px) + (q[1] - py) * (q[1] - py) + dz * dz) / 2;
    };
    double e0 = energy(x, y);
    for (int it = 0; it < 60; ++it) {
        const Terrain t = terrain(x, y, size);
        const double e = q[2] - t.f;
        const double gx = -(q[0] - x) - e * t.fx, gy = -(q[1] - y) - e * t.fy;
        const double hxx = 1 + t.fx * t.fx - e * t.fxx, hxy = t.fx * t.fy - e * t.fxy;
        const double hyy = 1 + t.fy * t.fy - e * t.fyy;
        const bool fix_x = (x <= -half && gx > 0) || (x >= half && gx < 0);
        const bool fix_y = (y <= -half && gy > 0) || (y >= half && gy < 0);
        double sx = 0, sy = 0;
        if (!fix_x && !fix_y) {
            const double det = hxx * hyy - hxy * hxy;
            if (hxx > 0 && det > 0) {
                sx = -(hyy * gx - hxy * gy) / det;
                sy = -(hxx * gy - hxy * gx) / det;
            } else {  // not convex here: steepest descent
                sx = -gx, sy = -gy;
            }
        } else if (!fix_x) {
            sx = hxx > 0 ? -gx / hxx : -gx;
        } else if (!fix_y) {
            sy = hyy > 0 ? -gy / hyy : -gy;
        }
        // Backtrack until the distance does not grow.
        bool moved = false;
        double step = 1;
        for (int k = 0; k < 60; ++k, step /= 2) {
            const double nx = std::clamp(x + step * sx, -half, half), ny = std::clamp(y + step * sy, -half, half);
            const double e1 = energy(nx, ny);
            if (e1 <= e0) {
                moved = nx != x || ny != y;
                x = nx, y = ny, e0 = e1;
                break;
            }
        }
        if (!moved || step * (std::abs(sx) + std::abs(sy)) < 1e-15 * size) break;
    }
    return e0;
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
    const long n = square_intervals(s, spacing, 6);
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

PointSet parallel_sheets(const Vec3& c, double size, double gap, double spacing) {
    require_finite(c);
    require_positive("size", size);
    require_positive("gap", gap);
    const long n = square_intervals(size, spacing, 2);
    const double h = size / 2;
    PointSet out;
    out.reserve(std::size_t(2 * (n + 1) * (n + 1)));
    for (double z : {c[2] - gap / 2, c[2] + gap / 2})
        for (long j = 0; j <= n; ++j)
            for (long i = 0; i <= n; ++i)
                out.push_back({lerp(c[0] - h, c[0] + h, i, n), lerp(c[1] - h, c[1] + h, j, n), z});
    return out;
}

PointSet mobius_strip(const Vec3& c, double R, double width, double spacing) {
    require_mobius(c, R, width);
    require_positive("spacing", spacing);
    require_count(2 * kPi * (R + width / 2) / spacing * (width / spacing + 1) + 16);
    const long nv = intervals(width, spacing);
    PointSet out;
    // Going once around turns a ruling end over end, so the rows at v and -v are one
    // closed curve of two turns; the centre row (v = 0, for even nv) closes after one.
    for (long k = 0; 2 * k <= nv; ++k) {
        const double v = lerp(-width / 2, width / 2, k, nv);
        auto point = [&](double u) {
            const Ruling r = mobius_ruling(c, R, u);
            return Vec3{r.base[0] + v * r.dir[0], r.base[1] + v * r.dir[1], r.base[2] + v * r.dir[2]};
        };
        const double turns = 2 * k == nv ? 1 : 2;
        for (double u : arc_length_params(point, 0.0, 2 * kPi * turns, spacing, true)) out.push_back(point(u));
    }
    return out;
}

PointSet helicoid(const Vec3& c, double radius, double pitch, double turns, double spacing) {
    require_helicoid(c, radius, pitch, turns);
    require_positive("spacing", spacing);
    const double longest = 2 * kPi * turns * std::hypot(radius, pitch / (2 * kPi));
    require_count(longest / spacing * (radius / spacing + 2) + 16);
    const long nv = intervals(radius, spacing);
    PointSet out;
    // Rows of constant v are helices (v = 0: the axis), each uniform in arc length.
    for (long k = 0; k <= nv; ++k) {
        const double v = lerp(0, radius, k, nv);
        auto point = [&](double u) {
            const Ruling r = helicoid_ruling(c, pitch, turns, u);
            return Vec3{r.base[0] + v * r.dir[0], r.base[1] + v * r.dir[1], r.base[2]};
        };
        for (double u : arc_length_params(point, 0.0, 2 * kPi * turns, spacing, false)) out.push_back(point(u));
    }
    return out;
}

PointSet noisy_sphere(const Vec3& c, double r, double spacing, double sigma, std::uint64_t seed) {
    require_non_negative("sigma", sigma);
    PointSet out = sphere(c, r, spacing);
    Gaussian noise(seed);
    for (Vec3& p : out)
        for (double& v : p) v += sigma * noise();
    return out;
}

PointSet with_outliers(PointSet points, double fraction, std::uint64_t seed) {
    require_non_negative("outlier fraction", fraction);
    if (points.empty() || fraction == 0) return points;
    Vec3 lo = points[0], hi = points[0];
    for (const Vec3& p : points)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], p[a]);
            hi[a] = std::max(hi[a], p[a]);
        }
    std::mt19937_64 gen(seed);
    const auto uniform = [&gen] { return double(gen() >> 11) * 0x1p-53; };  // in [0, 1)
    const std::size_t count = std::size_t(std::llround(fraction * double(points.size())));
    points.reserve(points.size() + count);
    for (std::size_t i = 0; i < count; ++i) {
        Vec3 p;
        for (int a = 0; a < 3; ++a) p[a] = lo[a] + (hi[a] - lo[a]) * uniform();
        points.push_back(p);
    }
    return points;
}

PointSet varying_sphere(const Vec3& c, double r, double spacing, double ratio) {
    require_finite(c);
    require_positive("radius", r);
    require_positive("spacing", spacing);
    if (!(std::isfinite(ratio) && ratio >= 1))
        throw ParameterError("shapes: density ratio must be at least 1, got " + std::to_string(ratio));
    // Points per area proportional to exp(-a (1 - z)) on the unit height z: 1 at the
    // top pole, 1 / ratio at the bottom. Per unit height (area 2 pi r^2) the top has
    // 2 pi r^2 / spacing^2 points; `total` integrates the profile over z in [-1, 1].
    const double a = std::log(ratio) / 2;
    const double total = a > 0 ? -std::expm1(-2 * a) / a : 2.0;
    const double estimate = std::ceil(2 * kPi * r * r / (spacing * spacing) * total);
    // The Fibonacci lattice with its heights warped so that point i has the share
    // (i + 1/2) / n of the profile above it; locally it stays a Fibonacci lattice.
    const auto height = [&](long i, long n) {
        const double share = (double(i) + 0.5) / double(n);
        return a > 0 ? 1 + std::log1p(-a * share * total) / a : 1 - 2 * share;
    };
    return golden_spiral(c, r, estimate, height, [](double) { return true; });
}

PointSet torus(const Vec3& c, double R, double r, double spacing) {
    require_torus(c, R, r);
    require_positive("spacing", spacing);
    require_count(4 * kPi * kPi * R * r / (spacing * spacing) * 2 + 16);
    const long n = intervals(2 * kPi * r, spacing);
    PointSet out;
    for (long k = 0; k < n; ++k) {
        const double phi = 2 * kPi * double(k) / double(n);
        add_ring(out, c, R + r * std::cos(phi), c[2] + r * std::sin(phi), spacing, k);
    }
    return out;
}

double lidar_height(double x, double y, double size) { return terrain(x, y, size).f; }

PointSet lidar_scan(const Vec3& c, double size, double spacing, double line_gap, double range_sigma,
                    std::uint64_t seed) {
    require_finite(c);
    require_positive("size", size);
    require_positive("spacing", spacing);
    require_positive("line gap", line_gap);
    require_non_negative("range sigma", range_sigma);
    // Slopes stay below 0.5, so a line is at most 1.2 sides long.
    require_count((size / line_gap + 2) * (1.2 * size / spacing + 2));
    const double half = size / 2;
    const long lines = intervals(size, line_gap);
    const Vec3 scanner{c[0], c[1], c[2] + size};
    Gaussian noise(seed);
    PointSet out;
    for (long j = 0; j <= lines; ++j) {
        const double y = lerp(-half, half, j, lines);
        auto point = [&](double x) { return Vec3{c[0] + x, c[1] + y, c[2] + lidar_height(x, y, size)}; };
        for (double x : arc_length_params(point, -half, half, spacing, false)) {
            Vec3 p = point(x);
            // Range noise moves a point along its ray from the scanner.
            const Vec3 ray = sub(p, scanner);
            const double shift = range_sigma * noise() / norm(ray);
            for (int a = 0; a < 3; ++a) p[a] += shift * ray[a];
            out.push_back(p);
        }
    }
    return out;
}

double sphere_distance(const Vec3& p, const Vec3& c, double r) {
    return std::abs(std::hypot(p[0] - c[0], p[1] - c[1], p[2] - c[2]) - r);
}

double half_sphere_distance(const Vec3& p, const Vec3& c, double r) {
    // Above the equator's plane the radial projection lies on the cap; below it the
    // nearest point is on the rim.
    if (p[2] >= c[2]) return sphere_distance(p, c, r);
    return std::hypot(std::hypot(p[0] - c[0], p[1] - c[1]) - r, p[2] - c[2]);
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

double two_headed_cone_distance(const Vec3& p, const Vec3& c, double r, double ht) {
    // In the (radius, |z|) half-plane the surface is the segment from (r, 0) to (0, a).
    const double a = ht / 2;
    const double rho = std::hypot(p[0] - c[0], p[1] - c[1]);
    const double z = std::abs(p[2] - c[2]);
    const double t = std::clamp(((rho - r) * -r + z * a) / (r * r + a * a), 0.0, 1.0);
    return std::hypot(rho - r * (1 - t), z - t * a);
}

double parallel_sheets_distance(const Vec3& p, const Vec3& c, double size, double gap) {
    // Both squares have the same footprint, so the nearer plane holds the nearer point.
    const double dx = std::max(std::abs(p[0] - c[0]) - size / 2, 0.0);
    const double dy = std::max(std::abs(p[1] - c[1]) - size / 2, 0.0);
    const double dz = std::abs(std::abs(p[2] - c[2]) - gap / 2);
    return std::hypot(dx, dy, dz);
}

double mobius_strip_distance(const Vec3& p, const Vec3& c, double R, double width) {
    require_mobius(c, R, width);
    // |dx/du|^2 = (R + v cos(u/2))^2 + v^2 / 4.
    const double lipschitz = std::hypot(R + width / 2, width / 4);
    auto ruling = [&](double u) { return mobius_ruling(c, R, u); };
    return ruled_distance(p, ruling, 0.0, 2 * kPi, true, -width / 2, width / 2, lipschitz, 256);
}

double helicoid_distance(const Vec3& p, const Vec3& c, double radius, double pitch, double turns) {
    require_helicoid(c, radius, pitch, turns);
    const double lipschitz = std::hypot(radius, pitch / (2 * kPi));  // |dx/du| at v = radius
    auto ruling = [&](double u) { return helicoid_ruling(c, pitch, turns, u); };
    const long samples = std::max(64L, static_cast<long>(std::ceil(128 * turns)));
    return ruled_distance(p, ruling, 0.0, 2 * kPi * turns, false, 0.0, radius, lipschitz, samples);
}

double torus_distance(const Vec3& p, const Vec3& c, double R, double r) {
    return std::abs(std::hypot(std::hypot(p[0] - c[0], p[1] - c[1]) - R, p[2] - c[2]) - r);
}

double lidar_distance(const Vec3& p, const Vec3& c, double size) {
    require_finite(c);
    require_positive("size", size);
    const double half = size / 2;
    const Vec3 q = sub(p, c);
    auto distance2 = [&](double x, double y) {
        const double dz = q[2] - lidar_height(x, y, size);
        return (q[0] - x) * (q[0] - x) + (q[1] - y) * (q[1] - y) + dz * dz;
    };
    // The terrain point over the nearest (x, y) of the square bounds the distance,
    // so the nearest point lies within that bound of q: search that box on a grid
    // finer than the bumps (a side / 50; at least 4 x 4 near the surface), then
    // refine the best few grid points by Newton's method.
    const double bound = std::sqrt(distance2(std::clamp(q[0], -half, half), std::clamp(q[1], -half, half)));
    const double x0 = std::max(-half, q[0] - bound), x1 = std::min(half, q[0] + bound);
    const double y0 = std::max(-half, q[1] - bound), y1 = std::min(half, q[1] + bound);
    const long cells = std::clamp(static_cast<long>(std::ceil(2 * bound / (0.02 * size))), 4L, 32L);
    std::vector<std::pair<double, std::pair<double, double>>> grid;
    grid.reserve(std::size_t((cells + 1) * (cells + 1)));
    for (long j = 0; j <= cells; ++j)
        for (long i = 0; i <= cells; ++i) {
            const double x = lerp(x0, x1, i, cells), y = lerp(y0, y1, j, cells);
            grid.push_back({distance2(x, y), {x, y}});
        }
    const std::size_t starts = 3;
    std::partial_sort(grid.begin(), grid.begin() + starts, grid.end());
    double best = grid.front().first;
    for (std::size_t k = 0; k < starts; ++k)
        best = std::min(best, 2 * terrain_newton(q, grid[k].second.first, grid[k].second.second, size));
    return std::sqrt(best);
}

namespace {

// Every named shape: its sampler and the distance to its noise-free surface.
struct Named {
    const char* name;
    PointSet (*sample)(double spacing);
    double (*distance)(const Vec3& p);
};

const Vec3 kCentre{0.5, 0.5, 0.5};
constexpr double kSize = 0.35;  // the paper's Table 2 size
constexpr double kSheetSide = 0.7, kSheetGap = 0.06;
constexpr double kMobiusR = 0.3, kMobiusWidth = 0.25;
constexpr double kHelixRadius = 0.35, kHelixPitch = 0.2, kHelixTurns = 3;
constexpr double kNoise = 0.3;  // noisy-sphere sigma, in spacings
constexpr double kDensityRatio = 10;
constexpr double kTorusR = 0.3, kTorusTube = 0.12;
constexpr double kTerrainSide = 0.7, kLineGap = 4, kRangeNoise = 0.1;  // the last two in spacings

const Named kNamed[] = {
    {"sphere", [](double s) { return sphere(kCentre, kSize, s); },
     [](const Vec3& p) { return sphere_distance(p, kCentre, kSize); }},
    {"cube", [](double s) { return cube(kCentre, kSize, s); },
     [](const Vec3& p) { return cube_distance(p, kCentre, kSize); }},
    {"cylinder", [](double s) { return cylinder(kCentre, kSize, kSize, s); },
     [](const Vec3& p) { return cylinder_distance(p, kCentre, kSize, kSize); }},
    {"half-sphere", [](double s) { return half_sphere(kCentre, kSize, s); },
     [](const Vec3& p) { return half_sphere_distance(p, kCentre, kSize); }},
    {"cone", [](double s) { return two_headed_cone(kCentre, kSize, 2 * kSize, s); },
     [](const Vec3& p) { return two_headed_cone_distance(p, kCentre, kSize, 2 * kSize); }},
    {"sheets", [](double s) { return parallel_sheets(kCentre, kSheetSide, kSheetGap, s); },
     [](const Vec3& p) { return parallel_sheets_distance(p, kCentre, kSheetSide, kSheetGap); }},
    {"mobius", [](double s) { return mobius_strip(kCentre, kMobiusR, kMobiusWidth, s); },
     [](const Vec3& p) { return mobius_strip_distance(p, kCentre, kMobiusR, kMobiusWidth); }},
    {"helicoid", [](double s) { return helicoid(kCentre, kHelixRadius, kHelixPitch, kHelixTurns, s); },
     [](const Vec3& p) { return helicoid_distance(p, kCentre, kHelixRadius, kHelixPitch, kHelixTurns); }},
    {"noisy-sphere", [](double s) { return noisy_sphere(kCentre, kSize, s, kNoise * s, 1); },
     [](const Vec3& p) { return sphere_distance(p, kCentre, kSize); }},
    {"varying-sphere", [](double s) { return varying_sphere(kCentre, kSize, s, kDensityRatio); },
     [](const Vec3& p) { return sphere_distance(p, kCentre, kSize); }},
    {"torus", [](double s) { return torus(kCentre, kTorusR, kTorusTube, s); },
     [](const Vec3& p) { return torus_distance(p, kCentre, kTorusR, kTorusTube); }},
    {"lidar", [](double s) { return lidar_scan(kCentre, kTerrainSide, s, kLineGap * s, kRangeNoise * s, 1); },
     [](const Vec3& p) { return lidar_distance(p, kCentre, kTerrainSide); }},
};

const Named& find_named(const std::string& name) {
    for (const Named& n : kNamed)
        if (name == n.name) return n;
    std::string known;
    for (const Named& n : kNamed) known += (known.empty() ? "" : ", ") + std::string(n.name);
    throw ParameterError("unknown shape '" + name + "' (known: " + known + ")");
}

}  // namespace

PointSet by_name(const std::string& name, double spacing) { return find_named(name).sample(spacing); }

PointSet random_by_name(const std::string& name, std::size_t count, std::uint64_t seed) {
    if (count < 1) throw ParameterError("the random point count must be at least 1");
    const Named& shape = find_named(name);
    // A blue-noise sampling 100 times as dense as asked (its count falls with the square
    // of the spacing), then `count` of its points by a partial Fisher-Yates shuffle.
    constexpr double kTrial = 0.01;
    const double trial = double(shape.sample(kTrial).size());
    PointSet dense = shape.sample(kTrial * std::sqrt(trial / (100.0 * double(count))));
    if (dense.size() < count) throw ParameterError("the shape holds too few points for " + std::to_string(count));
    std::mt19937_64 gen(seed);
    for (std::size_t i = 0; i < count; ++i) std::swap(dense[i], dense[i + std::size_t(gen() % (dense.size() - i))]);
    dense.resize(count);
    return dense;
}

std::function<double(const Vec3&)> exact_distance_by_name(const std::string& name, double spacing) {
    // The noise-free surfaces do not depend on the spacing; checking it keeps the
    // arguments those of by_name.
    require_positive("spacing", spacing);
    return find_named(name).distance;
}

std::vector<std::string> names() {
    std::vector<std::string> out;
    for (const Named& n : kNamed) out.push_back(n.name);
    return out;
}

}  // namespace snvr::shapes
