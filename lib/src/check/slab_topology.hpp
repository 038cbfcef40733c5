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
#include "check/slab_mesh.hpp"
#include "snvr/mesh.hpp"
#include "snvr/tiles.hpp"

namespace snvr::detail {

// In steps, so that a run can do other work between them: made on a SlabMesh (which
// exchanged the ghosts), count() does this part's work; then each other process sends what
// it counted to the first (send_to_first), which takes it (take_others, before or after
// its own count) and joins all (joined). The slabs are kept until count() is done.
class SlabTopology {
public:
    SlabTopology(SlabMesh& slabs, TileScheduler& on);
    void count();
    void send_to_first();
    void take_others();
    Topology joined();

private:
    TileScheduler& on_;
    SlabMesh& slabs_;
    VolumeSum sum_{Vec3{0, 0, 0}, Vec3{0, 0, 0}};
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
