// Per-vertex lists over a triangle mesh, as compressed rows: what the mesh passes
// (depth guard, fairing) walk around each vertex.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "snvr/geometry.hpp"

namespace snvr::detail {

// Per-vertex loops of the mesh passes run threaded above this many items: below it,
// waking threads costs more than it saves.
constexpr std::ptrdiff_t kParallelVertices = 4096;

// item(triangle index, corner) for every corner of every triangle, filed under that
// corner's vertex.
struct VertexLists {
    std::vector<std::size_t> start;
    std::vector<std::uint32_t> items;
    template <class Item>
    VertexLists(const Mesh& m, Item item) : start(m.vertices.size() + 1, 0) {
        for (const auto& t : m.triangles)
            for (std::uint32_t v : t) ++start[v + 1];
        for (std::size_t v = 0; v < m.vertices.size(); ++v) start[v + 1] += start[v];
        items.resize(start.back());
        std::vector<std::size_t> fill(start.begin(), start.end() - 1);
        for (std::uint32_t t = 0; t < m.triangles.size(); ++t)
            for (int c = 0; c < 3; ++c) items[fill[m.triangles[t][c]]++] = item(t, c);
    }
};

// Each vertex's neighbours along edges (each edge seen from one of its two triangles,
// so on a closed manifold mesh every neighbour once).
inline VertexLists rings(const Mesh& m) {
    return VertexLists(m, [&m](std::uint32_t t, int c) { return m.triangles[t][(c + 1) % 3]; });
}
// The triangles around each vertex.
inline VertexLists fans(const Mesh& m) {
    return VertexLists(m, [](std::uint32_t t, int) { return t; });
}

}  // namespace snvr::detail
