// Mesh validity report and point-in-mesh counting.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "snvr/error.hpp"
#include "snvr/mesh.hpp"

namespace snvr {
namespace {

using Tri = std::array<std::uint32_t, 3>;

bool degenerate(const Tri& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; }

void check_indices(const Mesh& mesh, const char* who) {
    const std::size_t nv = mesh.vertices.size();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (std::uint32_t v : mesh.triangles[t])
            if (v >= nv)
                throw InputError(std::string(who) + ": triangle " + std::to_string(t) + " uses vertex " +
                                 std::to_string(v) + " of " + std::to_string(nv));
}

class DisjointSets {
public:
    explicit DisjointSets(std::size_t n) : parent_(n) {
        for (std::size_t i = 0; i < n; ++i) parent_[i] = std::uint32_t(i);
    }
    std::uint32_t find(std::uint32_t x) {
        while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];  // path halving
        return x;
    }
    // The smaller root wins, which keeps the result independent of union order.
    void unite(std::uint32_t a, std::uint32_t b) {
        a = find(a);
        b = find(b);
        if (a != b) parent_[std::max(a, b)] = std::min(a, b);
    }

private:
    std::vector<std::uint32_t> parent_;
};

// Items grouped by bucket (counting sort): bucket b is items[start[b] .. start[b+1]).
struct Buckets {
    std::vector<std::size_t> start;
    std::vector<std::uint64_t> items;
};

template <class ForEach>  // ForEach(emit) calls emit(bucket, item) for every item
Buckets bucket_items(std::size_t n_buckets, const ForEach& for_each) {
    Buckets b;
    b.start.assign(n_buckets + 1, 0);
    for_each([&](std::size_t bucket, std::uint64_t) { ++b.start[bucket + 1]; });
    for (std::size_t i = 0; i < n_buckets; ++i) b.start[i + 1] += b.start[i];
    b.items.resize(b.start[n_buckets]);
    std::vector<std::size_t> fill(b.start.begin(), b.start.end() - 1);
    for_each([&](std::size_t bucket, std::uint64_t item) { b.items[fill[bucket]++] = item; });
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
        double q = terms[t];
        for (int i = 0; i < m; ++i) two_sum(q, e[i], q, e[i]);
        e[m++] = q;
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

// Uniform grid over xy; each cell lists the triangles whose xy bounding box meets it.
class ColumnGrid {
public:
    ColumnGrid(const Mesh& mesh, const std::vector<std::uint32_t>& tris) {
        const auto& V = mesh.vertices;
        lo_ = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
        hi_ = {-lo_[0], -lo_[1]};
        for (std::uint32_t t : tris)
            for (std::uint32_t v : mesh.triangles[t])
                for (int d = 0; d < 2; ++d) {
                    lo_[d] = std::min(lo_[d], V[v][d]);
                    hi_[d] = std::max(hi_[d], V[v][d]);
                }
        if (tris.empty()) return;
        // About one cell per triangle, shaped like the mesh's footprint.
        const double wx = hi_[0] - lo_[0], wy = hi_[1] - lo_[1], n = double(tris.size());
        const double fx = std::sqrt(n * wx / wy);  // both > 0: the triangles are not edge-on
        n_[0] = int(std::clamp(std::ceil(fx), 1.0, 4096.0));
        n_[1] = int(std::clamp(std::ceil(n / n_[0]), 1.0, 4096.0));
        for (int d = 0; d < 2; ++d) inv_[d] = n_[d] / (hi_[d] - lo_[d]);

        cells_ = bucket_items(std::size_t(n_[0]) * n_[1], [&](const auto& emit) {
            for (std::uint32_t t : tris) {
                const Tri& tri = mesh.triangles[t];
                std::array<int, 2> c0, c1;
                for (int d = 0; d < 2; ++d) {
                    const double a = V[tri[0]][d], b = V[tri[1]][d], c = V[tri[2]][d];
                    c0[d] = cell(d, std::min({a, b, c}));
                    c1[d] = cell(d, std::max({a, b, c}));
                }
                for (int y = c0[1]; y <= c1[1]; ++y)
                    for (int x = c0[0]; x <= c1[0]; ++x) emit(std::size_t(x) + std::size_t(n_[0]) * y, t);
            }
        });
    }
    bool covers(double x, double y) const { return x >= lo_[0] && x <= hi_[0] && y >= lo_[1] && y <= hi_[1]; }
    // Triangles that may contain (x, y); the same monotone cell() for boxes and
    // queries guarantees a point on a box's edge still finds the triangle.
    std::pair<const std::uint64_t*, const std::uint64_t*> candidates(double x, double y) const {
        const std::size_t c = std::size_t(cell(0, x)) + std::size_t(n_[0]) * cell(1, y);
        return {cells_.items.data() + cells_.start[c], cells_.items.data() + cells_.start[c + 1]};
    }

private:
    int cell(int d, double v) const { return int(std::clamp(std::floor((v - lo_[d]) * inv_[d]), 0.0, n_[d] - 1.0)); }
    std::array<double, 2> lo_{}, hi_{}, inv_{};
    std::array<int, 2> n_{1, 1};
    Buckets cells_;
};

}  // namespace

MeshReport check_mesh(const Mesh& mesh) {
    check_indices(mesh, "check_mesh");
    const auto& T = mesh.triangles;
    const std::size_t nv = mesh.vertices.size(), nt = T.size();
    if (nt >= (std::size_t(1) << 31)) throw ResourceError("check_mesh: more than 2^31 triangles");
    MeshReport r;
    r.vertices = nv;
    r.triangles = nt;
    for (const Tri& t : T) r.degenerate_triangles += degenerate(t);

    // Each undirected edge, bucketed by its lower vertex, as hi << 32 | triangle << 1 | forward;
    // sorting a bucket groups the triangles of each edge.
    Buckets edges = bucket_items(nv, [&](const auto& emit) {
        for (std::size_t t = 0; t < nt; ++t) {
            if (degenerate(T[t])) continue;
            for (int c = 0; c < 3; ++c) {
                const std::uint32_t a = T[t][c], b = T[t][(c + 1) % 3];
                emit(std::min(a, b), std::uint64_t(std::max(a, b)) << 32 | std::uint64_t(t) << 1 | (a < b));
            }
        }
    });
    std::size_t boundary = 0, nonmanifold = 0, misoriented = 0;
#pragma omp parallel for schedule(dynamic, 4096) reduction(+ : boundary, nonmanifold, misoriented)
    for (std::ptrdiff_t v = 0; v < std::ptrdiff_t(nv); ++v) {
        std::uint64_t* first = edges.items.data() + edges.start[v];
        std::uint64_t* last = edges.items.data() + edges.start[v + 1];
        std::sort(first, last);
        for (std::uint64_t* run = first; run != last;) {
            std::uint64_t* end = run + 1;
            while (end != last && *end >> 32 == *run >> 32) ++end;
            const std::ptrdiff_t count = end - run;
            if (count == 1) ++boundary;
            else if (count > 2) ++nonmanifold;
            else if ((run[0] & 1) == (run[1] & 1)) ++misoriented;
            run = end;
        }
    }
    r.boundary_edges = boundary;
    r.nonmanifold_edges = nonmanifold;
    r.misoriented_edges = misoriented;

    DisjointSets pieces(nt);
    for (std::size_t v = 0; v < nv; ++v)
        for (std::size_t q = edges.start[v] + 1; q < edges.start[v + 1]; ++q)
            if (edges.items[q] >> 32 == edges.items[q - 1] >> 32)
                pieces.unite(std::uint32_t(edges.items[q]) >> 1, std::uint32_t(edges.items[q - 1]) >> 1);
    for (std::size_t t = 0; t < nt; ++t) r.components += !degenerate(T[t]) && pieces.find(std::uint32_t(t)) == t;
    std::vector<std::uint64_t>().swap(edges.items);

    // A vertex is manifold when its triangles, linked through the edges at the
    // vertex, form one fan.
    const Buckets around = bucket_items(nv, [&](const auto& emit) {
        for (std::size_t t = 0; t < nt; ++t)
            if (!degenerate(T[t]))
                for (std::uint32_t v : T[t]) emit(v, t);
    });
    std::size_t nonmanifold_vertices = 0;
#pragma omp parallel reduction(+ : nonmanifold_vertices)
    {
        std::vector<std::uint64_t> spokes;  // other vertex << 32 | local triangle index
        std::vector<std::uint32_t> parent;
#pragma omp for schedule(dynamic, 4096)
        for (std::ptrdiff_t v = 0; v < std::ptrdiff_t(nv); ++v) {
            const std::size_t begin = around.start[v], n = around.start[v + 1] - begin;
            if (n < 2) continue;
            spokes.clear();
            parent.resize(n);
            for (std::size_t q = 0; q < n; ++q) {
                parent[q] = std::uint32_t(q);
                for (std::uint32_t w : T[around.items[begin + q]])
                    if (w != std::uint32_t(v)) spokes.push_back(std::uint64_t(w) << 32 | q);
            }
            std::sort(spokes.begin(), spokes.end());
            const auto find = [&](std::uint32_t x) {
                while (parent[x] != x) x = parent[x] = parent[parent[x]];
                return x;
            };
            std::size_t fans = n;
            for (std::size_t q = 1; q < spokes.size(); ++q)
                if (spokes[q] >> 32 == spokes[q - 1] >> 32) {
                    const std::uint32_t a = find(std::uint32_t(spokes[q])), b = find(std::uint32_t(spokes[q - 1]));
                    if (a != b) {
                        parent[a] = b;
                        --fans;
                    }
                }
            nonmanifold_vertices += fans > 1;
        }
    }
    r.nonmanifold_vertices = nonmanifold_vertices;

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
    constexpr std::size_t kChunk = 1 << 16;
    std::vector<double> partial((nt + kChunk - 1) / kChunk, 0.0);
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t c = 0; c < std::ptrdiff_t(partial.size()); ++c) {
        double sum = 0;
        for (std::size_t t = std::size_t(c) * kChunk; t < std::min(nt, std::size_t(c + 1) * kChunk); ++t) {
            const Vec3& A = mesh.vertices[T[t][0]];
            const Vec3& B = mesh.vertices[T[t][1]];
            const Vec3& C = mesh.vertices[T[t][2]];
            const double a0 = A[0] - o[0], a1 = A[1] - o[1], a2 = A[2] - o[2];
            const double b0 = B[0] - o[0], b1 = B[1] - o[1], b2 = B[2] - o[2];
            const double c0 = C[0] - o[0], c1 = C[1] - o[1], c2 = C[2] - o[2];
            sum += a0 * (b1 * c2 - b2 * c1) + a1 * (b2 * c0 - b0 * c2) + a2 * (b0 * c1 - b1 * c0);
        }
        partial[c] = sum;
    }
    for (double p : partial) r.volume += p;
    r.volume /= 6;
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
    // Triangles that are edge-on seen from +z cannot be crossed by the perturbed ray.
    std::vector<std::uint32_t> tris;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const Tri& tri = mesh.triangles[t];
        if (!degenerate(tri) && orient2d(V[tri[0]], V[tri[1]], V[tri[2]][0], V[tri[2]][1]) != 0)
            tris.push_back(std::uint32_t(t));
    }
    if (tris.empty()) return 0;
    const ColumnGrid grid(mesh, tris);

    std::size_t inside = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : inside)
    for (std::ptrdiff_t n = 0; n < std::ptrdiff_t(points.size()); ++n) {
        const Vec3& p = points[n];
        if (!grid.covers(p[0], p[1])) continue;
        long winding = 0;
        const auto [first, last] = grid.candidates(p[0], p[1]);
        for (const std::uint64_t* it = first; it != last; ++it) {
            const Tri& tri = mesh.triangles[*it];
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
