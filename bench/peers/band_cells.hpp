// The cells of a grid whose centres may lie within a reach of some point, found from
// the points a brick (8^3 cells) at a time, so that the work follows the surface and
// never the box: each point marks its cell, and each marked row of a brick marks the
// rows of cells within the reach around it. A superset (by at most half a cell's
// diagonal of reach), never a subset.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "snvr/domain.hpp"
#include "snvr/geometry.hpp"

namespace snvr::peers {

struct BandCells {
    static constexpr std::uint32_t kNone = 0xffffffffu;
    using Mask = std::array<std::uint64_t, 8>;  // a brick's 512 cells: bit x + 8 (y + 8 z)

    int bricks_x = 0, bricks_y = 0, bricks_z = 0;  // bricks of 8^3 cells per axis (as snvr::Field)
    std::vector<std::uint32_t> slot;   // per brick, x fastest: its index in `masks`, or kNone
    std::vector<std::uint32_t> brick;  // per slot: the brick it holds
    std::vector<Mask> masks;           // per slot: the band's cells of that brick (none empty)

    std::size_t cells() const;
};

// Every cell of `grid` whose centre is within `reach` (world units) of a point, and
// perhaps a few more within reach + half a cell's diagonal. The points must lie in the
// grid (cells outside it are clamped to its edge).
BandCells band_cells(const PointSet& points, const Domain& grid, double reach);

}  // namespace snvr::peers
