// Per-vertex lists over a triangle mesh, as compressed rows: what the mesh passes
// (depth guard, fairing) walk around each vertex.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "snvr/geometry.hpp"
#include "snvr/mesh.hpp"
#include "parallel_sizes.hpp"
#include "told_pace.hpp"

namespace snvr::detail {
class PointTree;
struct GuardElsewhere;  // guard_search.hpp
struct GuardCounted;    // guard_search.hpp
}

namespace snvr::detail {

// item(triangle index, corner) for every corner of every triangle, filed under that
// corner's vertex, in triangle order.
struct VertexLists {
    std::vector<std::size_t> start;
    std::vector<std::uint32_t> items;
    VertexLists() = default;
    template <class Item>
    VertexLists(const Mesh& m, Item item) : start(row_starts(m)) {
        fill(m, item);
    }

    // The two steps, for callers that share the row starts between several lists.
    static std::vector<std::size_t> row_starts(const Mesh& m) {
        std::vector<std::size_t> s(m.vertices.size() + 1, 0);
        for (const auto& t : m.triangles)
            for (std::uint32_t v : t) ++s[v + 1];
        for (std::size_t v = 0; v < m.vertices.size(); ++v) s[v + 1] += s[v];
        return s;
    }
    template <class Item>
    void fill(const Mesh& m, Item item) {
        items.resize(start.back());
        std::vector<std::size_t> at(start.begin(), start.end() - 1);
        for (std::uint32_t t = 0; t < m.triangles.size(); ++t)
            for (int c = 0; c < 3; ++c) items[at[m.triangles[t][c]]++] = item(t, c);
    }
};

// Each vertex's neighbours along edges (each edge seen from one of its two triangles,
// so on a closed manifold mesh every neighbour once).
inline auto ring_item(const Mesh& m) {
    return [&m](std::uint32_t t, int c) { return m.triangles[t][(c + 1) % 3]; };
}
inline VertexLists rings(const Mesh& m) { return VertexLists(m, ring_item(m)); }
// The triangles around each vertex.
inline auto fan_item() {
    return [](std::uint32_t t, int) { return t; };
}
inline VertexLists fans(const Mesh& m) { return VertexLists(m, fan_item()); }
// Each vertex's ring, and its fan where asked, as rings() and fans() make them, on the
// team's threads (over contiguous ranges of triangles).
void rings_and_fans(const Mesh& m, VertexLists& ring, VertexLists* fan = nullptr);

// The mesh passes with lists their caller built once for both (shell_mesh): the
// triangles, hence the lists, do not change between them. Same results as fair_mesh
// and keep_points_deep; the mesh must be valid (every index a vertex). The guard takes
// the rings over and frees them once the lift is spread, before its repair rounds.
void fair_mesh(Mesh& mesh, const MeshFairing& fairing, const VertexLists& rings);
// `elsewhere`: other processes search some of the points (guard_search.hpp), or null;
// `begun`: told as its search, its lift and each repair round begin.
// `counted`: the vertices and points its report counts (null: all).
DepthGuardReport keep_points_deep(Mesh& mesh, const PointTree& points, double depth, double voxel, double lone,
                                  VertexLists rings, const VertexLists& fans, const GuardElsewhere* elsewhere = nullptr,
                                  const Begun& begun = nullptr, const GuardCounted* counted = nullptr);

}  // namespace snvr::detail
