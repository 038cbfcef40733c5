#include "solver/hierarchy.hpp"

#include <algorithm>

namespace snvr {

Hierarchy make_levels(const Domain& domain) {
    Hierarchy hier;
    const int longest = domain.unit();
    for (int l = 0; l < domain.levels; ++l) {
        Level lv;
        static_cast<BrickTiling&>(lv) = BrickTiling::of(domain.nx >> l, domain.ny >> l, domain.nz >> l);
        lv.h = double(1 << l) / longest;
        hier.levels.push_back(lv);
    }
    return hier;
}

void set_active_bricks(Hierarchy& hier, const std::vector<std::uint8_t>& fine_mask) {
    std::vector<std::uint8_t> mask = fine_mask;
    for (std::size_t l = 0; l < hier.levels.size(); ++l) {
        Level& lv = hier.levels[l];
        lv.bricks.clear();
        lv.brick_cells = 0;
        for (std::uint32_t b = 0; b < mask.size(); ++b)
            if (mask[b]) {
                lv.bricks.push_back(b);
                const CellRange r = lv.range(b);
                lv.brick_cells += std::size_t(r.i1 - r.i0) * std::size_t(r.j1 - r.j0) * std::size_t(r.k1 - r.k0);
            }
        if (l + 1 == hier.levels.size()) break;
        // A coarse brick covers 2x2x2 fine bricks.
        const Level& cv = hier.levels[l + 1];
        std::vector<std::uint8_t> coarse(cv.brick_count(), 0);
        for (std::uint32_t b : lv.bricks) {
            const int bi = int(b % std::uint32_t(lv.bx)), bj = int(b / std::uint32_t(lv.bx) % std::uint32_t(lv.by)),
                      bk = int(b / (std::uint32_t(lv.bx) * std::uint32_t(lv.by)));
            coarse[std::size_t(bi / 2) + std::size_t(cv.bx) * (std::size_t(bj / 2) + std::size_t(cv.by) * std::size_t(bk / 2))] = 1;
        }
        mask.swap(coarse);
    }
}

}  // namespace snvr
