#include "geometry/neighbour_counts.hpp"

#include <algorithm>
#include <cmath>

namespace snvr::detail {

std::vector<std::uint8_t> points_short_of(const PointTree& t, double r2, std::size_t need, std::size_t below) {
    std::vector<std::uint8_t> short_of(t.size(), 0);
    if (t.size() == 0) return short_of;
    constexpr std::uint32_t kBlock = 128;
    std::vector<const PointTree::Node*> blocks;
    t.for_each_leaf(
        [&](const PointTree::Node& n) {
            if (n.begin >= below) return false;
            if (n.count() > kBlock) return true;
            blocks.push_back(&n);
            return false;
        },
        [&](const PointTree::Node& n) { blocks.push_back(&n); });
    // Float distances between the tree's own coordinates (so that the loops vectorise),
    // with room for their rounding and for that of the double ones the rule is stated in;
    // only a count the room leaves open is taken again in double.
    double far_coordinate = 0;
    for (int a = 0; a < 3; ++a)
        far_coordinate = std::max({far_coordinate, std::abs(t.origin[a]) + std::abs(double(t.nodes[0].lo[a])),
                                   std::abs(t.origin[a]) + std::abs(double(t.nodes[0].hi[a]))});
    const double room = 0x1p-20 * r2 + 8 * std::sqrt(r2) * 0x1p-52 * far_coordinate;
    const float sure_below = float((r2 - room) * (1 - 1e-6)), maybe_below = float((r2 + room) * (1 + 1e-6));
    const auto within = [&](std::uint32_t k, std::uint32_t b, std::uint32_t e) {
        const Vec3f q = t.xyz[k];
        std::size_t sure = 0, maybe = 0;
        for (std::uint32_t j = b; j < e; ++j) {
            const float x = t.xyz[j][0] - q[0], y = t.xyz[j][1] - q[1], z = t.xyz[j][2] - q[2];
            const float d = (x * x + y * y) + z * z;
            sure += d <= sure_below;
            maybe += d <= maybe_below;
        }
        if (sure >= need || maybe < need) return sure;
        const Vec3 p = t.point(k);
        std::size_t near = 0;
        for (std::uint32_t j = b; j < e; ++j) near += PointTree::dist_sq(p, t.point(j)) <= r2;
        return near;
    };
    const std::ptrdiff_t nb = std::ptrdiff_t(blocks.size());
#pragma omp parallel for schedule(dynamic, 16)
    for (std::ptrdiff_t b = 0; b < nb; ++b) {
        const PointTree::Node& block = *blocks[b];
        if (block.count() >= need && PointTree::dist_sq(t.lo(block), t.hi(block)) <= r2) continue;
        // The block with those on either side (when they are blocks, not leaves of copies).
        const std::uint32_t wide_begin = b > 0 && blocks[b - 1]->count() <= kBlock ? blocks[b - 1]->begin : block.begin;
        const std::uint32_t wide_end = b + 1 < nb && blocks[b + 1]->count() <= kBlock ? blocks[b + 1]->end : block.end;
        // Runs of `need` points in a row (neighbours in Morton order: on a dense cloud
        // nearly always close together) whose box is within reach across clear each other.
        bool cleared[kBlock] = {};
        const auto run = [&](std::uint32_t b) {
            Vec3f lo = t.xyz[b], hi = lo;
            for (std::uint32_t k = b + 1; k < b + need; ++k)
                for (int a = 0; a < 3; ++a) {
                    lo[a] = std::min(lo[a], t.xyz[k][a]);
                    hi[a] = std::max(hi[a], t.xyz[k][a]);
                }
            const Vec3 o = t.origin;  // as t.lo() and t.hi() make a box's corners
            if (PointTree::dist_sq({o[0] + double(lo[0]), o[1] + double(lo[1]), o[2] + double(lo[2])},
                                   {o[0] + double(hi[0]), o[1] + double(hi[1]), o[2] + double(hi[2])}) <= r2)
                std::fill(cleared + (b - block.begin), cleared + (b - block.begin + need), true);
        };
        // (A leaf of more points than a block holds copies of one point: the leaf test clears them.)
        const bool runs = block.count() >= need && block.count() <= kBlock;
        if (runs) {
            for (std::uint32_t shift = 0; shift < 3; ++shift)
                for (std::uint32_t b = block.begin + std::uint32_t(shift * need / 3); b + need <= block.end; b += std::uint32_t(need)) run(b);
            run(block.end - std::uint32_t(need));
        }
        t.for_each_leaf_below(
            block, [](const PointTree::Node&) { return true; },
            [&](const PointTree::Node& leaf) {
                if (leaf.count() >= need && PointTree::dist_sq(t.lo(leaf), t.hi(leaf)) <= r2) return;
                for (std::uint32_t k = leaf.begin; k < leaf.end; ++k) {
                    if (runs && cleared[k - block.begin]) continue;
                    if (within(k, leaf.begin, leaf.end) >= need) continue;
                    if (within(k, block.begin, block.end) >= need) continue;
                    // Then with the blocks on either side (in Morton order, often across
                    // the boundary that split the point from its neighbours), before a
                    // search of the tree.
                    if (wide_end - wide_begin > block.count() && within(k, wide_begin, wide_end) >= need) continue;
                    short_of[k] = t.count_within(t.point(k), r2, need) < need;
                }
            });
    }
    return short_of;
}

}  // namespace snvr::detail
