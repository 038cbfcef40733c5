// TriangleGrid: a uniform bucket grid over triangles, closest-triangle search by
// growing rings of cells and ray casting by a 3D DDA walk (Amanatides & Woo).
#include "mesh/triangle_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "snvr/error.hpp"
#include "geometry/vec3_math.hpp"

namespace snvr {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Finer cells mean fewer triangles tested per query and 4 bytes per cell.
constexpr double kCellsPerTriangle = 4;


double point_segment_dist_sq(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = sub(b, a), ap = sub(p, a);
    const double len_sq = dot(ab, ab);
    const double t = len_sq > 0 ? std::clamp(dot(ap, ab) / len_sq, 0.0, 1.0) : 0.0;
    const Vec3 d{ap[0] - t * ab[0], ap[1] - t * ab[1], ap[2] - t * ab[2]};
    return dot(d, d);
}

// Möller-Trumbore; the ray parameter of the crossing, or -infinity if none.
// `slack` widens the triangle (in barycentric units) so that a ray through a
// shared edge or corner cannot slip between the triangles by rounding.
double ray_triangle(const Vec3& o, const Vec3& dir, const Vec3& a, const Vec3& b, const Vec3& c, double slack) {
    const Vec3 e1 = sub(b, a), e2 = sub(c, a);
    const Vec3 pv = cross(dir, e2);
    const double det = dot(e1, pv);
    if (det == 0) return -kInf;  // parallel to the plane (or degenerate)
    const double inv = 1 / det;
    const Vec3 tv = sub(o, a);
    const double u = dot(tv, pv) * inv;
    if (u < -slack || u > 1 + slack) return -kInf;
    const Vec3 qv = cross(tv, e1);
    const double v = dot(dir, qv) * inv;
    if (v < -slack || u + v > 1 + slack) return -kInf;
    return dot(e2, qv) * inv;
}

}  // namespace

double point_triangle_dist_sq(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
    const Vec3 n = cross(ab, ac);
    if (dot(n, n) == 0)  // collinear corners: the triangle is its longest edge
        return std::min({point_segment_dist_sq(p, a, b), point_segment_dist_sq(p, b, c), point_segment_dist_sq(p, c, a)});
    // Ericson, Real-Time Collision Detection 5.1.5: find the Voronoi region of p.
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return dot(ap, ap);
    const Vec3 bp = sub(p, b);
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return dot(bp, bp);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return point_segment_dist_sq(p, a, b);
    const Vec3 cp = sub(p, c);
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return dot(cp, cp);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return point_segment_dist_sq(p, a, c);
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return point_segment_dist_sq(p, b, c);
    // Inside the face: the distance to the plane.
    const double s = dot(ap, n);
    return s * s / dot(n, n);
}

TriangleGrid::TriangleGrid(const Mesh& mesh) : mesh_(mesh) {
    const auto& V = mesh.vertices;
    const auto& T = mesh.triangles;
    const std::size_t nt = T.size();
    if (nt == 0) return;
    if (nt >= std::numeric_limits<std::uint32_t>::max()) throw ResourceError("TriangleGrid: more than 2^32 triangles");
    lo_ = {kInf, kInf, kInf};
    hi_ = {-kInf, -kInf, -kInf};
    double extent = 0;  // summed largest box side of the triangles
    for (const auto& t : T) {
        double side = 0;
        for (int d = 0; d < 3; ++d) {
            const double a = V[t[0]][d], b = V[t[1]][d], c = V[t[2]][d];
            const double mn = std::min({a, b, c}), mx = std::max({a, b, c});
            lo_[d] = std::min(lo_[d], mn);
            hi_[d] = std::max(hi_[d], mx);
            side = std::max(side, mx - mn);
        }
        extent += side;
    }
    // Cells no smaller than the mean triangle (so a triangle meets few cells) and
    // no more than kCellsPerTriangle per triangle.
    const Vec3 span = sub(hi_, lo_);
    const double diag = std::sqrt(dot(span, span));
    size_ = std::max({extent / double(nt), std::cbrt(span[0] * span[1] * span[2] / (kCellsPerTriangle * double(nt))), diag * 1e-6});
    if (!(size_ > 0)) size_ = 1;  // every triangle is one point
    for (;;) {
        double cells = 1;
        for (int d = 0; d < 3; ++d) {
            n_[d] = std::max(1, int(std::ceil(span[d] / size_)));
            cells *= n_[d];
        }
        if (cells <= kCellsPerTriangle * double(nt) + 4096) break;
        size_ *= 1.25;
    }

    // Boxes grown by a sliver, so that a point on a cell face finds the triangle
    // from both cells whatever the rounding.
    const double slack = size_ * 1e-9;
    // Calls visit(cell index) for every cell that triangle t's box meets; shared by
    // the counting and the filling pass so that both see the same cells.
    const auto for_box_cells = [&](std::size_t t, auto&& visit) {
        std::array<int, 3> c0, c1;
        for (int d = 0; d < 3; ++d) {
            const double a = V[T[t][0]][d], b = V[T[t][1]][d], c = V[T[t][2]][d];
            c0[d] = cell(d, std::min({a, b, c}) - slack);
            c1[d] = cell(d, std::max({a, b, c}) + slack);
        }
        for (int z = c0[2]; z <= c1[2]; ++z)
            for (int y = c0[1]; y <= c1[1]; ++y)
                for (int x = c0[0]; x <= c1[0]; ++x) visit(index(x, y, z));
    };
    const std::size_t n_cells = std::size_t(n_[0]) * std::size_t(n_[1]) * std::size_t(n_[2]);
    std::vector<std::uint64_t> count(n_cells + 1, 0);
    std::uint64_t* counts = count.data() + 1;
#pragma omp parallel for schedule(static) if (nt > 20000)
    for (std::ptrdiff_t t = 0; t < std::ptrdiff_t(nt); ++t)
        for_box_cells(std::size_t(t), [&](std::size_t cell_index) {
#pragma omp atomic
            ++counts[cell_index];
        });
    for (std::size_t c = 0; c < n_cells; ++c) count[c + 1] += count[c];
    if (count[n_cells] >= std::numeric_limits<std::uint32_t>::max())
        throw ResourceError("TriangleGrid: more than 2^32 cell entries");
    start_.assign(count.begin(), count.end());
    items_.resize(count[n_cells]);
    std::uint64_t* next = count.data();  // reused as each cell's write cursor
#pragma omp parallel for schedule(static) if (nt > 20000)
    for (std::ptrdiff_t t = 0; t < std::ptrdiff_t(nt); ++t)
        for_box_cells(std::size_t(t), [&](std::size_t cell_index) {
            std::uint64_t at;
#pragma omp atomic capture
            at = next[cell_index]++;
            items_[at] = std::uint32_t(t);
        });
}

int TriangleGrid::cell(int d, double v) const {
    return int(std::clamp(std::floor((v - lo_[d]) / size_), 0.0, double(n_[d] - 1)));
}

TriangleGrid::Closest TriangleGrid::closest(const Vec3& p) const {
    Closest best{kInf, none};
    if (items_.empty()) return best;
    const auto& V = mesh_.vertices;
    const auto& T = mesh_.triangles;
    const std::array<int, 3> c{cell(0, p[0]), cell(1, p[1]), cell(2, p[2])};
    const auto visit = [&](int x, int y, int z) {
        // Skip a cell whose box is no nearer than the best triangle so far.
        const std::array<int, 3> at{x, y, z};
        double box = 0;
        for (int d = 0; d < 3; ++d) {
            const double lo = lo_[d] + at[d] * size_;
            const double gap = std::max({0.0, lo - p[d], p[d] - (lo + size_)});
            box += gap * gap;
        }
        if (box >= best.dist_sq) return;
        const std::size_t i = index(x, y, z);
        for (std::uint32_t k = start_[i]; k < start_[i + 1]; ++k) {
            const auto& t = T[items_[k]];
            const double d = point_triangle_dist_sq(p, V[t[0]], V[t[1]], V[t[2]]);
            if (d < best.dist_sq) best = {d, items_[k]};
        }
    };
    for (int r = 0;; ++r) {
        // The cells at Chebyshev distance exactly r from c, clipped to the grid.
        const int z0 = std::max(0, c[2] - r), z1 = std::min(n_[2] - 1, c[2] + r);
        const int y0 = std::max(0, c[1] - r), y1 = std::min(n_[1] - 1, c[1] + r);
        const int x0 = std::max(0, c[0] - r), x1 = std::min(n_[0] - 1, c[0] + r);
        for (int z = z0; z <= z1; ++z)
            for (int y = y0; y <= y1; ++y) {
                if (std::abs(z - c[2]) == r || std::abs(y - c[1]) == r) {
                    for (int x = x0; x <= x1; ++x) visit(x, y, z);
                } else {
                    if (c[0] - r >= 0) visit(c[0] - r, y, z);
                    if (r > 0 && c[0] + r < n_[0]) visit(c[0] + r, y, z);
                }
            }
        // Every cell not yet visited lies beyond one of the box's faces that still
        // has cells behind it: the nearest such face bounds what is left.
        double bound = kInf;
        for (int d = 0; d < 3; ++d) {
            if (c[d] + r + 1 < n_[d]) bound = std::min(bound, std::max(0.0, lo_[d] + (c[d] + r + 1) * size_ - p[d]));
            if (c[d] - r - 1 >= 0) bound = std::min(bound, std::max(0.0, p[d] - (lo_[d] + (c[d] - r) * size_)));
        }
        if (bound == kInf || best.dist_sq <= bound * bound) return best;
    }
}

template <class Visit>
void TriangleGrid::walk(const Vec3& origin, const Vec3& dir, const Visit& visit) const {
    if (items_.empty()) return;
    // Clip the ray to the grid's box (slab test).
    double t0 = 0, t1 = kInf;
    for (int d = 0; d < 3; ++d) {
        const double box_lo = lo_[d], box_hi = lo_[d] + n_[d] * size_;
        if (dir[d] == 0) {
            if (origin[d] < box_lo || origin[d] > box_hi) return;
            continue;
        }
        double a = (box_lo - origin[d]) / dir[d], b = (box_hi - origin[d]) / dir[d];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
    }
    if (t0 > t1) return;
    std::array<int, 3> c, step;
    std::array<double, 3> t_next, t_delta;
    for (int d = 0; d < 3; ++d) {
        c[d] = cell(d, origin[d] + t0 * dir[d]);
        if (dir[d] > 0) {
            step[d] = 1;
            t_next[d] = (lo_[d] + (c[d] + 1) * size_ - origin[d]) / dir[d];
            t_delta[d] = size_ / dir[d];
        } else if (dir[d] < 0) {
            step[d] = -1;
            t_next[d] = (lo_[d] + c[d] * size_ - origin[d]) / dir[d];
            t_delta[d] = -size_ / dir[d];
        } else {
            step[d] = 0;
            t_next[d] = t_delta[d] = kInf;
        }
    }
    for (;;) {
        const int d = t_next[0] < t_next[1] ? (t_next[0] < t_next[2] ? 0 : 2) : (t_next[1] < t_next[2] ? 1 : 2);
        const std::size_t i = index(c[0], c[1], c[2]);
        if (!visit(items_.data() + start_[i], items_.data() + start_[i + 1], t_next[d])) return;
        c[d] += step[d];
        if (c[d] < 0 || c[d] >= n_[d] || t_next[d] > t1) return;
        t_next[d] += t_delta[d];
    }
}

TriangleGrid::Hit TriangleGrid::first_hit(const Vec3& origin, const Vec3& dir, double t_min,
                                          std::uint32_t skip_vertex) const {
    Hit best{kInf, none};
    const auto& V = mesh_.vertices;
    const auto& T = mesh_.triangles;
    walk(origin, dir, [&](const std::uint32_t* first, const std::uint32_t* last, double t_exit) {
        for (const std::uint32_t* it = first; it != last; ++it) {
            const auto& t = T[*it];
            if (t[0] == skip_vertex || t[1] == skip_vertex || t[2] == skip_vertex) continue;
            const double s = ray_triangle(origin, dir, V[t[0]], V[t[1]], V[t[2]], 1e-9);
            if (s > t_min && s < best.t) best = {s, *it};
        }
        // A hit beyond this cell may still be beaten by one in a later cell.
        return best.t > t_exit;
    });
    return best;
}

std::size_t TriangleGrid::count_crossings(const Vec3& origin, const Vec3& dir) const {
    const auto& V = mesh_.vertices;
    const auto& T = mesh_.triangles;
    std::vector<std::uint32_t> hits;  // a triangle is listed in every cell it meets
    walk(origin, dir, [&](const std::uint32_t* first, const std::uint32_t* last, double) {
        for (const std::uint32_t* it = first; it != last; ++it) {
            const auto& t = T[*it];
            // No slack: a widened triangle would count a crossing twice.
            if (ray_triangle(origin, dir, V[t[0]], V[t[1]], V[t[2]], 0) > 0) hits.push_back(*it);
        }
        return true;
    });
    std::sort(hits.begin(), hits.end());
    return std::size_t(std::unique(hits.begin(), hits.end()) - hits.begin());
}

}  // namespace snvr
