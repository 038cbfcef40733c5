// A tiled run's surface (Parameters::whole_field false) welded and faired in slabs of
// planes, one a process. The whole mesh's order is plane by plane (a vertex's key and a
// triangle's name its plane first: mesh/dual_pieces.hpp), so a slab of planes [c_s, c_s+1)
// owns a run of the whole order: its vertices are the whole mesh's from the count of
// those in the slabs before, and the slabs in turn are the whole mesh. Each slab is welded
// from the tiles' parts and the seams over its planes and `ghost` planes on either side,
// then faired; it keeps its own. Why the ghosts make its fairing the whole mesh's, bit for
// bit: a triangle of plane z uses vertices of planes z - 1 and z, so a vertex's ring (its
// neighbours in the order of its triangles, which the slab keeps) lies within a plane of
// it; each of the fairing's 2 x passes steps takes a vertex from its ring, so a ring cut
// short at the ghosts' edge reaches one plane further in a step: 2 x passes planes of
// ghosts keep it from the slab (tests/test_tiles.cpp fails with one fewer).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "snvr/domain.hpp"
#include "snvr/mesh.hpp"
#include "mesh/dual_pieces.hpp"
#include "solver/tile_plan.hpp"
#include "solver/tile_surface.hpp"

namespace snvr {

// The planes of ghosts a slab is welded and faired with on either side (at least one: a
// triangle of the slab's first plane uses the plane below).
int slab_ghost_planes(const MeshFairing& fairing);

// Slab s owns the vertices of cube planes, and the triangles of sample planes, [cuts[s], cuts[s + 1]).
struct SlabPlan {
    std::vector<int> cuts;  // slabs + 1 of them: 0, ..., the grid's samples along z
    int ghost = 1;
    int slabs() const { return int(cuts.size()) - 1; }
    // The planes slab s is welded from: its own and the ghosts' (within the grid).
    detail::Planes welded(int s) const;
};

// The slices the tiles cut their parts in where there are slabs (tile_surface): a slice
// goes whole to each slab whose welded planes it meets, so that a slab's weld passes over
// at most a slice less a plane more on either side.
constexpr int kSlabSlice = 8;

// `slabs` slabs with about as many of `by_plane` each (even planes where there are none).
SlabPlan plan_slabs(const std::vector<std::uint64_t>& by_plane, int slabs, int ghost);
// The pieces' own vertices by the grid's plane (samples along z), added to `by_plane`.
void count_by_plane(const detail::MeshPiece& piece, std::vector<std::uint64_t>& by_plane);

// Slab s welded with its ghosts, then faired.
struct SlabWeld {
    Mesh mesh;
    std::size_t below = 0;                          // the ghost planes' vertices below the slab: the mesh's first
    std::size_t vertices = 0;                       // the slab's own, next
    std::size_t first_triangle = 0, triangles = 0;  // the slab's own triangles
};
// From the tiles' pieces that meet its welded planes (they may reach beyond them) and the
// faces over those planes. Frees the pieces.
SlabWeld weld_slab(std::vector<detail::MeshPiece>& pieces, const FacesPart& faces, const Domain& whole, int core_cells,
                   const SlabPlan& plan, int s, const MeshFairing& fairing);

// The slab's own vertices and triangles, numbered as the whole mesh numbers them: the
// slab's first vertex is the whole mesh's `first` (the count of the slabs' before it).
Mesh slab_own(SlabWeld weld, std::size_t first);

}  // namespace snvr
