// check_mesh's figures, the genus and the open pieces (mesh_topology.hpp) of a mesh held in
// slabs by the processes of a run, one slab a process, no process holding the whole mesh.
// Each process gives every other its own triangles that use that one's vertices (its
// ghosts) and the positions of the vertices of those it is given back, so that it holds
// every triangle at each of its own vertices: it counts the edges at their smaller end and
// the fans there, its own triangles' defects and volume, and its pieces (joined over the
// edges at its own vertices). The first joins the pieces that share a triangle and adds
// their counts: the whole mesh's figures, to the bit, from messages the size of the
// slabs' borders and of the pieces.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "check/mesh_topology.hpp"
#include "snvr/mesh.hpp"
#include "snvr/tiles.hpp"

namespace snvr::detail {

// In steps, so that a run can do other work between them: made, it has exchanged the
// ghosts with every other process (all make it at once); count() does this part's work;
// then each other process sends what it counted to the first (send_to_first), which takes
// it (take_others, before or after its own count) and joins all (joined).
// `part`: this process's slab: its vertices are the whole mesh's from the count of those
// of the processes before it (by rank), its triangles the whole mesh's from the count of
// theirs, by the whole mesh's vertex numbers (any vertex of any slab). Throws InputError
// for a vertex number beyond the whole mesh's.
// A slab as the process holds it (a run of the whole mesh's vertices and triangles): kept
// by the caller until count() is done, and unchanged.
struct SlabPart {
    const Vec3* vertices = nullptr;
    std::size_t vertex_count = 0;
    const std::array<std::uint32_t, 3>* triangles = nullptr;
    std::size_t triangle_count = 0;
    // The first `vertices` and `triangles` of a mesh, or all of them.
    static SlabPart of(const Mesh& mesh, std::size_t vertices, std::size_t triangles) {
        return {mesh.vertices.data(), vertices, mesh.triangles.data(), triangles};
    }
    static SlabPart of(const Mesh& mesh) { return of(mesh, mesh.vertices.size(), mesh.triangles.size()); }
};
class SlabTopology {
public:
    SlabTopology(SlabPart part, TileScheduler& on);
    void count();
    void send_to_first();
    void take_others();
    Topology joined();

private:
    TileScheduler& on_;
    SlabPart part_;
    std::vector<std::uint64_t> starts_, triangle_starts_;  // each slab's first vertex and triangle, and the whole's counts
    VolumeSum sum_{Vec3{0, 0, 0}, Vec3{0, 0, 0}};
    // The others' triangles that use its vertices (each's number in the whole mesh, then
    // its corners), and the others' vertices its own triangles use, with their positions.
    std::vector<std::array<std::uint32_t, 4>> ghosts_;
    std::vector<std::uint32_t> foreign_;
    std::vector<Vec3> foreign_at_;
    std::vector<std::uint8_t> given_;  // an own triangle given to another process
    // What it counted; at the first, each other's too.
    MeshReport counts_;
    PartPieces pieces_;
    std::vector<std::array<std::uint32_t, 2>> ghost_pieces_, given_pieces_;
    using CountsRow = std::array<std::uint64_t, 6>;  // part_counts' defects, in a row (slab_topology.cpp)
    std::vector<CountsRow> their_counts_;
    std::vector<PartPieces> their_pieces_;
    std::vector<std::vector<std::array<std::uint32_t, 2>>> their_ghosts_, their_given_;
};

// All steps at once: every process calls it; the figures come out at the first
// (elsewhere, zeros).
Topology slab_topology(SlabPart part, TileScheduler& on);

}  // namespace snvr::detail
