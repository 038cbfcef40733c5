// Mesh validity report and point-in-mesh counting.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "geometry/disjoint_sets.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh.hpp"

namespace snvr {
namespace {

using Tri = std::array<std::uint32_t, 3>;

// Below these sizes, waking threads costs more than it saves.
constexpr std::size_t kParallelTriangles = 1 << 15, kParallelPoints = 1 << 10;

bool degenerate(const Tri& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; }

void check_indices(const Mesh& mesh, const char* who) {
    const std::size_t nv = mesh.vertices.size();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (std::uint32_t v : mesh.triangles[t])
            if (v >= nv)
                throw InputError(std::string(who) + ": triangle " + std::to_string(t) + " uses vertex " +
                                 std::to_string(v) + " of " + std::to_string(nv));
}

// Items grouped by bucket (counting sort): bucket b is items[start[b] .. start[b+1]).
template <class Item>
struct Buckets {
    std::vector<std::size_t> start;
    std::vector<Item> items;
};

// ForEach(source, emit) calls emit(bucket, item) for each item of one source.
// Sources run in parallel, so the order within a bucket is unspecified;
// callers sort a bucket or do not depend on its order.
template <class Item, class ForEach>
Buckets<Item> bucket_items(std::size_t n_buckets, std::size_t n_sources, [[maybe_unused]] bool parallel,
                            const ForEach& for_each) {
    Buckets<Item> b;
    b.start.assign(n_buckets + 1, 0);
    std::size_t* count = b.start.data() + 1;
#pragma omp parallel for schedule(static) if (parallel)
    for (std::ptrdiff_t src = 0; src < std::ptrdiff_t(n_sources); ++src)
        for_each(std::size_t(src), [&](std::size_t bucket, Item) {
#pragma omp atomic
            ++count[bucket];
        });
    for (std::size_t i = 0; i < n_buckets; ++i) b.start[i + 1] += b.start[i];
    b.items.resize(b.start[n_buckets]);
    std::vector<std::size_t> cursor(b.start.begin(), b.start.end() - 1);
    std::size_t* next = cursor.data();
    Item* items = b.items.data();
#pragma omp parallel for schedule(static) if (parallel)
    for (std::ptrdiff_t src = 0; src < std::ptrdiff_t(n_sources); ++src)
        for_each(std::size_t(src), [&](std::size_t bucket, Item item) {
            std::size_t at;
#pragma omp atomic capture
            at = next[bucket]++;
            items[at] = item;
        });
    return b;
}

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

// A triangle's footprint seen from +z: its xy box, rounded outwards to
// floats (a box only needs to contain the triangle) to halve the memory traffic.
struct Footprint {
    std::array<float, 2> lo, hi;
    std::uint32_t tri;
};

float round_down(double v) {
    const float f = float(v);
    return double(f) > v ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
float round_up(double v) {
    const float f = float(v);
    return double(f) < v ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

// Uniform grid over xy; each cell lists the footprints whose box meets it.
class ColumnGrid {
public:
    ColumnGrid(const std::vector<Footprint>& feet, bool parallel) {
        lo_ = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
        hi_ = {-lo_[0], -lo_[1]};
        std::array<double, 2> extent{0, 0};  // summed box sizes
        for (const Footprint& f : feet)
            for (int d = 0; d < 2; ++d) {
                lo_[d] = std::min<double>(lo_[d], f.lo[d]);
                hi_[d] = std::max<double>(hi_[d], f.hi[d]);
                extent[d] += f.hi[d] - f.lo[d];
            }
        if (feet.empty()) return;
        // Cells twice the mean box: a box meets about two cells, a cell holds a
        // few dozen boxes per sheet (building is bound by scattered writes, so
        // finer cells cost more than they save); never more than ~2 cells per triangle.
        const double n = double(feet.size());
        std::array<double, 2> cells;
        for (int d = 0; d < 2; ++d)  // width and extent > 0: no footprint is edge-on
            cells[d] = std::clamp(std::floor((hi_[d] - lo_[d]) / (2 * extent[d] / n)), 1.0, 4096.0);
        const double excess = cells[0] * cells[1] / (2 * n + 16);
        for (int d = 0; d < 2; ++d) {
            if (excess > 1) cells[d] = std::max(1.0, std::floor(cells[d] / std::sqrt(excess)));
            n_[d] = int(cells[d]);
            inv_[d] = n_[d] / (hi_[d] - lo_[d]);
        }
        const auto for_each = [&](std::size_t f, const auto& emit) {
            const int x0 = cell(0, feet[f].lo[0]), x1 = cell(0, feet[f].hi[0]);
            const int y0 = cell(1, feet[f].lo[1]), y1 = cell(1, feet[f].hi[1]);
            for (int y = y0; y <= y1; ++y)
                for (int x = x0; x <= x1; ++x) emit(std::size_t(x) + std::size_t(n_[0]) * y, std::uint32_t(f));
        };
        cells_ = bucket_items<std::uint32_t>(std::size_t(n_[0]) * n_[1], feet.size(), parallel, for_each);
    }
    bool covers(double x, double y) const { return x >= lo_[0] && x <= hi_[0] && y >= lo_[1] && y <= hi_[1]; }
    // Footprints that may contain (x, y); the same monotone cell() for boxes and
    // queries guarantees a point on a box's edge still finds the box.
    std::pair<const std::uint32_t*, const std::uint32_t*> candidates(double x, double y) const {
        const std::size_t c = std::size_t(cell(0, x)) + std::size_t(n_[0]) * cell(1, y);
        return {cells_.items.data() + cells_.start[c], cells_.items.data() + cells_.start[c + 1]};
    }

private:
    int cell(int d, double v) const { return int(std::clamp(std::floor((v - lo_[d]) * inv_[d]), 0.0, n_[d] - 1.0)); }
    std::array<double, 2> lo_{}, hi_{}, inv_{};
    std::array<int, 2> n_{1, 1};
    Buckets<std::uint32_t> cells_;
};

}  // namespace

MeshReport check_mesh(const Mesh& mesh) {
    check_indices(mesh, "check_mesh");
    const auto& T = mesh.triangles;
    const std::size_t nv = mesh.vertices.size(), nt = T.size();
    if (nt > std::numeric_limits<std::uint32_t>::max()) throw ResourceError("check_mesh: more than 2^32 triangles");
    MeshReport r;
    r.vertices = nv;
    r.triangles = nt;
    for (const Tri& t : T) r.degenerate_triangles += degenerate(t);
    const bool parallel = nt >= kParallelTriangles;

    // Half-edges a -> b of the non-degenerate triangles, bucketed by a, as
    // b << 32 | triangle.  Bucket a lists each triangle around a exactly once;
    // sorted, it groups the half-edges by their other end.
    Buckets<std::uint64_t> out = bucket_items<std::uint64_t>(nv, nt, parallel, [&](std::size_t t, const auto& emit) {
        if (degenerate(T[t])) return;
        for (int c = 0; c < 3; ++c) emit(T[t][c], std::uint64_t(T[t][(c + 1) % 3]) << 32 | t);
    });
#pragma omp parallel for schedule(dynamic, 4096) if (parallel)
    for (std::ptrdiff_t v = 0; v < std::ptrdiff_t(nv); ++v)
        std::sort(out.items.begin() + std::ptrdiff_t(out.start[v]), out.items.begin() + std::ptrdiff_t(out.start[v + 1]));
    using Run = std::pair<const std::uint64_t*, const std::uint64_t*>;
    const auto bucket = [&](std::size_t v) -> Run {
        return {out.items.data() + out.start[v], out.items.data() + out.start[v + 1]};
    };
    const auto target = [](std::uint64_t item) { return std::uint32_t(item >> 32); };
    // The half-edges a -> b: a sub-range of bucket a.
    const auto half_edges = [&](std::uint32_t a, std::uint32_t b) -> Run {
        const auto [first, last] = bucket(a);
        const std::uint64_t* lo = std::lower_bound(first, last, std::uint64_t(b) << 32);
        const std::uint64_t* hi = lo;
        while (hi != last && target(*hi) == b) ++hi;
        return {lo, hi};
    };

    // Edges and fans, vertex by vertex.  An edge {v, x} is classified at v if
    // v -> x exists and either v < x or x -> v does not exist: exactly once.
    std::size_t boundary = 0, nonmanifold = 0, misoriented = 0, nonmanifold_vertices = 0;
#pragma omp parallel reduction(+ : boundary, nonmanifold, misoriented, nonmanifold_vertices) if (parallel)
    {
        std::vector<std::uint64_t> spokes;  // neighbour << 32 | local triangle index
        std::vector<std::uint32_t> parent;
#pragma omp for schedule(dynamic, 4096)
        for (std::ptrdiff_t vi = 0; vi < std::ptrdiff_t(nv); ++vi) {
            const auto v = std::uint32_t(vi);
            const auto [first, last] = bucket(v);
            for (const std::uint64_t* run = first; run != last;) {
                const std::uint32_t x = target(*run);
                const std::uint64_t* end = run;
                while (end != last && target(*end) == x) ++end;
                const Run back = half_edges(x, v);
                const std::ptrdiff_t fwd = end - run, bwd = back.second - back.first;
                if (v < x || bwd == 0) {
                    if (fwd + bwd == 1) ++boundary;
                    else if (fwd + bwd > 2) ++nonmanifold;
                    else if (bwd != 1) ++misoriented;  // both triangles run the same way
                }
                run = end;
            }

            // The triangles around v form one fan when linked through shared spokes.
            const std::size_t n = std::size_t(last - first);
            if (n < 2) continue;
            spokes.clear();
            parent.resize(n);
            for (std::size_t q = 0; q < n; ++q) {
                parent[q] = std::uint32_t(q);
                const Tri& tri = T[std::uint32_t(first[q])];
                const std::uint32_t b = target(first[q]);
                const auto c = std::uint32_t(std::uint64_t(tri[0]) + tri[1] + tri[2] - v - b);  // the third corner
                spokes.push_back(std::uint64_t(b) << 32 | q);
                spokes.push_back(std::uint64_t(c) << 32 | q);
            }
            std::sort(spokes.begin(), spokes.end());
            const auto find = [&](std::uint32_t y) {
                while (parent[y] != y) y = parent[y] = parent[parent[y]];
                return y;
            };
            std::size_t fans = n;
            for (std::size_t q = 1; q < spokes.size(); ++q)
                if (target(spokes[q]) == target(spokes[q - 1])) {
                    const std::uint32_t a = find(std::uint32_t(spokes[q])), b = find(std::uint32_t(spokes[q - 1]));
                    if (a != b) {
                        parent[a] = b;
                        --fans;
                    }
                }
            nonmanifold_vertices += fans > 1;
        }
    }
    r.boundary_edges = boundary;
    r.nonmanifold_edges = nonmanifold;
    r.misoriented_edges = misoriented;
    r.nonmanifold_vertices = nonmanifold_vertices;

    // Components: join the triangles of each run v -> x, and the run to x -> v.
    DisjointSets pieces(nt);
    for (std::size_t vi = 0; vi < nv; ++vi) {
        const auto v = std::uint32_t(vi);
        const auto [first, last] = bucket(v);
        for (const std::uint64_t* it = first; it != last; ++it) {
            if (it != first && target(it[-1]) == target(*it)) {
                pieces.unite(std::uint32_t(it[-1]), std::uint32_t(*it));
                continue;
            }
            const Run back = half_edges(target(*it), v);
            if (back.first != back.second) pieces.unite(std::uint32_t(*back.first), std::uint32_t(*it));
        }
    }
    for (std::size_t t = 0; t < nt; ++t)
        r.components += !degenerate(T[t]) && pieces.find(std::uint32_t(t)) == std::uint32_t(t);
    std::vector<std::uint64_t>().swap(out.items);

    // Divergence theorem about the bounding-box centre (less cancellation than
    // about the origin); fixed chunks keep the sum independent of thread count.
    Vec3 lo{0, 0, 0}, hi{0, 0, 0};
    if (nv) lo = hi = mesh.vertices[0];
    for (const Vec3& p : mesh.vertices)
        for (int d = 0; d < 3; ++d) {
            lo[d] = std::min(lo[d], p[d]);
            hi[d] = std::max(hi[d], p[d]);
        }
    const Vec3 o{0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
    // Six times the signed volume of the tetrahedron (o, triangle t).
    const auto six_volume = [&](std::size_t t) {
        const Vec3& A = mesh.vertices[T[t][0]];
        const Vec3& B = mesh.vertices[T[t][1]];
        const Vec3& C = mesh.vertices[T[t][2]];
        const double a0 = A[0] - o[0], a1 = A[1] - o[1], a2 = A[2] - o[2];
        const double b0 = B[0] - o[0], b1 = B[1] - o[1], b2 = B[2] - o[2];
        const double c0 = C[0] - o[0], c1 = C[1] - o[1], c2 = C[2] - o[2];
        return a0 * (b1 * c2 - b2 * c1) + a1 * (b2 * c0 - b0 * c2) + a2 * (b0 * c1 - b1 * c0);
    };
    constexpr std::size_t kChunk = 1 << 16;
    std::vector<double> partial((nt + kChunk - 1) / kChunk, 0.0);
#pragma omp parallel for schedule(static) if (parallel)
    for (std::ptrdiff_t c = 0; c < std::ptrdiff_t(partial.size()); ++c) {
        double sum = 0;
        for (std::size_t t = std::size_t(c) * kChunk; t < std::min(nt, std::size_t(c + 1) * kChunk); ++t)
            sum += six_volume(t);
        partial[c] = sum;
    }
    for (double p : partial) r.volume += p;
    r.volume /= 6;

    // Solid pieces: components enclosing positive volume (outer boundaries); the
    // negative ones are cavities inside them.
    std::vector<double> piece_volume(nt, 0.0);
    for (std::size_t t = 0; t < nt; ++t)
        if (!degenerate(T[t])) piece_volume[pieces.find(std::uint32_t(t))] += six_volume(t);
    for (double v : piece_volume) r.solids += v > 0;
    return r;
}

// Winding number along a ray in +z: every triangle the ray crosses counts +1
// if it faces up (leaving the solid) and -1 if it faces down.  For a closed,
// outward-oriented mesh this is the exact winding number (the generalised one
// is the same there), and "inside" means winding >= 1.  Points on the surface
// itself may go either way.
std::size_t count_points_inside(const Mesh& mesh, const PointSet& points) {
    check_indices(mesh, "count_points_inside");
    const auto& V = mesh.vertices;
    const auto& T = mesh.triangles;
    const bool parallel = points.size() >= kParallelPoints || T.size() >= kParallelTriangles;
    // Triangles that are edge-on seen from +z cannot be crossed by the perturbed ray.
    std::vector<char> seen(T.size());
#pragma omp parallel for schedule(static) if (parallel)
    for (std::ptrdiff_t t = 0; t < std::ptrdiff_t(T.size()); ++t)
        seen[t] = !degenerate(T[t]) && orient2d(V[T[t][0]], V[T[t][1]], V[T[t][2]][0], V[T[t][2]][1]) != 0;
    std::vector<std::uint32_t> kept;
    for (std::size_t t = 0; t < T.size(); ++t)
        if (seen[t]) kept.push_back(std::uint32_t(t));
    if (kept.empty()) return 0;
    std::vector<Footprint> feet(kept.size());
#pragma omp parallel for schedule(static) if (parallel)
    for (std::ptrdiff_t n = 0; n < std::ptrdiff_t(kept.size()); ++n) {
        const Tri& tri = T[kept[n]];
        for (int d = 0; d < 2; ++d) {
            const double a = V[tri[0]][d], b = V[tri[1]][d], c = V[tri[2]][d];
            feet[n].lo[d] = round_down(std::min({a, b, c}));
            feet[n].hi[d] = round_up(std::max({a, b, c}));
        }
        feet[n].tri = kept[n];
    }
    const ColumnGrid grid(feet, parallel);

    std::size_t inside = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : inside) if (parallel)
    for (std::ptrdiff_t n = 0; n < std::ptrdiff_t(points.size()); ++n) {
        const Vec3& p = points[n];
        if (!grid.covers(p[0], p[1])) continue;
        long winding = 0;
        const auto [first, last] = grid.candidates(p[0], p[1]);
        for (const std::uint32_t* it = first; it != last; ++it) {
            const Footprint& f = feet[*it];
            // Outside the closed box, the perturbed point is outside the triangle too.
            if (p[0] < f.lo[0] || p[0] > f.hi[0] || p[1] < f.lo[1] || p[1] > f.hi[1]) continue;
            const Tri& tri = T[f.tri];
            const Vec3 &a = V[tri[0]], &b = V[tri[1]], &c = V[tri[2]];
            const int s = orient2d_perturbed(a, b, p[0], p[1]);
            if (s == 0 || orient2d_perturbed(b, c, p[0], p[1]) != s || orient2d_perturbed(c, a, p[0], p[1]) != s)
                continue;
            // The column crosses the triangle; count it if the crossing is above p,
            // i.e. p lies on the side of the plane opposite to where the normal's z points.
            const double u0 = b[0] - a[0], u1 = b[1] - a[1], u2 = b[2] - a[2];
            const double w0 = c[0] - a[0], w1 = c[1] - a[1], w2 = c[2] - a[2];
            const double side = (p[0] - a[0]) * (u1 * w2 - u2 * w1) + (p[1] - a[1]) * (u2 * w0 - u0 * w2) +
                                (p[2] - a[2]) * (u0 * w1 - u1 * w0);
            if (side * s < 0) winding += s;
        }
        inside += winding > 0;
    }
    return inside;
}

}  // namespace snvr
