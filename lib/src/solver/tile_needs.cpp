// needs_of and owners_of (tile_needs.hpp).
#include "solver/tile_needs.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace snvr {

namespace {

// A box of world coordinates: a tile's cells [lo, hi) widened by `reach`.
struct Reach {
    Vec3 lo, hi;
    Reach(const Domain& whole, const std::array<int, 3>& from, const std::array<int, 3>& to, double reach) {
        for (int a = 0; a < 3; ++a) {
            lo[std::size_t(a)] = whole.origin[std::size_t(a)] + from[std::size_t(a)] * whole.h - reach;
            hi[std::size_t(a)] = whole.origin[std::size_t(a)] + to[std::size_t(a)] * whole.h + reach;
        }
    }
    bool holds(const Vec3& p) const {
        for (int a = 0; a < 3; ++a)
            if (!(p[a] >= lo[a] && p[a] <= hi[a])) return false;
        return true;
    }
    bool holds(const Vec3& from, const Vec3& to) const { return holds(from) && holds(to); }
    bool meets(const Vec3& from, const Vec3& to) const {
        for (int a = 0; a < 3; ++a)
            if (to[a] < lo[a] || from[a] > hi[a]) return false;
        return true;
    }
};

// One leaf's share of the tiles' needs: a leaf's box inside the tile's reach counts whole,
// one across its edge point by point.
void add_leaf(const detail::PointTree& tree, const detail::PointTree::Node& leaf, const Domain& whole,
              const Tile& t, double reach, TileNeeds& need) {
    const Vec3 lo = tree.lo(leaf), hi = tree.hi(leaf);
    const Reach box(whole, t.lo, t.hi, reach), core(whole, t.core_lo, t.core_hi, reach);
    if (!box.meets(lo, hi)) return;
    if (box.holds(lo, hi)) {
        need.points += leaf.count();
    } else {
        for (std::uint32_t k = leaf.begin; k < leaf.end; ++k) need.points += box.holds(tree.point(k));
    }
    if (need.core_near || !core.meets(lo, hi)) return;
    for (std::uint32_t k = leaf.begin; k < leaf.end && !need.core_near; ++k) need.core_near = core.holds(tree.point(k));
}

// Calls f(t) for each tile whose box can come within `reach` of the box [lo, hi] (by
// core: the caller checks exactly); `count` tiles along each axis.
template <class F>
void for_tiles_near(const Vec3& lo, const Vec3& hi, const Domain& whole, const int (&count)[3], int core_cells,
                    int halo_cells, double reach, F&& f) {
    int first[3], last[3];
    for (int a = 0; a < 3; ++a) {
        const double cells = reach / whole.h + halo_cells;
        first[a] = std::max(0, int(std::floor(((lo[a] - whole.origin[std::size_t(a)]) / whole.h - cells) / core_cells)));
        last[a] = std::min(count[a] - 1,
                           int(std::floor(((hi[a] - whole.origin[std::size_t(a)]) / whole.h + cells) / core_cells)));
    }
    for (int kz = first[2]; kz <= last[2]; ++kz)
        for (int ky = first[1]; ky <= last[1]; ++ky)
            for (int kx = first[0]; kx <= last[0]; ++kx) f(std::size_t(kx + count[0] * (ky + count[1] * kz)));
}

void tile_counts(const Domain& whole, int core_cells, int (&count)[3]) {
    const int n[3] = {whole.nx, whole.ny, whole.nz};
    for (int a = 0; a < 3; ++a) count[a] = (n[a] + core_cells - 1) / core_cells;
}

}  // namespace

double band_reach(const DomainPlan& plan, const Parameters& params) {
    return plan.offset + std::max(params.band_xi * plan.xi, plan.domain.h) + plan.domain.h;
}

std::vector<TileNeeds> needs_of(const detail::PointTree& tree, const Domain& whole, const std::vector<Tile>& tiles,
                                int core_cells, int halo_cells, double reach) {
    std::vector<const detail::PointTree::Node*> leaves;
    tree.for_each_leaf([](const detail::PointTree::Node&) { return true; },
                       [&](const detail::PointTree::Node& leaf) { leaves.push_back(&leaf); });
    int count[3];
    tile_counts(whole, core_cells, count);
    std::vector<TileNeeds> needs(tiles.size());
    const std::ptrdiff_t nl = std::ptrdiff_t(leaves.size());
#pragma omp parallel
    {
        std::vector<TileNeeds> mine(tiles.size());
#pragma omp for schedule(dynamic, 1024)
        for (std::ptrdiff_t l = 0; l < nl; ++l) {
            const detail::PointTree::Node& leaf = *leaves[std::size_t(l)];
            const Vec3 lo = tree.lo(leaf), hi = tree.hi(leaf);
            for_tiles_near(lo, hi, whole, count, core_cells, halo_cells, reach,
                           [&](std::size_t t) { add_leaf(tree, leaf, whole, tiles[t], reach, mine[t]); });
        }
#pragma omp critical
        for (std::size_t t = 0; t < tiles.size(); ++t) {
            needs[t].points += mine[t].points;
            needs[t].core_near = needs[t].core_near || mine[t].core_near;
        }
    }
    return needs;
}

std::vector<int> owners_of(const std::vector<TileNeeds>& needs, int processes) {
    std::vector<std::size_t> order;
    for (std::size_t t = 0; t < needs.size(); ++t)
        if (needs[t].core_near) order.push_back(t);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return needs[a].points > needs[b].points; });
    std::vector<int> owner(needs.size(), -1);
    std::vector<double> load(std::size_t(processes), 0);
    for (std::size_t t : order) {
        const auto least = std::min_element(load.begin(), load.end());
        owner[t] = int(least - load.begin());
        *least += double(needs[t].points) + 1;
    }
    return owner;
}

std::vector<float> points_for(const detail::PointTree& tree, const Domain& whole, const std::vector<Tile>& tiles,
                              const std::vector<int>& owner, int process, int core_cells, int halo_cells, double reach) {
    int count[3];
    tile_counts(whole, core_cells, count);
    std::vector<float> xyz;
    std::vector<std::size_t> near;
    tree.for_each_leaf([](const detail::PointTree::Node&) { return true; }, [&](const detail::PointTree::Node& leaf) {
        const Vec3 lo = tree.lo(leaf), hi = tree.hi(leaf);
        near.clear();
        for_tiles_near(lo, hi, whole, count, core_cells, halo_cells, reach, [&](std::size_t t) {
            if (owner[t] == process && Reach(whole, tiles[t].lo, tiles[t].hi, reach).meets(lo, hi)) near.push_back(t);
        });
        for (std::uint32_t k = leaf.begin; k < leaf.end && !near.empty(); ++k) {
            const Vec3 p = tree.point(k);
            for (std::size_t t : near)
                if (Reach(whole, tiles[t].lo, tiles[t].hi, reach).holds(p)) {
                    xyz.insert(xyz.end(), tree.xyz[k].begin(), tree.xyz[k].end());
                    break;
                }
        }
    });
    return xyz;
}

}  // namespace snvr
