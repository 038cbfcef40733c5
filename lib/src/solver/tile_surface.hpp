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
#include "snvr/tiles.hpp"
#include "solver/tile_plan.hpp"

namespace snvr {

// The samples [lo, hi) the tile's own part owns.
void tile_interior(const Tile& tile, const Domain& whole, std::array<int, 3>& lo, std::array<int, 3>& hi);

// The tile's own part of the surface, from its field (on the tile's own grid).
TileSurface tile_surface(const Field& tile_field, const Tile& tile, const Domain& whole);

// The tile's field with only the bricks of its core next to a face inside the grid (the
// rest of the tile constant): what the seams need of it.
Field tile_faces(const Field& tile_field, const Tile& tile, const Domain& whole);

// The faces of the tile's core inside the grid (0 to 6).
int inner_faces(const Tile& tile, const Domain& whole);

// The stored (not constant) bricks of the tile's core, in its field (on the tile's grid).
std::size_t stored_core_bricks(const Field& tile_field, const Tile& tile);

// The whole grid's surface: the tiles' own parts (by tile index; empty for a tile not run)
// and the seams from `faces`, the whole grid's field where the cores' face bricks are
// placed. Frees the parts as it goes.
Mesh weld_tile_surfaces(std::vector<TileSurface>& parts, const std::vector<Tile>& tiles, const Field& faces,
                        const Domain& whole, int core_cells);

}  // namespace snvr
