// Mesh validity report (check_mesh, quality.hpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <omp.h>

#include "geometry/disjoint_sets.hpp"
#include "snvr/error.hpp"
#include "snvr/quality.hpp"
#include "mesh/mesh_indices.hpp"
#include "check/mesh_adjacency.hpp"
#include "threads_here.hpp"
#include "snvr/mesh.hpp"
#include "parallel_sizes.hpp"

namespace snvr {
namespace {

using detail::threads_here;

using Tri = std::array<std::uint32_t, 3>;

// Below these sizes, waking threads costs more than it saves.

bool degenerate(const Tri& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; }

// The cross product of two edges is zero. Exact for float32 coordinates (as written to
// STL): their differences and the products of those are exact in double.
bool zero_area(const Mesh& m, const Tri& t) {
    const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    return u[1] * v[2] == u[2] * v[1] && u[2] * v[0] == u[0] * v[2] && u[0] * v[1] == u[1] * v[0];
}

// Items grouped by bucket (counting sort): bucket b is items[start[b] .. start[b+1]).
template <class Item>
struct Buckets {
    std::vector<std::size_t> start;
    std::vector<Item> items;
};

// ForEach(source, emit) calls emit(bucket, item) for each item of one source.
// Each thread takes a range of buckets and goes through all sources in order, so
// a bucket lists its items in source order whatever the number of threads (and
// no two threads write to one counter: no atomics, no shared cache lines).
template <class Item, class ForEach>
Buckets<Item> bucket_items(std::size_t n_buckets, std::size_t n_sources, bool parallel, const ForEach& for_each) {
    Buckets<Item> b;
    b.start.assign(n_buckets + 1, 0);
    const int parts = parallel ? std::max(1, threads_here()) : 1;
    const auto part_start = [&](int k) { return std::size_t(double(n_buckets) * k / parts); };
    std::size_t* count = b.start.data() + 1;
#pragma omp parallel for schedule(static, 1) if (parts > 1)
    for (int k = 0; k < parts; ++k) {
        const std::size_t lo = part_start(k), hi = part_start(k + 1);
        for (std::size_t src = 0; src < n_sources; ++src)
            for_each(src, [&](std::size_t bucket, Item) {
                if (bucket >= lo && bucket < hi) ++count[bucket];
            });
    }
    for (std::size_t i = 0; i < n_buckets; ++i) b.start[i + 1] += b.start[i];
    b.items.resize(b.start[n_buckets]);
    std::vector<std::size_t> cursor(b.start.begin(), b.start.end() - 1);
    std::size_t* next = cursor.data();
    Item* items = b.items.data();
#pragma omp parallel for schedule(static, 1) if (parts > 1)
    for (int k = 0; k < parts; ++k) {
        const std::size_t lo = part_start(k), hi = part_start(k + 1);
        for (std::size_t src = 0; src < n_sources; ++src)
            for_each(src, [&](std::size_t bucket, Item item) {
                if (bucket >= lo && bucket < hi) items[next[bucket]++] = item;
            });
    }
    return b;
}

// Sorts a short range in place (the buckets here hold a handful of items).
void sort_small(std::uint64_t* first, std::uint64_t* last) {
    if (last - first > 16) {
        std::sort(first, last);
        return;
    }
    for (std::uint64_t* i = first + (first != last); i < last; ++i) {
        const std::uint64_t x = *i;
        std::uint64_t* j = i;
        for (; j != first && j[-1] > x; --j) *j = j[-1];
        *j = x;
    }
}

std::uint32_t upper(std::uint64_t item) { return std::uint32_t(item >> 32); }

// The edges at v's smaller end (a run of one neighbour is one edge): counts boundary,
// non-manifold and misoriented ones.
void count_edges_at(const Mesh& mesh, std::uint32_t v, const std::vector<std::size_t>& edge_start,
                    const std::vector<std::uint64_t>& edge_items, std::size_t& boundary, std::size_t& nonmanifold,
                    std::size_t& misoriented) {
    const auto& T = mesh.triangles;
    const std::uint64_t* first = edge_items.data() + edge_start[v];
    const std::uint64_t* last = edge_items.data() + edge_start[v + 1];
    for (const std::uint64_t* run = first; run != last;) {
        const std::uint32_t x = upper(*run);
        std::ptrdiff_t forward = 0;  // triangles that run v -> x (the others run x -> v)
        const std::uint64_t* end = run;
        for (; end != last && upper(*end) == x; ++end) {
            const Tri& t = T[std::uint32_t(*end)];
            forward += (t[0] == v && t[1] == x) || (t[1] == v && t[2] == x) || (t[2] == v && t[0] == x);
        }
        const std::ptrdiff_t n = end - run;
        if (n == 1) ++boundary;
        else if (n > 2) ++nonmanifold;
        else if (forward != 1) ++misoriented;  // both triangles run the same way
        run = end;
    }
}

// Whether the triangles around v (its fan) fail to form one fan when linked through
// shared spokes. spokes and parent: a thread's scratch.
bool split_fan(const Mesh& mesh, std::uint32_t v, const std::uint32_t* fan, std::size_t n,
               std::vector<std::uint64_t>& spokes, std::vector<std::uint32_t>& parent) {
    const auto& T = mesh.triangles;
    // Each triangle leaves v by spoke b and comes back by spoke c.
    constexpr std::size_t kSmall = 16;
    std::uint32_t b[kSmall], c[kSmall];
    const auto spokes_of = [&](std::size_t q, std::uint32_t& out, std::uint32_t& back) {
        const Tri& t = T[fan[q]];
        const int at = t[0] == v ? 0 : t[1] == v ? 1 : 2;
        out = t[(at + 1) % 3];
        back = t[(at + 2) % 3];
    };
    // The usual case first: every spoke leaves in one triangle and comes back
    // in one other, so "the triangle whose b is my c" is a permutation, and
    // the fans are its cycles.
    bool simple = n <= kSmall;
    std::uint32_t next[kSmall];
    if (simple) {
        for (std::size_t q = 0; q < n; ++q) {
            spokes_of(q, b[q], c[q]);
            next[q] = std::uint32_t(-1);
        }
        for (std::size_t q = 0; q < n && simple; ++q) {
            std::size_t match = n, matches = 0;
            for (std::size_t j = 0; j < n; ++j)
                if (b[j] == c[q]) {
                    match = j;
                    ++matches;
                }
            if (matches != 1 || next[match] != std::uint32_t(-1))
                simple = false;
            else
                next[match] = std::uint32_t(q);
        }
    }
    if (simple) {
        std::size_t cycle = 1;
        for (std::uint32_t q = next[0]; q != 0; q = next[q]) ++cycle;
        return cycle != n;
    }
    spokes.clear();
    parent.resize(n);
    for (std::size_t q = 0; q < n; ++q) {
        parent[q] = std::uint32_t(q);
        std::uint32_t out, back;
        spokes_of(q, out, back);
        spokes.push_back(std::uint64_t(out) << 32 | q);
        spokes.push_back(std::uint64_t(back) << 32 | q);
    }
    std::sort(spokes.begin(), spokes.end());
    const auto find = [&](std::uint32_t y) {
        while (parent[y] != y) y = parent[y] = parent[parent[y]];
        return y;
    };
    std::size_t fans = n;
    for (std::size_t q = 1; q < spokes.size(); ++q)
        if (upper(spokes[q]) == upper(spokes[q - 1])) {
            const std::uint32_t a = find(std::uint32_t(spokes[q])), e = find(std::uint32_t(spokes[q - 1]));
            if (a != e) {
                parent[a] = e;
                --fans;
            }
        }
    return fans > 1;
}

// Edges at their smaller end (so each once), and fans, vertex by vertex.
void count_edges_and_fans(const Mesh& mesh, const std::vector<std::size_t>& fan_start,
                          const std::vector<std::uint32_t>& fan_tri, const std::vector<std::size_t>& edge_start,
                          const std::vector<std::uint64_t>& edge_items, bool parallel, MeshReport& r) {
    const std::size_t nv = mesh.vertices.size();
    std::size_t boundary = 0, nonmanifold = 0, misoriented = 0, nonmanifold_vertices = 0;
#pragma omp parallel reduction(+ : boundary, nonmanifold, misoriented, nonmanifold_vertices) if (parallel)
    {
        std::vector<std::uint64_t> spokes;  // neighbour << 32 | local triangle index
        std::vector<std::uint32_t> parent;
#pragma omp for schedule(dynamic, 4096)
        for (std::ptrdiff_t vi = 0; vi < std::ptrdiff_t(nv); ++vi) {
            const auto v = std::uint32_t(vi);
            count_edges_at(mesh, v, edge_start, edge_items, boundary, nonmanifold, misoriented);
            const std::size_t n = fan_start[v + 1] - fan_start[v];
            if (n >= 2) nonmanifold_vertices += split_fan(mesh, v, fan_tri.data() + fan_start[v], n, spokes, parent);
        }
    }
    r.boundary_edges = boundary;
    r.nonmanifold_edges = nonmanifold;
    r.misoriented_edges = misoriented;
    r.nonmanifold_vertices = nonmanifold_vertices;
}

// Components: join the triangles on each edge. root: each proper triangle's
// component root (-1 for degenerate ones); returns each component's smallest
// triangle, in order.
std::vector<std::uint32_t> components(const Mesh& mesh, const std::vector<std::size_t>& edge_start,
                                      const std::vector<std::uint64_t>& edge_items, std::vector<std::uint32_t>& root) {
    const auto& T = mesh.triangles;
    const std::size_t nv = mesh.vertices.size(), nt = T.size();
    DisjointSets pieces(nt);
    for (std::size_t v = 0; v < nv; ++v)
        for (std::size_t k = edge_start[v] + 1; k < edge_start[v + 1]; ++k)
            if (upper(edge_items[k]) == upper(edge_items[k - 1]))
                pieces.unite(std::uint32_t(edge_items[k - 1]), std::uint32_t(edge_items[k]));
    root.assign(nt, std::uint32_t(-1));
    std::vector<std::uint32_t> first_of;
    for (std::size_t t = 0; t < nt; ++t)
        if (!degenerate(T[t])) {
            root[t] = pieces.find(std::uint32_t(t));
            if (root[t] == std::uint32_t(t)) first_of.push_back(root[t]);
        }
    return first_of;
}

// Six times the signed volume of the tetrahedron (o, triangle t), o the bounding-box
// centre (less cancellation than about the origin).
struct SixVolume {
    explicit SixVolume(const Mesh& m) : mesh(m) {
        Vec3 lo{0, 0, 0}, hi{0, 0, 0};
        if (!mesh.vertices.empty()) lo = hi = mesh.vertices[0];
        for (const Vec3& p : mesh.vertices)
            for (int d = 0; d < 3; ++d) {
                lo[d] = std::min(lo[d], p[d]);
                hi[d] = std::max(hi[d], p[d]);
            }
        o = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
    }
    double operator()(std::size_t t) const {
        const auto& T = mesh.triangles;
        const Vec3& A = mesh.vertices[T[t][0]];
        const Vec3& B = mesh.vertices[T[t][1]];
        const Vec3& C = mesh.vertices[T[t][2]];
        const double a0 = A[0] - o[0], a1 = A[1] - o[1], a2 = A[2] - o[2];
        const double b0 = B[0] - o[0], b1 = B[1] - o[1], b2 = B[2] - o[2];
        const double c0 = C[0] - o[0], c1 = C[1] - o[1], c2 = C[2] - o[2];
        return a0 * (b1 * c2 - b2 * c1) + a1 * (b2 * c0 - b0 * c2) + a2 * (b0 * c1 - b1 * c0);
    }
    const Mesh& mesh;
    Vec3 o;
};

// Divergence theorem; fixed chunks keep the sum independent of thread count.
double enclosed_volume(const SixVolume& six_volume, std::size_t nt, bool parallel) {
    constexpr std::size_t kChunk = 1 << 16;
    std::vector<double> partial((nt + kChunk - 1) / kChunk, 0.0);
#pragma omp parallel for schedule(static) if (parallel)
    for (std::ptrdiff_t c = 0; c < std::ptrdiff_t(partial.size()); ++c) {
        double sum = 0;
        for (std::size_t t = std::size_t(c) * kChunk; t < std::min(nt, std::size_t(c + 1) * kChunk); ++t)
            sum += six_volume(t);
        partial[c] = sum;
    }
    double volume = 0;
    for (double p : partial) volume += p;
    return volume / 6;
}

// Solid pieces: components enclosing positive volume (outer boundaries); the
// negative ones are cavities inside them.
// (The sums run in triangle order, per component, as they always did.)
std::size_t solid_pieces(const SixVolume& six_volume, const std::vector<std::uint32_t>& root,
                         const std::vector<std::uint32_t>& first_of) {
    const std::size_t nt = root.size();
    std::vector<double> piece_volume(first_of.size(), 0.0);
    if (first_of.size() == 1) {
        for (std::size_t t = 0; t < nt; ++t)
            if (root[t] != std::uint32_t(-1)) piece_volume[0] += six_volume(t);
    } else {
        std::vector<std::uint32_t> id(nt);  // compact component of each root
        for (std::size_t c = 0; c < first_of.size(); ++c) id[first_of[c]] = std::uint32_t(c);
        for (std::size_t t = 0; t < nt; ++t)
            if (root[t] != std::uint32_t(-1)) piece_volume[id[root[t]]] += six_volume(t);
    }
    std::size_t solids = 0;
    for (double v : piece_volume) solids += v > 0;
    return solids;
}

}  // namespace

namespace detail {


// The proper triangles around each vertex, in ascending order: vertex v's are
// tri[start[v] .. start[v + 1]).
void vertex_fans(const Mesh& mesh, std::vector<std::size_t>& start, std::vector<std::uint32_t>& tri) {
    const auto& T = mesh.triangles;
    Buckets<std::uint32_t> b = bucket_items<std::uint32_t>(
        mesh.vertices.size(), T.size(), T.size() >= std::size_t(detail::kParallelCheapItems), [&](std::size_t t, const auto& emit) {
            if (!degenerate(T[t]))
                for (std::uint32_t v : T[t]) emit(v, std::uint32_t(t));
        });
    start = std::move(b.start);
    tri = std::move(b.items);
}

// The edges of the proper triangles at their smaller end: vertex v's bucket
// items[start[v] .. start[v + 1]) holds (larger end << 32 | triangle) for every
// triangle on an edge {v, x}, x > v, sorted, so that a run of one x is one edge.
void lower_edges(const Mesh& mesh, std::vector<std::size_t>& start, std::vector<std::uint64_t>& items) {
    const auto& T = mesh.triangles;
    const bool parallel = T.size() >= std::size_t(detail::kParallelCheapItems);
    Buckets<std::uint64_t> b = bucket_items<std::uint64_t>(
        mesh.vertices.size(), T.size(), parallel, [&](std::size_t t, const auto& emit) {
            if (degenerate(T[t])) return;
            for (int c = 0; c < 3; ++c) {
                const std::uint32_t a = T[t][c], e = T[t][(c + 1) % 3];
                emit(std::min(a, e), std::uint64_t(std::max(a, e)) << 32 | t);
            }
        });
    const std::ptrdiff_t nv = std::ptrdiff_t(mesh.vertices.size());
#pragma omp parallel for schedule(dynamic, 4096) if (parallel)
    for (std::ptrdiff_t v = 0; v < nv; ++v) sort_small(b.items.data() + b.start[v], b.items.data() + b.start[v + 1]);
    start = std::move(b.start);
    items = std::move(b.items);
}

MeshReport check_mesh_unchecked(const Mesh& mesh, const std::vector<std::size_t>& fan_start,
                                const std::vector<std::uint32_t>& fan_tri, const std::vector<std::size_t>& edge_start,
                                const std::vector<std::uint64_t>& edge_items, std::vector<std::uint32_t>* piece) {
    const auto& T = mesh.triangles;
    const std::size_t nv = mesh.vertices.size(), nt = T.size();
    MeshReport r;
    r.vertices = nv;
    r.triangles = nt;
    const bool parallel = nt >= std::size_t(detail::kParallelCheapItems);
    std::size_t repeated = 0, zero = 0;
#pragma omp parallel for reduction(+ : repeated, zero) if (parallel)
    for (std::size_t t = 0; t < nt; ++t) {
        if (degenerate(T[t]))
            ++repeated;
        else
            zero += zero_area(mesh, T[t]);
    }
    r.degenerate_triangles = repeated;
    r.zero_area_triangles = zero;
    count_edges_and_fans(mesh, fan_start, fan_tri, edge_start, edge_items, parallel, r);
    std::vector<std::uint32_t> root;
    const std::vector<std::uint32_t> first_of = components(mesh, edge_start, edge_items, root);
    r.components = first_of.size();
    const SixVolume six_volume(mesh);
    r.volume = enclosed_volume(six_volume, nt, parallel);
    r.solids = solid_pieces(six_volume, root, first_of);
    if (piece) *piece = std::move(root);
    return r;
}

}  // namespace detail

MeshReport check_mesh(const Mesh& mesh) {
    detail::check_triangle_indices(mesh, "check_mesh");
    if (mesh.triangles.size() > std::numeric_limits<std::uint32_t>::max())
        throw ResourceError("check_mesh: more than 2^32 triangles");
    std::vector<std::size_t> fan_start, edge_start;
    std::vector<std::uint32_t> fan_tri;
    std::vector<std::uint64_t> edge_items;
    detail::vertex_fans(mesh, fan_start, fan_tri);
    detail::lower_edges(mesh, edge_start, edge_items);
    return detail::check_mesh_unchecked(mesh, fan_start, fan_tri, edge_start, edge_items, nullptr);
}

}  // namespace snvr
