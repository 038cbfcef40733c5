// The adjacency check_mesh builds (mesh_check.cpp), shared with measure_quality so the
// figures reuse it rather than build it again, and with a mesh held in slabs by several
// processes (slab_topology.hpp), each counting what its part owns.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "snvr/mesh.hpp"
#include "snvr/quality.hpp"

namespace snvr::detail {

// The proper triangles around each vertex (vertex_fans), and the edges of the proper
// triangles at their smaller end (lower_edges: vertex v's items[start[v] .. start[v + 1])
// hold (larger end << 32 | triangle), sorted, so that a run of one larger end is one edge).
struct MeshAdjacency {
    std::vector<std::size_t> fan_start;
    std::vector<std::uint32_t> fan_tri;
    std::vector<std::size_t> edge_start;
    std::vector<std::uint64_t> edge_items;
};
void vertex_fans(const Mesh& mesh, std::vector<std::size_t>& start, std::vector<std::uint32_t>& tri);
void lower_edges(const Mesh& mesh, std::vector<std::size_t>& start, std::vector<std::uint64_t>& items);
MeshAdjacency adjacency_of(const Mesh& mesh);

inline bool degenerate(const std::array<std::uint32_t, 3>& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; }
inline std::uint32_t upper_end(std::uint64_t edge_item) { return std::uint32_t(edge_item >> 32); }

// What of check_mesh's report a part of a mesh owns: of its first `own_triangles`
// triangles, the degenerate and zero-area ones; of its vertices [own_lo, own_hi), the
// edges at their smaller end (boundary, non-manifold, misoriented) and the fans (the
// mesh's vertex numbers in the whole mesh's order, so that each edge has one smaller end
// in one part). Pieces, solids, volume and the sizes are left 0 (mesh_topology.hpp).
// The whole mesh is one part owning everything.
MeshReport part_counts(const Mesh& mesh, const MeshAdjacency& adjacency, std::size_t own_triangles, std::size_t own_lo,
                       std::size_t own_hi);

}  // namespace snvr::detail
