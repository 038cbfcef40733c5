// The brick layout of a run, built once and handed to Backend::setup: the multigrid
// levels with their active bricks, and where each brick's cells are stored (an own
// slot for an active brick, a shared constant brick otherwise). Backends allocate and
// index by it; they never derive it themselves.
#pragma once
#include <cstdint>
#include <vector>

#include "solver/brick_grid.hpp"
#include "solver/hierarchy.hpp"

namespace snvr {

struct BrickLayout {
    Hierarchy hierarchy;
    std::vector<BrickGrid> grids;  // one per level

    const Level& level(int l) const { return hierarchy.levels[std::size_t(l)]; }
    const BrickGrid& grid(int l) const { return grids[std::size_t(l)]; }
    int levels() const { return int(hierarchy.levels.size()); }
};

// Levels of `domain`, active where `fine_mask` (one byte per level-0 brick) is set and
// where any of a coarse brick's children is. Level 0's inactive bricks hold +1 where
// `inside_bricks` is set (inside the shell, l > d), -1 elsewhere.
BrickLayout make_layout(const Domain& domain, const std::vector<std::uint8_t>& fine_mask,
                        const std::vector<std::uint8_t>& inside_bricks);

// The same from a dense normalised distance: an inactive brick's first cell decides.
template <class Real>
BrickLayout make_layout(const Domain& domain, const std::vector<std::uint8_t>& fine_mask, const Real* distance,
                        Real offset);

// A dense level-0 field (x-fastest) in the layout's brick storage, as init_phase and
// the backends take it: active bricks' cells, zero elsewhere.
template <class Real>
std::vector<Real> pack_level0(const BrickLayout& layout, const Real* dense) {
    std::vector<Real> packed(layout.grid(0).storage(), Real(0));
    pack_active(layout.grid(0), layout.level(0), dense, packed.data());
    return packed;
}

}  // namespace snvr
