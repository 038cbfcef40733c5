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
//
// The depth guard (keep_points_deep) may run on a slab too, with the points near it: a
// vertex's lift comes from the points within the aim of the vertices within 4 rings of
// it (mesh/guard_search.hpp, guard_reach_planes: 8 planes at the default depth of 2
// voxels) on vertices whose fairing is exact (beyond the fairing's ghosts). Its repair and
// untangling rounds, which act on the few points and triangles still wrong, are not
// bounded so: a slab is welded with half the reach more ghost planes, and each slab's
// guard is checked, where those ghosts (the planes next to its own) must come out as the
// neighbour slab's own did; else the first runs the guard again on the whole surface
// (shared_slabs.hpp). (bench_guard_slabs: 8 planes of ghosts, fairing and guard on them,
// gave every vertex of the whole guard on the bunny, the sampler's lidar scene and a
// sparse city block with 4 and 8 repair rounds, 4 planes did not; with 12, the 4 next to
// the slab differed from their owners' on the bunny faired in 5 passes, where the fairing
// alone reaches 10, and in 3 vertices of the 12.5 M-point city block at 2048 cells, each
// slab's own vertices the whole guard's all the same.)
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "snvr/domain.hpp"
#include "snvr/mesh.hpp"
#include "geometry/point_tree.hpp"
#include "mesh/dual_pieces.hpp"
#include "mesh/fair_and_keep_deep.hpp"
#include "solver/tile_plan.hpp"
#include "solver/tile_surface.hpp"

namespace snvr {

// The planes of ghosts a slab is welded and faired with on either side (at least one: a
// triangle of the slab's first plane uses the plane below).
// With `deep`, the depth guard's as well: the fairing's, then the guard's reach over the
// vertices so faired, then the planes its check compares (guard_checked_planes: half the
// reach, the ghosts next to the slab's own).
int slab_ghost_planes(const MeshFairing& fairing, const detail::KeepDeep* deep = nullptr);
int guard_checked_planes(const detail::KeepDeep& deep);

// Slab s owns the vertices of cube planes, and the triangles of sample planes, [cuts[s], cuts[s + 1]).
struct SlabPlan {
    std::vector<int> cuts;  // slabs + 1 of them: 0, ..., the grid's samples along z
    int ghost = 1;
    int checked = 0;  // of those, the planes next to the slab's own that a guard's check compares (SlabWeld)
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
    // Where the guard ran: the report over the slab's own vertices and points, its own
    // vertices before it, and the ghosts its check compares with their owners', the mesh's
    // [band_below, below) and [below + vertices, band_above).
    DepthGuardReport guard;
    std::vector<Vec3> unguarded;
    std::size_t band_below = 0, band_above = 0;
};
// From the tiles' pieces that meet its welded planes (they may reach beyond them) and the
// faces over those planes. Frees the pieces. With `deep`, its points kept deep as well:
// `points` those near the slab (at least within guard_point_reach of its welded planes),
// in the whole run's tree's frame and order, their report counted over those in its planes.
SlabWeld weld_slab(std::vector<detail::MeshPiece>& pieces, const FacesPart& faces, const Domain& whole, int core_cells,
                   const SlabPlan& plan, int s, const MeshFairing& fairing, const detail::KeepDeep* deep = nullptr,
                   const detail::PointTree* points = nullptr);

// The ghosts of a slab that its guard's check compares with their owners' (SlabWeld's
// bands), and how many of them differ from the whole surface's vertices, the slab's own
// (`own` of them) beginning at `first` there.
struct SlabBands {
    std::vector<Vec3> below, above;
};
SlabBands slab_bands(const SlabWeld& w);
std::size_t bands_differing(const SlabBands& b, const std::vector<Vec3>& whole, std::size_t first, std::size_t own);

// The slab's own vertices and triangles, numbered as the whole mesh numbers them: the
// slab's first vertex is the whole mesh's `first` (the count of the slabs' before it).
Mesh slab_own(SlabWeld weld, std::size_t first);

}  // namespace snvr
