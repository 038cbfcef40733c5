// The computational grid: a uniform cell-centred box around the points.
#pragma once
#include <algorithm>
#include <cstddef>

#include "snvr/geometry.hpp"

namespace snvr {

struct Domain {
    Vec3 origin{0, 0, 0};  // world position of the lower corner of cell (0,0,0)
    double h = 1;          // voxel size in world units
    int nx = 0, ny = 0, nz = 0;
    int levels = 1;        // multigrid levels; each size is a multiple of 2^(levels-1)

    std::size_t cells() const { return std::size_t(nx) * std::size_t(ny) * std::size_t(nz); }
    std::size_t index(int i, int j, int k) const {
        return std::size_t(i) + std::size_t(nx) * (std::size_t(j) + std::size_t(ny) * std::size_t(k));
    }
    Vec3 cell_center(int i, int j, int k) const {
        return {origin[0] + (i + 0.5) * h, origin[1] + (j + 0.5) * h, origin[2] + (k + 0.5) * h};
    }
    // The solver's unit length in cells: the longest side, or (a tile of a larger grid) the
    // whole grid's, so that a tile computes in the same numbers as the whole run.
    int unit_cells = 0;  // 0: the longest side
    int unit() const { return unit_cells > 0 ? unit_cells : std::max({nx, ny, nz}); }
    // Length that maps to 1 in the solver's normalised units.
    double length_scale() const { return h * unit(); }
};

}  // namespace snvr
