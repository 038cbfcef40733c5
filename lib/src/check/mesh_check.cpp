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

#include "snvr/error.hpp"
#include "snvr/quality.hpp"
#include "mesh/mesh_indices.hpp"
#include "check/mesh_adjacency.hpp"
#include "check/mesh_topology.hpp"
#include "threads_here.hpp"
#include "snvr/mesh.hpp"
#include "parallel_sizes.hpp"

namespace snvr {
namespace {

using detail::degenerate;
using detail::threads_here;

using Tri = std::array<std::uint32_t, 3>;

// Below these sizes, waking threads costs more than it saves.

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

std::uint32_t upper(std::uint64_t item) { return detail::upper_end(item); }

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

// Edges at their smaller end (so each once), and fans, vertex by vertex, of [lo, hi).
void count_edges_and_fans(const Mesh& mesh, const detail::MeshAdjacency& a, std::size_t lo, std::size_t hi,
                          bool parallel, MeshReport& r) {
    std::size_t boundary = 0, nonmanifold = 0, misoriented = 0, nonmanifold_vertices = 0;
#pragma omp parallel reduction(+ : boundary, nonmanifold, misoriented, nonmanifold_vertices) if (parallel)
    {
        std::vector<std::uint64_t> spokes;  // neighbour << 32 | local triangle index
        std::vector<std::uint32_t> parent;
#pragma omp for schedule(dynamic, 4096)
        for (std::ptrdiff_t vi = std::ptrdiff_t(lo); vi < std::ptrdiff_t(hi); ++vi) {
            const auto v = std::uint32_t(vi);
            count_edges_at(mesh, v, a.edge_start, a.edge_items, boundary, nonmanifold, misoriented);
            const std::size_t n = a.fan_start[v + 1] - a.fan_start[v];
            if (n >= 2) nonmanifold_vertices += split_fan(mesh, v, a.fan_tri.data() + a.fan_start[v], n, spokes, parent);
        }
    }
    r.boundary_edges = boundary;
    r.nonmanifold_edges = nonmanifold;
    r.misoriented_edges = misoriented;
    r.nonmanifold_vertices = nonmanifold_vertices;
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

MeshAdjacency adjacency_of(const Mesh& mesh) {
    MeshAdjacency a;
    vertex_fans(mesh, a.fan_start, a.fan_tri);
    lower_edges(mesh, a.edge_start, a.edge_items);
    return a;
}

MeshReport part_counts(const Mesh& mesh, const MeshAdjacency& adjacency, std::size_t own_triangles, std::size_t own_lo,
                       std::size_t own_hi) {
    const auto& T = mesh.triangles;
    MeshReport r;
    const bool parallel = own_triangles >= std::size_t(detail::kParallelCheapItems);
    std::size_t repeated = 0, zero = 0;
#pragma omp parallel for reduction(+ : repeated, zero) if (parallel)
    for (std::size_t t = 0; t < own_triangles; ++t) {
        if (degenerate(T[t]))
            ++repeated;
        else
            zero += zero_area(mesh, T[t]);
    }
    r.degenerate_triangles = repeated;
    r.zero_area_triangles = zero;
    count_edges_and_fans(mesh, adjacency, own_lo, own_hi, parallel, r);
    return r;
}

}  // namespace detail

MeshReport check_mesh(const Mesh& mesh) {
    detail::check_triangle_indices(mesh, "check_mesh");
    if (mesh.triangles.size() > std::numeric_limits<std::uint32_t>::max())
        throw ResourceError("check_mesh: more than 2^32 triangles");
    return detail::mesh_topology(mesh, detail::adjacency_of(mesh)).report;
}

}  // namespace snvr
