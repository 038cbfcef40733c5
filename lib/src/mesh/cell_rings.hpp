// What the mesh checks' uniform grids share (TriangleGrid, the point grid of the
// quality measures): cells of edge `size` from `lo`, n per axis, searched outwards from
// a query's cell ring by ring.
#pragma once
#include <algorithm>
#include <array>
#include <cstdlib>
#include <limits>

#include "snvr/geometry.hpp"

namespace snvr::detail {

// Squared distance from p to cell `at`.
inline double cell_gap_sq(const Vec3& lo, double size, const std::array<int, 3>& at, const Vec3& p) {
    double box = 0;
    for (int d = 0; d < 3; ++d) {
        const double low = lo[d] + at[d] * size;
        const double gap = std::max(0.0, std::max(low - p[d], p[d] - (low + size)));
        box += gap * gap;
    }
    return box;
}

// visit(x, y, z) for each cell at Chebyshev distance exactly r from cell c, clipped to
// the grid.
template <class Visit>
void for_ring(const std::array<int, 3>& c, int r, const std::array<int, 3>& n, Visit&& visit) {
    const int z0 = std::max(0, c[2] - r), z1 = std::min(n[2] - 1, c[2] + r);
    const int y0 = std::max(0, c[1] - r), y1 = std::min(n[1] - 1, c[1] + r);
    const int x0 = std::max(0, c[0] - r), x1 = std::min(n[0] - 1, c[0] + r);
    for (int z = z0; z <= z1; ++z)
        for (int y = y0; y <= y1; ++y) {
            if (std::abs(z - c[2]) == r || std::abs(y - c[1]) == r) {
                for (int x = x0; x <= x1; ++x) visit(x, y, z);
            } else {
                if (c[0] - r >= 0) visit(c[0] - r, y, z);
                if (r > 0 && c[0] + r < n[0]) visit(c[0] + r, y, z);
            }
        }
}

// Every cell beyond ring r of c lies beyond one of the ring's faces that still has cells
// behind it: the distance from p to the nearest such face (infinity when none is left).
inline double beyond_ring(const Vec3& lo, double size, const std::array<int, 3>& n, const std::array<int, 3>& c, int r,
                          const Vec3& p) {
    double bound = std::numeric_limits<double>::infinity();
    for (int d = 0; d < 3; ++d) {
        if (c[d] + r + 1 < n[d]) bound = std::min(bound, std::max(0.0, lo[d] + (c[d] + r + 1) * size - p[d]));
        if (c[d] - r - 1 >= 0) bound = std::min(bound, std::max(0.0, p[d] - (lo[d] + (c[d] - r) * size)));
    }
    return bound;
}

}  // namespace snvr::detail
