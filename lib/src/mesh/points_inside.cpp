// count_points_inside (mesh.hpp): the points' winding numbers along +z against a
// closed mesh, with exact orientation tests, so that an inside test never depends on
// rounding.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "mesh/float_rounding.hpp"
#include "mesh/mesh_indices.hpp"
#include "parallel_sizes.hpp"
#include "snvr/mesh.hpp"

namespace snvr {
namespace {

using detail::round_down;
using detail::round_up;
using Tri = std::array<std::uint32_t, 3>;

bool degenerate(const Tri& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; }

// ---- exact 2D orientation (Shewchuk-style filter with an expansion fallback)

void two_sum(double a, double b, double& s, double& e) {
    s = a + b;
    const double bv = s - a, av = s - bv;
    e = (a - av) + (b - bv);
}

void two_diff(double a, double b, double& d, double& e) {
    d = a - b;
    const double bv = a - d, av = d + bv;
    e = (a - av) + (bv - b);
}

// Exact sign of a sum of doubles: grow a nonoverlapping expansion one term at
// a time; its largest (last nonzero) component carries the sign.
int sign_of_sum(const double* terms, int n) {
    double e[16];
    int m = 0;
    for (int t = 0; t < n; ++t) {
        if (terms[t] == 0) continue;
        double q = terms[t];
        int kept = 0;
        for (int i = 0; i < m; ++i) {
            double err;
            two_sum(q, e[i], q, err);
            if (err != 0) e[kept++] = err;  // dropping zeros keeps the expansion short
        }
        e[kept] = q;
        m = kept + 1;
    }
    for (int i = m - 1; i >= 0; --i)
        if (e[i] != 0) return e[i] > 0 ? 1 : -1;
    return 0;
}

// Sign of (b - a) x (q - a) in the xy plane, exactly.
int orient2d(const Vec3& a, const Vec3& b, double qx, double qy) {
    const double l = (b[0] - a[0]) * (qy - a[1]), r = (b[1] - a[1]) * (qx - a[0]);
    const double det = l - r;
    // A bound on the rounding error of det (Shewchuk's ccwerrboundA, rounded up).
    const double bound = 2 * std::numeric_limits<double>::epsilon() * (std::fabs(l) + std::fabs(r));
    if (det > bound) return 1;
    if (-det > bound) return -1;

    double x1, x1e, y1, y1e, x2, x2e, y2, y2e;  // each difference as an exact pair
    two_diff(b[0], a[0], x1, x1e);
    two_diff(qy, a[1], y2, y2e);
    two_diff(b[1], a[1], y1, y1e);
    two_diff(qx, a[0], x2, x2e);
    double terms[16];
    int n = 0;
    const auto add_products = [&](double u, double ue, double v, double ve, double sign) {
        for (double p : {u, ue})
            for (double q : {v, ve}) {
                const double prod = p * q;
                terms[n++] = sign * prod;
                terms[n++] = sign * std::fma(p, q, -prod);  // exact rounding error of the product
            }
    };
    add_products(x1, x1e, y2, y2e, 1);
    add_products(y1, y1e, x2, x2e, -1);
    return sign_of_sum(terms, n);
}

// Orientation for the query moved to (qx + e, qy + e^2) with e -> 0+: never
// zero unless a == b in xy.  One shared perturbation for all triangles makes
// rays that hit edges or vertices count exactly as a nearby generic ray.
int orient2d_perturbed(const Vec3& a, const Vec3& b, double qx, double qy) {
    if (const int s = orient2d(a, b, qx, qy)) return s;
    if (a[1] != b[1]) return a[1] > b[1] ? 1 : -1;  // the e term: -(by - ay)
    if (a[0] != b[0]) return b[0] > a[0] ? 1 : -1;  // the e^2 term: bx - ax
    return 0;
}


// The points bucketed by a uniform grid over their xy box, each bucket holding
// its points' coordinates (in ascending index order) next to their indices.
class PointColumns {
public:
    explicit PointColumns(const PointSet& points) {
        const std::size_t n = points.size();
        lo_ = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
        hi_ = {-lo_[0], -lo_[1]};
        for (const Vec3& p : points)
            if (finite_xy(p))
                for (int d = 0; d < 2; ++d) {
                    lo_[d] = std::min(lo_[d], p[d]);
                    hi_[d] = std::max(hi_[d], p[d]);
                }
        if (!(lo_[0] <= hi_[0])) return;  // no point with finite x and y
        // About four cells per point: most cells a triangle's box meets are empty.
        const double w = hi_[0] - lo_[0], h = hi_[1] - lo_[1];
        const double cells = 4.0 * double(n) + 16;
        double side = std::sqrt(w * h / cells);
        if (!(side > 0)) side = std::max(w, h) / cells;
        for (int d = 0; d < 2; ++d) {
            const double span = d == 0 ? w : h;
            n_[d] = side > 0 ? int(std::clamp(std::floor(span / side), 1.0, 4096.0)) : 1;
            inv_[d] = span > 0 ? n_[d] / span : 0;
        }
        const std::size_t n_cells = std::size_t(n_[0]) * std::size_t(n_[1]);
        start_.assign(n_cells + 1, 0);
        std::vector<std::uint32_t> cell_of(n);
        for (std::size_t k = 0; k < n; ++k) {
            const double x = points[k][0], y = points[k][1];
            if (!finite_xy(points[k])) {
                cell_of[k] = std::uint32_t(-1);  // left out: in no triangle's box that matters
                continue;
            }
            cell_of[k] = std::uint32_t(cell(0, x) + std::size_t(n_[0]) * cell(1, y));
            ++start_[cell_of[k] + 1];
        }
        for (std::size_t c = 0; c < n_cells; ++c) start_[c + 1] += start_[c];
        items_.resize(start_[n_cells]);
        std::vector<std::uint32_t> next(start_.begin(), start_.end() - 1);
        for (std::size_t k = 0; k < n; ++k)
            if (cell_of[k] != std::uint32_t(-1)) items_[next[cell_of[k]]++] = {points[k], std::uint32_t(k)};
    }

    struct Item {
        Vec3 p;
        std::uint32_t index;
    };
    // Calls visit(item) for every point whose cell meets the box [x0, x1] x [y0, y1]
    // (a superset of the points in the box: the caller tests them).
    template <class Visit>
    void for_each_near(double x0, double y0, double x1, double y1, const Visit& visit) const {
        if (start_.empty() || x1 < lo_[0] || x0 > hi_[0] || y1 < lo_[1] || y0 > hi_[1]) return;
        const int cx0 = cell(0, x0), cx1 = cell(0, x1), cy0 = cell(1, y0), cy1 = cell(1, y1);
        for (int y = cy0; y <= cy1; ++y) {
            const std::size_t row = std::size_t(n_[0]) * y;
            for (std::uint32_t k = start_[row + cx0]; k < start_[row + cx1 + 1]; ++k) visit(items_[k]);
        }
    }

private:
    static bool finite_xy(const Vec3& p) { return std::isfinite(p[0]) && std::isfinite(p[1]); }
    // Monotone in v, so the cells of a box's corners bound the cells of its points.
    int cell(int d, double v) const {
        const double x = (v - lo_[d]) * inv_[d];
        if (!(x > 0)) return 0;
        if (x >= n_[d] - 1) return n_[d] - 1;
        return int(x);
    }
    std::array<double, 2> lo_{}, hi_{}, inv_{};
    std::array<int, 2> n_{1, 1};
    std::vector<std::uint32_t> start_;  // cell c holds items_[start_[c] .. start_[c + 1]); rows are contiguous
    std::vector<Item> items_;
};

}  // namespace

// Winding number along a ray in +z: every triangle the ray crosses counts +1
// if it faces up (leaving the solid) and -1 if it faces down.  For a closed,
// outward-oriented mesh this is the exact winding number (the generalised one
// is the same there), and "inside" means winding >= 1.  Points on the surface
// itself may go either way.
std::size_t count_points_inside(const Mesh& mesh, const PointSet& points) {
    detail::check_triangle_indices(mesh, "count_points_inside");
    const auto& V = mesh.vertices;
    const auto& T = mesh.triangles;
    const bool parallel = points.size() >= std::size_t(detail::kParallelCostlyItems) || T.size() >= std::size_t(detail::kParallelCheapItems);
    if (points.empty() || T.empty()) return 0;
    // Triangle by triangle over a grid of the points (far fewer than the triangles
    // here), rather than point by point over a grid of the triangles: only the
    // triangles with a point under them cost more than a glance.
    const PointColumns columns(points);
    std::vector<std::int32_t> winding(points.size(), 0);
#pragma omp parallel for schedule(dynamic, 4096) if (parallel)
    for (std::ptrdiff_t t = 0; t < std::ptrdiff_t(T.size()); ++t) {
        const Tri& tri = T[t];
        if (degenerate(tri)) continue;
        const Vec3 &a = V[tri[0]], &b = V[tri[1]], &c = V[tri[2]];
        // The footprint's xy box, rounded outwards to floats as it always was.
        const double x0 = round_down(std::min({a[0], b[0], c[0]})), x1 = round_up(std::max({a[0], b[0], c[0]}));
        const double y0 = round_down(std::min({a[1], b[1], c[1]})), y1 = round_up(std::max({a[1], b[1], c[1]}));
        int seen = -1;  // whether the triangle is seen from +z: decided at the first point in its box
        columns.for_each_near(x0, y0, x1, y1, [&](const PointColumns::Item& item) {
            const Vec3& p = item.p;
            // Outside the closed box, the perturbed point is outside the triangle too.
            if (seen == 0 || p[0] < x0 || p[0] > x1 || p[1] < y0 || p[1] > y1) return;
            // Triangles that are edge-on seen from +z cannot be crossed by the perturbed ray.
            if (seen < 0) seen = orient2d(a, b, c[0], c[1]) != 0 ? 1 : 0;
            if (seen == 0) return;
            const double u0 = b[0] - a[0], u1 = b[1] - a[1], u2 = b[2] - a[2];
            const double w0 = c[0] - a[0], w1 = c[1] - a[1], w2 = c[2] - a[2];
            const int s = orient2d_perturbed(a, b, p[0], p[1]);
            if (s == 0 || orient2d_perturbed(b, c, p[0], p[1]) != s || orient2d_perturbed(c, a, p[0], p[1]) != s)
                return;
            // The column crosses the triangle; count it if the crossing is above p,
            // i.e. p lies on the side of the plane opposite to where the normal's z points.
            const double side = (p[0] - a[0]) * (u1 * w2 - u2 * w1) + (p[1] - a[1]) * (u2 * w0 - u0 * w2) +
                                (p[2] - a[2]) * (u0 * w1 - u1 * w0);
            if (side * s < 0) {
#pragma omp atomic
                winding[item.index] += s;
            }
        });
    }
    std::size_t inside = 0;
    for (std::int32_t w : winding) inside += w > 0;
    return inside;
}

}  // namespace snvr
