// The shell handed to a MeshSink (snvr/mesh_io.hpp) slab by slab over the processes of a
// run, so that no process holds it whole (Parameters::surface_in_parts): the first hands
// on its own slab, then each other's as that one sends it, a run of at most kHandoverRun
// triangles (or vertices) at a time.
#pragma once
#include <array>

#include "check/slab_mesh.hpp"
#include "snvr/mesh_io.hpp"
#include "snvr/tiles.hpp"

namespace snvr::detail {

// At the first: `sink` fed from the slabs. own() while the others still measure their
// shares of the check: the counts, then what of its own slab comes first (its triangles
// where the sink wants corners, else its vertices); rest() once the check is done: the
// others' slabs as each sends it (give_slab), in turn, then finish().
class SlabHandover {
public:
    SlabHandover(TileScheduler& on, MeshSink& sink) : on_(on), sink_(sink) {}
    void own(const SlabMesh& slabs);
    void rest(const SlabMesh& slabs);
    // The whole shell's box (the slabs'), and the seconds spent handing on.
    const std::array<Vec3, 2>& box() const { return box_; }
    double seconds() const { return seconds_; }

private:
    TileScheduler& on_;
    MeshSink& sink_;
    bool begun_ = false;
    std::array<Vec3, 2> box_{};
    double seconds_ = 0;
};
// At another process, at the first's rest(): its slab sent to the first.
void give_slab(const SlabMesh& slabs, TileScheduler& on);

}  // namespace snvr::detail
