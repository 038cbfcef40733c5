// The multigrid levels and, on each, the bricks (8^3 blocks of cells) where the
// coefficient g can be non-zero. Everywhere else the linear step is the identity and
// the nonlinear step does nothing, so every operation visits active bricks only and
// the cost follows the surface area, not the volume.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "grid/brick_tiling.hpp"
#include "snvr/domain.hpp"

namespace snvr {

struct Level : BrickTiling {
    double h = 0;                        // normalised cell size
    std::vector<std::uint32_t> bricks;   // active brick ids, ascending
    std::size_t brick_cells = 0;         // cells inside the active bricks
};

struct Hierarchy {
    std::vector<Level> levels;
};

// Level shapes for the domain (level l has n / 2^l cells per axis, normalised h = 2^l / max n).
Hierarchy make_levels(const Domain& domain);

// Sets the active bricks: level 0 from the mask (one byte per level-0 brick), each coarser
// level where any of its eight child bricks is active.
void set_active_bricks(Hierarchy& hierarchy, const std::vector<std::uint8_t>& fine_mask);

}  // namespace snvr
