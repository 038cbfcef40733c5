#include "solver/layout.hpp"

namespace snvr {

template <class Real>
BrickLayout make_layout(const Domain& domain, const std::vector<std::uint8_t>& fine_mask, const Real* distance,
                        Real offset) {
    BrickLayout layout;
    layout.hierarchy = make_levels(domain);
    set_active_bricks(layout.hierarchy, fine_mask);
    for (const Level& lv : layout.hierarchy.levels) layout.grids.emplace_back(lv);
    assign_constant_slots(layout.grids[0], layout.hierarchy.levels[0], distance, offset);
    return layout;
}

template BrickLayout make_layout<double>(const Domain&, const std::vector<std::uint8_t>&, const double*, double);
template BrickLayout make_layout<float>(const Domain&, const std::vector<std::uint8_t>&, const float*, float);

}  // namespace snvr
