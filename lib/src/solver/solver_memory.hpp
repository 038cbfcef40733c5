// What the solver will hold, estimated before anything is allocated.
#pragma once
#include <cstddef>

#include "snvr/domain.hpp"
#include "snvr/field.hpp"

namespace snvr {

inline std::size_t real_size(Precision p) { return p == Precision::Double ? sizeof(double) : sizeof(float); }

// At most: three fields (phi, rhs, g) on every level (fewer where bricks are inactive),
// the distance on the finest (per near brick while it is computed, then kept by the
// backend for the tube), and the dense copy of phi handed back in the result.
inline std::size_t estimate_solver_bytes(const Domain& d, Precision p) {
    std::size_t cells = 0;
    for (int l = 0; l < d.levels; ++l)
        cells += std::size_t(d.nx >> l) * std::size_t(d.ny >> l) * std::size_t(d.nz >> l);
    return (3 * cells + 2 * d.cells()) * real_size(p);
}

}  // namespace snvr
