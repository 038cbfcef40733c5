// TriangleGrid: a uniform bucket grid over triangles, closest-triangle search by
// cells in order of their distance and ray casting by a 3D DDA walk (Amanatides &
// Woo). Every query returns what testing all triangles would: cells and triangles
// are skipped only when a bound, with room for rounding, shows they cannot win.
#include "mesh/cell_rings.hpp"
#include "mesh/float_rounding.hpp"
#include "threads_here.hpp"
#include "mesh/triangle_grid.hpp"

#include <omp.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "snvr/error.hpp"
#include "geometry/vec3_math.hpp"

namespace snvr {
namespace {

using detail::round_down;
using detail::round_up;

using detail::threads_here;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr float kInfF = std::numeric_limits<float>::infinity();
// Finer cells mean fewer triangles tested per query, but 4 bytes per cell and
// more cells per triangle (each one 10 bytes): on the bunny at 256 cells, 2
// to 16 cells per triangle cost about the same, 2 the least memory.
constexpr double kCellsPerTriangle = 2;
// The float box tests count boxes as this much larger, relative to the largest
// coordinate involved (in box steps): far above the rounding of floats (2^-24).
constexpr double kFloatSlack = 0x1p-20;

// An item's box is kept only near its cell, in bytes: byte v stands for (v - kBoxLow)
// / kBoxSteps cells from the cell's low corner, so a box covers at most half a cell
// either side of the cell. That is all a query needs: the nearest point of a triangle,
// or a ray's crossing with it, lies in a cell the triangle is listed in, and each query
// visits that cell (closest() every cell nearer than the best, a ray every cell it
// passes); in the other cells the box may dismiss the triangle, as it does here.
// A third of the memory of float boxes of the whole triangle, and tighter.
constexpr int kBoxSteps = 128;
constexpr int kBoxLow = 64;

// A box side at `cells` from the cell's low corner as a byte, rounded outwards (the
// 1e-6 steps cover the rounding of `cells`) and cut back to the bytes' range.
std::uint8_t step_down(double cells) {
    return std::uint8_t(std::clamp(std::floor(cells * kBoxSteps - 1e-6) + kBoxLow, 0.0, 255.0));
}
std::uint8_t step_up(double cells) {
    return std::uint8_t(std::clamp(std::ceil(cells * kBoxSteps + 1e-6) + kBoxLow, 0.0, 255.0));
}

// Cell offsets up to this many cells away on each axis are visited in order of
// their distance by closest(); farther ones in growing rings.
constexpr int kNear = 4;

struct NearOffset {
    std::array<int, 3> d;
    double lower_sq;  // squared distance, in cells, from any point of cell 0 to cell d
};

// The offsets of the (2 kNear + 1)^3 cells around a cell, nearest first.
const std::vector<NearOffset>& near_offsets() {
    static const std::vector<NearOffset> table = [] {
        std::vector<std::pair<double, NearOffset>> keyed;
        for (int z = -kNear; z <= kNear; ++z)
            for (int y = -kNear; y <= kNear; ++y)
                for (int x = -kNear; x <= kNear; ++x) {
                    double lower = 0;
                    for (int o : {x, y, z}) lower += double(std::max(0, std::abs(o) - 1)) * std::max(0, std::abs(o) - 1);
                    // Among equal bounds, nearer centres first: they hold the likelier winners.
                    keyed.push_back({lower * 1024 + x * x + y * y + z * z, NearOffset{{x, y, z}, lower}});
                }
        std::stable_sort(keyed.begin(), keyed.end(),
                         [](const auto& a, const auto& b) { return a.first < b.first; });
        std::vector<NearOffset> out;
        for (const auto& k : keyed) out.push_back(k.second);
        return out;
    }();
    return table;
}


// floor(x) clamped to [0, n - 1] (NaN gives 0).
int clamp_cell(double x, int n) {
    if (!(x > 0)) return 0;
    if (x >= double(n - 1)) return n - 1;
    return int(x);  // truncation is floor for x > 0
}

// Four floats at a time: GCC's and Clang's vector extensions, else plain arrays
// (SNVR_PLAIN_FLOAT4 forces those, to test them).
#if defined(__GNUC__) && !defined(SNVR_PLAIN_FLOAT4)
typedef float F4 __attribute__((vector_size(16)));
typedef std::int32_t M4 __attribute__((vector_size(16)));
F4 load4(const std::uint8_t* p) {
#if defined(__SSE2__)  // widened in registers: GCC converts a 4-byte vector lane by lane
    std::int32_t bytes;
    std::memcpy(&bytes, p, sizeof bytes);
    const __m128i zero = _mm_setzero_si128();
    const __m128i words = _mm_unpacklo_epi8(_mm_cvtsi32_si128(bytes), zero);
    return F4(_mm_cvtepi32_ps(_mm_unpacklo_epi16(words, zero)));
#else
    return F4{float(p[0]), float(p[1]), float(p[2]), float(p[3])};
#endif
}
F4 splat(float x) { return F4{x, x, x, x}; }
#if defined(__SSE__)
F4 max4(F4 a, F4 b) { return __builtin_ia32_maxps(a, b); }
F4 min4(F4 a, F4 b) { return __builtin_ia32_minps(a, b); }
#else
F4 max4(F4 a, F4 b) {
    const M4 m = a > b;
    return F4((m & M4(a)) | (~m & M4(b)));
}
F4 min4(F4 a, F4 b) {
    const M4 m = a < b;
    return F4((m & M4(a)) | (~m & M4(b)));
}
#endif
M4 less_eq(F4 a, F4 b) { return a <= b; }
unsigned lanes(M4 m) {
#if defined(__SSE__)
    return unsigned(__builtin_ia32_movmskps(F4(m)));
#else
    return (m[0] ? 1u : 0u) | (m[1] ? 2u : 0u) | (m[2] ? 4u : 0u) | (m[3] ? 8u : 0u);
#endif
}
int lowest_lane(unsigned m) { return __builtin_ctz(m); }
#else
struct F4 {
    float v[4];
};
struct M4 {
    bool v[4];
};
F4 load4(const std::uint8_t* p) { return {{float(p[0]), float(p[1]), float(p[2]), float(p[3])}}; }
F4 splat(float x) { return {{x, x, x, x}}; }
template <class Op>
F4 each(F4 a, F4 b, Op op) {
    return {{op(a.v[0], b.v[0]), op(a.v[1], b.v[1]), op(a.v[2], b.v[2]), op(a.v[3], b.v[3])}};
}
F4 operator+(F4 a, F4 b) { return each(a, b, [](float x, float y) { return x + y; }); }
F4 operator-(F4 a, F4 b) { return each(a, b, [](float x, float y) { return x - y; }); }
F4 operator*(F4 a, F4 b) { return each(a, b, [](float x, float y) { return x * y; }); }
F4 max4(F4 a, F4 b) { return each(a, b, [](float x, float y) { return x > y ? x : y; }); }
F4 min4(F4 a, F4 b) { return each(a, b, [](float x, float y) { return x < y ? x : y; }); }
M4 less_eq(F4 a, F4 b) { return {{a.v[0] <= b.v[0], a.v[1] <= b.v[1], a.v[2] <= b.v[2], a.v[3] <= b.v[3]}}; }
unsigned lanes(M4 m) { return (m.v[0] ? 1u : 0u) | (m.v[1] ? 2u : 0u) | (m.v[2] ? 4u : 0u) | (m.v[3] ? 8u : 0u); }
int lowest_lane(unsigned m) {
    int k = 0;
    while (!(m & 1u)) {
        m >>= 1;
        ++k;
    }
    return k;
}
#endif

// The lanes of a group of four items that still belong to a range with `left` items.
unsigned valid_lanes(std::uint32_t left) { return left >= 4 ? 15u : (1u << left) - 1u; }

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

int face_side(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
    const Vec3 n = cross(ab, ac);
    const double nn = dot(n, n), s = dot(ap, n);
    // p's foot on the plane in barycentric coordinates, times |n|^2.
    const Vec3 bp = sub(p, b), cp = sub(p, c);
    const double wa = dot(cross(bp, cp), n), wb = dot(cross(cp, ap), n), wc = dot(cross(ap, bp), n);
    // Margins far above rounding: near an edge or a corner another triangle may be as
    // near, and near a corner its side can differ (a saddle).
    constexpr double kClear = 1e-6;
    if (!(nn > 0) || !(wa > kClear * nn && wb > kClear * nn && wc > kClear * nn)) return 0;
    if (!(s * s > 1e-12 * nn * dot(ap, ap))) return 0;
    return s > 0 ? 1 : -1;
}

// A point against item boxes, four at a time: lower bounds on the squared
// distance, in box steps, from the point to each box, shrunk by the rounding of floats.
class TriangleGrid::PointBoxes {
public:
    PointBoxes(const TriangleGrid& g, const Vec3& p) : g_(g) {
        for (int d = 0; d < 3; ++d) p_cells_[d] = (p[d] - g.lo_[d]) * g.inv_size_;
    }
    // The point as seen from cell (x, y, z)'s boxes.
    void move_to(int x, int y, int z) {
        const int at[3] = {x, y, z};
        double reach = 256;
        for (int d = 0; d < 3; ++d) {
            const double steps = (p_cells_[d] - at[d]) * kBoxSteps + kBoxLow;
            p_[d] = splat(float(steps));
            reach = std::max(reach, std::fabs(steps));
        }
        slack_ = splat(float(reach * kFloatSlack));
    }
    // The items k .. k + 3 whose box may come nearer than sqrt(limit) steps, as bits.
    unsigned near(std::uint32_t k, F4 limit) const {
        const F4 zero = splat(0);
        F4 sum = zero;
        for (int d = 0; d < 3; ++d) {
            const F4 gap = max4(load4(g_.plane(d) + k) - p_[d], p_[d] - load4(g_.plane(3 + d) + k));
            const F4 g = max4(gap - slack_, zero);
            sum = sum + g * g;
        }
        return lanes(less_eq(sum, limit));
    }
    // best_sq (world units) as a float limit in steps, rounded up with room to spare.
    F4 limit(double best_sq) const {
        const double steps = g_.inv_size_ * kBoxSteps;
        return splat(float(best_sq * steps * steps * (1 + 1e-5)));
    }

private:
    const TriangleGrid& g_;
    std::array<double, 3> p_cells_;
    std::array<F4, 3> p_;
    F4 slack_;
};

// A ray against item boxes, four at a time: the slab test against each box grown
// by the margin (which covers the rounding of the exact test and the sliver that
// first_hit widens triangles by) and by the rounding of floats.
class TriangleGrid::RayBoxes {
public:
    // inv: 1 / dir on each axis (so that the walk and the boxes share three divisions).
    RayBoxes(const TriangleGrid& g, const Vec3& o, const Vec3& dir, const std::array<double, 3>& inv_dir) : g_(g) {
        for (int d = 0; d < 3; ++d) {
            down_[d] = dir[d] < 0;
            o_cells_[d] = (o[d] - g.lo_[d]) * g.inv_size_;
            // t per box step along this axis; a coordinate the ray keeps gets a huge
            // slope instead of a branch: a box off the ray's line by more than the
            // margin then lies beyond any t.
            double inv = g.size_ * inv_dir[d] / kBoxSteps;
            if (!(std::fabs(inv) <= 1e30)) inv = down_[d] ? -1e30 : 1e30;
            inv_[d] = splat(float(inv));
            near_[d] = g.plane(down_[d] ? 3 + d : d);
            far_[d] = g.plane(down_[d] ? d : 3 + d);
        }
    }
    // The ray as seen from cell c's boxes.
    void move_to(const std::array<int, 3>& c) {
        double reach = 256;
        std::array<double, 3> steps;
        for (int d = 0; d < 3; ++d) {
            steps[d] = (o_cells_[d] - c[d]) * kBoxSteps + kBoxLow;
            reach = std::max(reach, std::fabs(steps[d]));
        }
        const double m = g_.margin_ * kBoxSteps + reach * kFloatSlack;
        for (int d = 0; d < 3; ++d) {
            near_o_[d] = splat(float(down_[d] ? steps[d] - m : steps[d] + m));
            far_o_[d] = splat(float(down_[d] ? steps[d] + m : steps[d] - m));
        }
    }
    // The items k .. k + 3 whose box may meet origin + t dir for some t in [ta, tb], as bits.
    unsigned meet(std::uint32_t k, F4 ta, F4 tb) const {
        for (int d = 0; d < 3; ++d) {
            ta = max4(ta, (load4(near_[d] + k) - near_o_[d]) * inv_[d]);
            tb = min4(tb, (load4(far_[d] + k) - far_o_[d]) * inv_[d]);
        }
        return lanes(less_eq(ta, tb));
    }

private:
    const TriangleGrid& g_;
    std::array<bool, 3> down_;
    std::array<double, 3> o_cells_;
    std::array<F4, 3> inv_, near_o_, far_o_;
    std::array<const std::uint8_t*, 3> near_, far_;  // the planes each axis enters and leaves by
};

TriangleGrid::TriangleGrid(const Mesh& mesh) : mesh_(mesh) {
    const std::size_t nt = mesh.triangles.size();
    if (nt == 0) return;
    if (nt >= std::numeric_limits<std::uint32_t>::max()) throw ResourceError("TriangleGrid: more than 2^32 triangles");
    size_cells();
    fill_cells();
}

void TriangleGrid::size_cells() {
    const auto& V = mesh_.vertices;
    const auto& T = mesh_.triangles;
    const std::size_t nt = T.size();
    // Bounds and summed largest box side in fixed chunks, so that the grid does
    // not depend on the number of threads.
    constexpr std::size_t kChunk = 1 << 14;
    const std::size_t n_chunks = (nt + kChunk - 1) / kChunk;
    std::vector<std::array<double, 7>> part(n_chunks);
#pragma omp parallel for schedule(static) if (nt > 20000)
    for (std::ptrdiff_t c = 0; c < std::ptrdiff_t(n_chunks); ++c) {
        std::array<double, 7> acc{kInf, kInf, kInf, -kInf, -kInf, -kInf, 0};
        for (std::size_t t = std::size_t(c) * kChunk; t < std::min(nt, std::size_t(c + 1) * kChunk); ++t) {
            double side = 0;
            for (int d = 0; d < 3; ++d) {
                const double a = V[T[t][0]][d], b = V[T[t][1]][d], e = V[T[t][2]][d];
                const double mn = std::min({a, b, e}), mx = std::max({a, b, e});
                acc[d] = std::min(acc[d], mn);
                acc[3 + d] = std::max(acc[3 + d], mx);
                side = std::max(side, mx - mn);
            }
            acc[6] += side;
        }
        part[c] = acc;
    }
    lo_ = {kInf, kInf, kInf};
    hi_ = {-kInf, -kInf, -kInf};
    double extent = 0;  // summed largest box side of the triangles
    for (const auto& acc : part) {
        for (int d = 0; d < 3; ++d) {
            lo_[d] = std::min(lo_[d], acc[d]);
            hi_[d] = std::max(hi_[d], acc[3 + d]);
        }
        extent += acc[6];
    }
    // Cells no smaller than the mean triangle (so a triangle meets few cells) and
    // no more than kCellsPerTriangle per triangle.
    const Vec3 span = sub(hi_, lo_);
    const double diag = std::sqrt(dot(span, span));
    size_ = std::max({extent / double(nt), std::cbrt(span[0] * span[1] * span[2] / (kCellsPerTriangle * double(nt))),
                      diag * 1e-6});
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
    inv_size_ = 1 / size_;
    double max_abs = 0;
    for (int d = 0; d < 3; ++d) max_abs = std::max({max_abs, std::fabs(lo_[d]), std::fabs(hi_[d])});
    // Far above the rounding of coordinates and of the exact tests, far below a triangle.
    margin_ = (1e-7 * (diag + size_) + 1e-12 * max_abs) * inv_size_;
    tiny_sq_ = 1e-10 * size_ * size_;
}

// Calls visit(cell index, x, y, z, box) for every cell (x, y, z) with z in
// [z_lo, z_hi) that triangle t's box meets (grown by a sliver, so that a point on
// a cell face finds the triangle from both cells whatever the rounding); box is
// the box in cells from lo_ (lo x y z, hi x y z). Worked out again from the
// corners by each pass: cheaper than keeping them.
template <class Visit>
void TriangleGrid::for_box_cells(std::size_t t, int z_lo, int z_hi, Visit&& visit) const {
    const auto& V = mesh_.vertices;
    const auto& T = mesh_.triangles;
    const Vec3 &a = V[T[t][0]], &b = V[T[t][1]], &c = V[T[t][2]];
    const double z_min = (std::min({a[2], b[2], c[2]}) - lo_[2]) * inv_size_;
    const double z_max = (std::max({a[2], b[2], c[2]}) - lo_[2]) * inv_size_;
    const int z0 = std::max(z_lo, clamp_cell(z_min - 1e-9, n_[2]));
    const int z1 = std::min(z_hi - 1, clamp_cell(z_max + 1e-9, n_[2]));
    if (z0 > z1) return;
    const double x_min = (std::min({a[0], b[0], c[0]}) - lo_[0]) * inv_size_;
    const double x_max = (std::max({a[0], b[0], c[0]}) - lo_[0]) * inv_size_;
    const double y_min = (std::min({a[1], b[1], c[1]}) - lo_[1]) * inv_size_;
    const double y_max = (std::max({a[1], b[1], c[1]}) - lo_[1]) * inv_size_;
    const int y0 = clamp_cell(y_min - 1e-9, n_[1]), y1 = clamp_cell(y_max + 1e-9, n_[1]);
    const int x0 = clamp_cell(x_min - 1e-9, n_[0]), x1 = clamp_cell(x_max + 1e-9, n_[0]);
    const std::array<double, 6> box{x_min, y_min, z_min, x_max, y_max, z_max};
    for (int z = z0; z <= z1; ++z)
        for (int y = y0; y <= y1; ++y) {
            const std::size_t row = index(0, y, z);
            for (int x = x0; x <= x1; ++x) visit(row + std::size_t(x), x, y, z, box);
        }
}

void TriangleGrid::fill_cells() {
    const std::size_t nt = mesh_.triangles.size();
    // Counted and filled in slabs of z, one thread each, every slab in triangle
    // order: each cell lists its triangles in ascending order whatever the threads.
    const std::size_t n_cells = std::size_t(n_[0]) * std::size_t(n_[1]) * std::size_t(n_[2]);
    const int slabs = std::max(1, std::min(n_[2], nt > 20000 ? threads_here() : 1));
    const auto slab_z = [&](int s) { return int(std::int64_t(n_[2]) * s / slabs); };
    start_.assign(n_cells + 1, 0);
    std::uint32_t* count = start_.data() + 1;
#pragma omp parallel for schedule(static, 1) if (slabs > 1)
    for (int s = 0; s < slabs; ++s) {
        const int z_lo = slab_z(s), z_hi = slab_z(s + 1);
        for (std::size_t t = 0; t < nt; ++t)
            for_box_cells(t, z_lo, z_hi, [&](std::size_t c, int, int, int, const std::array<double, 6>&) { ++count[c]; });
    }
    std::uint64_t total = 0;
    for (std::size_t c = 1; c <= n_cells; ++c) {
        total += start_[c];
        if (total >= std::numeric_limits<std::uint32_t>::max())
            throw ResourceError("TriangleGrid: more than 2^32 cell entries");
        start_[c] = std::uint32_t(total);
    }
    // Items padded by a group of four (zeros), so that whole groups can be read.
    stride_ = std::size_t(total) + 4;
    items_.reset(new std::uint32_t[stride_]);
    item_boxes_.reset(new std::uint8_t[6 * stride_]);
    for (std::size_t k = total; k < stride_; ++k) {
        items_[k] = 0;
        for (int j = 0; j < 6; ++j) item_boxes_[std::size_t(j) * stride_ + k] = 0;
    }
    // start_[c] serves as cell c's write cursor, ending at the start of c + 1.
#pragma omp parallel for schedule(static, 1) if (slabs > 1)
    for (int s = 0; s < slabs; ++s) {
        const int z_lo = slab_z(s), z_hi = slab_z(s + 1);
        std::uint32_t* cursor = start_.data();
        std::uint32_t* items = items_.get();
        std::uint8_t* planes = item_boxes_.get();
        for (std::size_t t = 0; t < nt; ++t)
            for_box_cells(t, z_lo, z_hi, [&](std::size_t c, int x, int y, int z, const std::array<double, 6>& box) {
                const std::uint32_t k = cursor[c]++;
                items[k] = std::uint32_t(t);
                const int at[3] = {x, y, z};
                for (int d = 0; d < 3; ++d) {
                    planes[std::size_t(d) * stride_ + k] = step_down(box[d] - at[d]);
                    planes[std::size_t(3 + d) * stride_ + k] = step_up(box[3 + d] - at[d]);
                }
            });
    }
    std::copy_backward(start_.begin(), start_.end() - 1, start_.end());
    start_[0] = 0;
}

int TriangleGrid::cell(int d, double v) const { return clamp_cell((v - lo_[d]) * inv_size_, n_[d]); }

TriangleGrid::Cells TriangleGrid::cells() const {
    Cells c;
    if (start_.empty()) return c;
    c.lo = lo_;
    c.size = size_;
    c.inv_size = inv_size_;
    c.margin = margin_;
    c.n = n_;
    c.start = start_.data();
    c.cells = start_.size() - 1;
    c.items = items_.get();
    c.boxes = item_boxes_.get();
    c.stride = stride_;
    return c;
}

double TriangleGrid::cell_gap_sq(const Vec3& p, int x, int y, int z) const {
    return detail::cell_gap_sq(lo_, size_, {x, y, z}, p);
}

void TriangleGrid::scan_cell(const Vec3& p, PointBoxes& boxes, int x, int y, int z, Closest& best) const {
    const auto& V = mesh_.vertices;
    const auto& T = mesh_.triangles;
    const std::size_t i = index(x, y, z);
    const std::uint32_t last = start_[i + 1];
    if (start_[i] == last) return;
    boxes.move_to(x, y, z);
    F4 limit = boxes.limit(best.dist_sq);
    for (std::uint32_t k = start_[i]; k < last; k += 4)
        for (unsigned m = boxes.near(k, limit) & valid_lanes(last - k); m; m &= m - 1) {
            const std::uint32_t tri = items_[k + std::uint32_t(lowest_lane(m))];
            const auto& t = T[tri];
            // The distance to the triangle's plane first: a box beside a slanted triangle
            // lets through many that the plane alone shows too far (1e-6 covers its rounding).
            const Vec3 &a = V[t[0]], &b = V[t[1]], &c = V[t[2]];
            const Vec3 n = cross(sub(b, a), sub(c, a));
            const double nn = dot(n, n), s = dot(sub(p, a), n);
            if (nn > 0 && beyond(s * s / nn * (1 - 1e-6), best.dist_sq)) continue;
            const double d = point_triangle_dist_sq(p, a, b, c);
            // Of two at one distance the lower numbered, whatever order the cells come in (a
            // mesh held in slabs finds the same: check/slab_queries.hpp).
            if (d < best.dist_sq || (d == best.dist_sq && best.triangle != none && tri < best.triangle)) {
                best = {d, tri};
                limit = boxes.limit(d);
            }
        }
}

TriangleGrid::Closest TriangleGrid::closest(const Vec3& p, double bound_sq) const {
    const Closest nothing{kInf, none};
    if (start_.empty() || !(bound_sq > 0)) return nothing;
    Closest best{bound_sq, none};
    PointBoxes boxes(*this, p);
    // Only a triangle with a distance below the bound replaces it.
    const auto result = [&] { return best.triangle == none ? nothing : best; };
    const std::array<int, 3> c{cell(0, p[0]), cell(1, p[1]), cell(2, p[2])};
    bool in_grid = true;
    for (int d = 0; d < 3; ++d) in_grid = in_grid && p[d] >= lo_[d] && p[d] <= lo_[d] + n_[d] * size_;
    int first_ring = 0;
    if (in_grid) {
        // p lies in cell c (up to rounding, which the 1e-6 covers): visit the cells
        // around it nearest first, until the rest are all farther than the best.
        const double cell_sq = size_ * size_ * (1 - 1e-6);
        // The squared gap from p to the cells kNear or fewer away along each axis
        // (infinite outside the grid), so that a cell's gap is three lookups.
        std::array<std::array<double, 2 * kNear + 1>, 3> gap;
        for (int d = 0; d < 3; ++d)
            for (int o = -kNear; o <= kNear; ++o) {
                const int at = c[d] + o;
                const double lo = lo_[d] + at * size_;
                const double g = std::max(0.0, std::max(lo - p[d], p[d] - (lo + size_)));
                gap[d][o + kNear] = at < 0 || at >= n_[d] ? kInf : g * g;
            }
        bool done = false;
        for (const NearOffset& o : near_offsets()) {
            if (beyond(o.lower_sq * cell_sq, best.dist_sq)) {
                done = true;
                break;
            }
            const double cell_gap = gap[0][o.d[0] + kNear] + gap[1][o.d[1] + kNear] + gap[2][o.d[2] + kNear];
            if (cell_gap == kInf || beyond(cell_gap, best.dist_sq)) continue;  // off the grid, or too far
            scan_cell(p, boxes, c[0] + o.d[0], c[1] + o.d[1], c[2] + o.d[2], best);
        }
        if (done) return result();
        first_ring = kNear + 1;
    }
    for (int r = first_ring;; ++r) {
        detail::for_ring(c, r, n_, [&](int x, int y, int z) {
            if (!beyond(cell_gap_sq(p, x, y, z), best.dist_sq)) scan_cell(p, boxes, x, y, z, best);
        });
        const double bound = detail::beyond_ring(lo_, size_, n_, c, r, p);
        if (bound == kInf || beyond(bound * bound, best.dist_sq)) return result();
    }
}

void TriangleGrid::near(const Vec3& p, double r, std::vector<std::uint32_t>& out, std::vector<std::uint64_t>& seen) const {
    out.clear();
    const std::size_t words = (mesh_.triangles.size() + 63) / 64;
    if (seen.size() < words) seen.assign(words, 0);
    if (start_.empty() || !(r >= 0)) return;
    PointBoxes boxes(*this, p);
    const F4 limit = boxes.limit(r * r);
    const double reach = r * (1 + 1e-9) + margin_ * size_;
    int c0[3], c1[3];
    for (int d = 0; d < 3; ++d) {
        c0[d] = cell(d, p[d] - reach);
        c1[d] = cell(d, p[d] + reach);
    }
    for (int z = c0[2]; z <= c1[2]; ++z)
        for (int y = c0[1]; y <= c1[1]; ++y)
            for (int x = c0[0]; x <= c1[0]; ++x) {
                const std::size_t i = index(x, y, z);
                const std::uint32_t last = start_[i + 1];
                if (start_[i] == last || beyond(cell_gap_sq(p, x, y, z), r * r)) continue;
                boxes.move_to(x, y, z);
                for (std::uint32_t k = start_[i]; k < last; k += 4)
                    for (unsigned m = boxes.near(k, limit) & valid_lanes(last - k); m; m &= m - 1) {
                        const std::uint32_t t = items_[k + std::uint32_t(lowest_lane(m))];
                        std::uint64_t& word = seen[t >> 6];
                        const std::uint64_t bit = std::uint64_t(1) << (t & 63);
                        if (!(word & bit)) word |= bit, out.push_back(t);
                    }
            }
    for (std::uint32_t t : out) seen[t >> 6] &= ~(std::uint64_t(1) << (t & 63));
}

template <class Visit>
void TriangleGrid::walk(const Vec3& origin, const Vec3& dir, const std::array<double, 3>& inv, const Visit& visit) const {
    if (start_.empty()) return;
    // Clip the ray to the grid's box (slab test). Products with 1 / dir: the
    // traversal only has to be right up to rounding, which the lists' slack covers.
    double t0 = 0, t1 = kInf;
    for (int d = 0; d < 3; ++d) {
        const double box_lo = lo_[d], box_hi = lo_[d] + n_[d] * size_;
        if (dir[d] == 0) {
            if (origin[d] < box_lo || origin[d] > box_hi) return;
            continue;
        }
        double a = (box_lo - origin[d]) * inv[d], b = (box_hi - origin[d]) * inv[d];
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
            t_next[d] = (lo_[d] + (c[d] + 1) * size_ - origin[d]) * inv[d];
            t_delta[d] = size_ * inv[d];
        } else if (dir[d] < 0) {
            step[d] = -1;
            t_next[d] = (lo_[d] + c[d] * size_ - origin[d]) * inv[d];
            t_delta[d] = -size_ * inv[d];
        } else {
            step[d] = 0;
            t_next[d] = t_delta[d] = kInf;
        }
    }
    for (;;) {
        const int d = t_next[0] < t_next[1] ? (t_next[0] < t_next[2] ? 0 : 2) : (t_next[1] < t_next[2] ? 1 : 2);
        const std::size_t i = index(c[0], c[1], c[2]);
        if (start_[i] != start_[i + 1] && !visit(start_[i], start_[i + 1], t_next[d], c)) return;
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
    const std::array<double, 3> inv{1 / dir[0], 1 / dir[1], 1 / dir[2]};
    RayBoxes boxes(*this, origin, dir, inv);
    const F4 ta = splat(round_down(t_min));
    F4 tb = splat(kInfF);
    walk(origin, dir, inv, [&](std::uint32_t first, std::uint32_t last, double t_exit, const std::array<int, 3>& cell) {
        boxes.move_to(cell);
        for (std::uint32_t k = first; k < last; k += 4)
            for (unsigned m = boxes.meet(k, ta, tb) & valid_lanes(last - k); m; m &= m - 1) {
                const std::uint32_t tri = items_[k + std::uint32_t(lowest_lane(m))];
                const auto& t = T[tri];
                if (t[0] == skip_vertex || t[1] == skip_vertex || t[2] == skip_vertex) continue;
                const double s = ray_triangle(origin, dir, V[t[0]], V[t[1]], V[t[2]], 1e-9);
                if (s > t_min && s < best.t) {
                    best = {s, tri};
                    tb = splat(round_up(s));
                }
            }
        // A hit beyond this cell may still be beaten by one in a later cell.
        return best.t > t_exit;
    });
    return best;
}

std::size_t TriangleGrid::count_crossings(const Vec3& origin, const Vec3& dir) const {
    const auto& V = mesh_.vertices;
    const auto& T = mesh_.triangles;
    const std::array<double, 3> inv{1 / dir[0], 1 / dir[1], 1 / dir[2]};
    RayBoxes boxes(*this, origin, dir, inv);
    const F4 ta = splat(0), tb = splat(kInfF);
    // A triangle is listed in every cell it meets: keep the hits to count each once.
    constexpr std::size_t kLocal = 64;
    std::uint32_t local[kLocal];
    std::vector<std::uint32_t> more;
    std::size_t n = 0;
    walk(origin, dir, inv, [&](std::uint32_t first, std::uint32_t last, double, const std::array<int, 3>& cell) {
        boxes.move_to(cell);
        for (std::uint32_t k = first; k < last; k += 4)
            for (unsigned m = boxes.meet(k, ta, tb) & valid_lanes(last - k); m; m &= m - 1) {
                const std::uint32_t tri = items_[k + std::uint32_t(lowest_lane(m))];
                const auto& t = T[tri];
                // No slack: a widened triangle would count a crossing twice.
                if (!(ray_triangle(origin, dir, V[t[0]], V[t[1]], V[t[2]], 0) > 0)) continue;
                if (n < kLocal)
                    local[n++] = tri;
                else
                    more.push_back(tri);
            }
        return true;
    });
    if (more.empty()) {
        std::sort(local, local + n);
        return std::size_t(std::unique(local, local + n) - local);
    }
    more.insert(more.end(), local, local + n);
    std::sort(more.begin(), more.end());
    return std::size_t(std::unique(more.begin(), more.end()) - more.begin());
}

}  // namespace snvr
