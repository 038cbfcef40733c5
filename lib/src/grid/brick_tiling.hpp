// A grid of cells cut into 8^3 bricks, the unit every stage works in from the band's
// distance to the kernels (the last bricks along an axis may be partial). Below both the
// geometry, which computes the distance brick by brick, and the solver, whose levels and
// storage are brick-major.
#pragma once
#include <cstddef>
#include <cstdint>

namespace snvr {

constexpr int kBrick = 8;

struct CellRange {
    int i0, i1, j0, j1, k0, k1;  // half-open
};

struct BrickTiling {
    int nx = 0, ny = 0, nz = 0;
    int bx = 0, by = 0, bz = 0;  // bricks per axis

    // The tiling of an nx x ny x nz grid of cells.
    static BrickTiling of(int nx, int ny, int nz);

    std::size_t cells() const { return std::size_t(nx) * std::size_t(ny) * std::size_t(nz); }
    std::size_t brick_count() const { return std::size_t(bx) * std::size_t(by) * std::size_t(bz); }
    // The cells of a brick (x fastest in the brick ids).
    CellRange range(std::uint32_t brick) const;
};

}  // namespace snvr
