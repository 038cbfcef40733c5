// The whole grid's phase field put together from tiles' cores: each core's bricks copied
// into one brick field, the constant bricks shared as in a whole run's.
#pragma once
#include <cstdint>
#include <vector>

#include "snvr/domain.hpp"
#include "snvr/field.hpp"
#include "solver/tile_plan.hpp"

namespace snvr {

template <class Real>
class FieldAssembly {
public:
    // Every brick -1 (outside the shell) until a tile's core says otherwise.
    explicit FieldAssembly(const Domain& whole);
    // The bricks of the tile's core from its field (on the tile's own grid; a whole run's
    // brick layout: the constant bricks in its first slots); a core placed again replaces
    // what it placed before.
    void place(const Field& tile_field, const Tile& tile);
    Field take();

private:
    Domain whole_;
    std::vector<std::uint32_t> table_;
    std::vector<Real> stored_;
};

}  // namespace snvr
