// A tiled run's surface without the whole field (Parameters::whole_field false). Each tile
// extracts the part of the dual mesh that its core alone decides, its interior: the core
// less one sample at a low face and two at a high face inside the grid (a piece reads one
// sample below what it owns and two above; mesh/dual_pieces.hpp). What no interior owns,
// the seams (three samples about each plane between cores), is extracted from the bricks
// next to the cores' faces, which the tiles keep of their fields (a brick layer a face).
// Welded by the whole grid's keys, the pieces are the mesh of the field the cores make
// together, bit for bit: no distance tolerance, one owner for each vertex.
#pragma once
#include <array>
#include <vector>

#include "snvr/domain.hpp"
#include "snvr/field.hpp"
#include "snvr/mesh.hpp"
#include "mesh/dual_pieces.hpp"
#include "solver/tile_plan.hpp"

namespace snvr {

// The samples [lo, hi) the tile's own part owns.
void tile_interior(const Tile& tile, const Domain& whole, std::array<int, 3>& lo, std::array<int, 3>& hi);

// The tile's own part of the surface, from its field (on the tile's own grid), in slices
// of `slice` planes along z (detail::split_planes; 0: one piece).
std::vector<detail::MeshPiece> tile_surface(const Field& tile_field, const Tile& tile, const Domain& whole, int slice = 0);

// The tile's field with only the bricks of its core next to a face inside the grid (the
// rest of the tile constant): what the seams need of it.
Field tile_faces(const Field& tile_field, const Tile& tile, const Domain& whole);

// The faces of the tile's core inside the grid (0 to 6).
int inner_faces(const Tile& tile, const Domain& whole);

// The stored (not constant) bricks of the tile's core, in its field (on the tile's grid).
std::size_t stored_core_bricks(const Field& tile_field, const Tile& tile);

// The bricks next to the cores' faces (the whole grid's field with them placed) over the
// whole grid's planes [z, z + field.nz), z a multiple of the brick.
struct FacesPart {
    Field field;
    int z = 0;
};
// Those `planes` need for their seams.
FacesPart faces_for(const Field& faces, const detail::Planes& planes);

// The seams' pieces of the whole grid's surface in `planes` (no tile's interior owns
// them), from `faces`, which must cover what faces_for gives; each owning its box within
// the planes. With the tiles' pieces there, welded with those planes
// (detail::weld_pieces), they are the whole grid's mesh over them, in its order.
std::vector<detail::MeshPiece> seam_pieces(const FacesPart& faces, const Domain& whole, int core_cells,
                                           const detail::Planes& planes);

}  // namespace snvr
