// What a run will hold, checked before it is allocated: first what follows the box
// (brick tables, the mesher's sign bits; plan_domain, before any distance), then the
// solver's fields exactly, from the brick layout (the session, before the backend
// allocates them).
#pragma once
#include <cstddef>

#include "snvr/domain.hpp"
#include "snvr/field.hpp"
#include "solver/layout.hpp"

namespace snvr {

inline std::size_t real_size(Precision p) { return p == Precision::Double ? sizeof(double) : sizeof(float); }

// One slot entry per brick of every level, and the mesher's bit per cell.
std::size_t estimate_plan_bytes(const Domain& d);

// The distance of the bricks near the points, and its packed copy beside it for a
// moment: known before the distance is computed, so that a grid far too fine is refused
// before it fills the memory (the fields are checked exactly once the layout is known).
std::size_t band_distance_bytes(std::size_t near_bricks, Precision p);

// The solver's fields on this layout: phi, rhs and g on every level, and the distance
// on level 0, each over the active bricks plus the shared constant bricks.
std::size_t layout_bytes(const BrickLayout& layout, Precision p);

// Throws ResourceError naming the grid when `bytes` exceed 90% of the memory available
// plus `held`, the part of `bytes` the run holds already.
void require_memory(std::size_t bytes, const Domain& d, std::size_t held = 0);

}  // namespace snvr
