// A tiled run's surface (Parameters::whole_field false) in slabs of planes over the
// processes of a run (slab_surface.hpp), one slab a process, balanced by the tiles'
// vertices by plane. Each process sends every other its tiles' slices that meet that
// one's welded planes (sent whole, the tiles having cut them), and the first sends
// each the bricks at the cores' faces over its planes (the seams' need: every tile's come
// to the first with its figures); each welds and fairs its slab, and the slabs come to
// the first in turn. Alone (no scheduler, or one process) the one slab is the whole surface.
#pragma once
#include <vector>

#include "snvr/domain.hpp"
#include "snvr/field.hpp"
#include "snvr/mesh.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/tiles.hpp"
#include "mesh/dual_pieces.hpp"
#include "mesh/fair_and_keep_deep.hpp"
#include "solver/slab_surface.hpp"

namespace snvr {

// `pieces`: this process's tiles' (tile_surface, in slices of kSlabSlice planes where there
// are several processes; freed); `faces`: at the first, the whole grid's field with every
// tile's face bricks placed (elsewhere unused). Returns the whole surface, faired, at the
// first; elsewhere the slab's own vertices and triangles (kept for the check: pipeline/
// shared_check.hpp). `in_parts` (Parameters::surface_in_parts): at the first too, its own
// slab only, where the guard allows (facts.slabs_kept). Sets facts.slabs, slab_ghost,
// slab_bytes, slab_starts, slab_triangles, surface_triangles and slabs_kept.
//
// With `guard` (several processes), each slab's points are kept deep as well (slab_surface.hpp),
// where the points near the others' slabs are no more than the vertices they own (else the
// first guards the whole surface as before, the others searching their ranges of the points
// for it; facts.guard_slabs says which): `points` at the first are the run's, and it gives
// each other process those within the guard's reach of its slab (in its tree's order and
// frame); elsewhere null. The first then
// compares each slab's ghosts within half their width of its planes with their owner's
// vertices: where any differs, it runs the guard again on the whole surface from the slabs'
// vertices as they were before it (facts.guard_rerun). `report`: the guard's, at the first.
struct SlabsGuard {
    detail::KeepDeep deep;
    const PointCloud* points = nullptr;
};
Mesh surface_in_slabs(std::vector<detail::MeshPiece>& pieces, Field faces, const Domain& whole, int core_cells,
                      const MeshFairing& fairing, const SlabsGuard* guard, bool in_parts, TileScheduler* on,
                      TileFacts& facts, DepthGuardReport* report);

}  // namespace snvr
