// check_mesh's pieces, solids and volume, and the genus and open pieces of measure_quality,
// of a mesh whole or held in parts (slab_topology.hpp: a slab of vertices and triangles a
// process). Each part joins its triangles over the edges at its own vertices into pieces
// of its own and counts each piece's faces, edges (at their smaller end), vertices and
// volume (volume_sum.hpp: the same sum in any order); a piece of one part that holds a
// triangle of another (a ghost, on an edge of its own) is the piece that triangle is in
// there. Joining the parts' pieces so and adding their counts gives the whole mesh's
// pieces and counts, and so every figure as the whole mesh gives it, to the bit.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "check/mesh_adjacency.hpp"
#include "check/volume_sum.hpp"
#include "snvr/mesh.hpp"
#include "snvr/quality.hpp"

namespace snvr::detail {

struct Topology {
    MeshReport report;
    long genus = 0;                   // MeshQuality's: over the closed pieces
    std::size_t open_components = 0;  // the pieces with boundary edges
};

// The whole mesh's, from its adjacency.
Topology mesh_topology(const Mesh& mesh, const MeshAdjacency& adjacency);

// A part's pieces (a piece each label) and what it counts of them, its triangles' labels
// (kNoPiece for a degenerate one), and its vertices whose fan meets more than one of its
// pieces (those may be one piece of the whole: each as its count of labels, then the labels).
constexpr std::uint32_t kNoPiece = 0xffffffffu;
struct PartPieces {
    std::vector<std::uint64_t> faces, edges, vertices;
    std::vector<std::uint8_t> open;
    std::vector<ExactSum> volume;
    std::vector<std::uint32_t> shared_vertices;
    std::vector<std::uint32_t> label;  // a held triangle's
    ExactSum total = 0;                // every own triangle's, degenerate too (check_mesh's volume)
    bool finite = true;
    std::size_t pieces() const { return faces.size(); }
    // Another part's after these, its labels offset by pieces() (its triangles' labels left).
    void append(const PartPieces& other);
};
// `mesh`: the part's own triangles first (own_triangles of them), then the ghosts; its
// vertices [own_lo, own_hi) its own, numbered in the whole mesh's order among the others.
PartPieces part_pieces(const Mesh& mesh, const MeshAdjacency& adjacency, std::size_t own_triangles, std::size_t own_lo,
                       std::size_t own_hi, const VolumeSum& sum);

// The whole mesh's figures from all parts' pieces appended, `joined` (pairs of labels that
// are one piece) and the parts' counts summed (part_counts), with its vertices and triangles.
Topology joined_topology(MeshReport counts, const PartPieces& all, const std::vector<std::array<std::uint32_t, 2>>& joined,
                         const VolumeSum& sum);

}  // namespace snvr::detail
