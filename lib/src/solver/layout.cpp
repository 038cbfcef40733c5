#include "solver/layout.hpp"

namespace snvr {

BrickLayout make_layout(const Domain& domain, const std::vector<std::uint8_t>& fine_mask,
                        const std::vector<std::uint8_t>& inside_bricks) {
    BrickLayout layout;
    layout.hierarchy = make_levels(domain);
    set_active_bricks(layout.hierarchy, fine_mask);
    for (const Level& lv : layout.hierarchy.levels) layout.grids.emplace_back(lv);
    BrickGrid& fine = layout.grids[0];
    for (std::uint32_t b = 0; b < fine.slot.size(); ++b)
        if (fine.slot[b] < kConstantSlots) fine.slot[b] = inside_bricks[b] ? kPlusSlot : kMinusSlot;
    return layout;
}

template <class Real>
BrickLayout make_layout(const Domain& domain, const std::vector<std::uint8_t>& fine_mask, const Real* distance,
                        Real offset) {
    const Level fine = make_levels(domain).levels[0];
    std::vector<std::uint8_t> inside(fine.brick_count(), 0);
    for (std::uint32_t b = 0; b < inside.size(); ++b) {
        const CellRange r = fine.range(b);
        inside[b] = offset - distance[domain.index(r.i0, r.j0, r.k0)] > 0;
    }
    return make_layout(domain, fine_mask, inside);
}

template BrickLayout make_layout<double>(const Domain&, const std::vector<std::uint8_t>&, const double*, double);
template BrickLayout make_layout<float>(const Domain&, const std::vector<std::uint8_t>&, const float*, float);

}  // namespace snvr
