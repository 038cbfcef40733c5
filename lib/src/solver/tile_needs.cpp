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

// The leaves with points in `range`, each's points there [begin, end) (its box may hold
// more: a superset, so that a test of the box passed holds for those points too).
template <class Leaf>
void for_each_leaf_in(const detail::PointTree& tree, PointRange range, Leaf&& leaf) {
    tree.for_each_leaf([&](const detail::PointTree::Node& n) { return n.end > range.begin && n.begin < range.end; },
                       [&](const detail::PointTree::Node& n) {
                           leaf(n, std::max(n.begin, range.begin), std::min(n.end, range.end));
                       });
}

// One leaf's share of the tiles' needs, its points [begin, end): a leaf's box inside the
// tile's reach counts them all, one across its edge point by point.
void add_leaf(const detail::PointTree& tree, const detail::PointTree::Node& leaf, std::uint32_t begin,
              std::uint32_t end, const Domain& whole, const Tile& t, double reach, TileNeeds& need) {
    const Vec3 lo = tree.lo(leaf), hi = tree.hi(leaf);
    const Reach box(whole, t.lo, t.hi, reach), core(whole, t.core_lo, t.core_hi, reach);
    if (!box.meets(lo, hi)) return;
    if (box.holds(lo, hi)) {
        need.points += end - begin;
    } else {
        for (std::uint32_t k = begin; k < end; ++k) need.points += box.holds(tree.point(k));
    }
    if (need.core_near || !core.meets(lo, hi)) return;
    for (std::uint32_t k = begin; k < end && !need.core_near; ++k) need.core_near = core.holds(tree.point(k));
}

// Calls f(t) for each tile whose box may come within `reach` of the world box [lo, hi]
// (by whole cells: the caller tests exactly).
template <class F>
void for_tiles_near(const Vec3& lo, const Vec3& hi, const Domain& whole, const std::vector<Tile>& tiles,
                    int core_cells, int halo_cells, double reach, F&& f) {
    std::array<int, 3> from{}, to{};
    for (int a = 0; a < 3; ++a) {
        const double o = whole.origin[std::size_t(a)];
        from[std::size_t(a)] = int(std::floor((lo[a] - reach - o) / whole.h));
        to[std::size_t(a)] = int(std::floor((hi[a] + reach - o) / whole.h)) + 1;
    }
    for_tiles_meeting(tiles, whole, core_cells, halo_cells, from, to, f);
}

}  // namespace

double band_reach(const DomainPlan& plan, const Parameters& params) {
    return plan.offset + std::max(params.band_xi * plan.xi, plan.domain.h) + plan.domain.h;
}

std::vector<TileNeeds> needs_of(const detail::PointTree& tree, const Domain& whole, const std::vector<Tile>& tiles,
                                int core_cells, int halo_cells, double reach, PointRange range) {
    struct Part {
        const detail::PointTree::Node* leaf;
        std::uint32_t begin, end;
    };
    std::vector<Part> leaves;
    for_each_leaf_in(tree, range, [&](const detail::PointTree::Node& leaf, std::uint32_t begin, std::uint32_t end) {
        leaves.push_back({&leaf, begin, end});
    });
    std::vector<TileNeeds> needs(tiles.size());
    const std::ptrdiff_t nl = std::ptrdiff_t(leaves.size());
#pragma omp parallel
    {
        std::vector<TileNeeds> mine(tiles.size());
#pragma omp for schedule(dynamic, 1024)
        for (std::ptrdiff_t l = 0; l < nl; ++l) {
            const Part& part = leaves[std::size_t(l)];
            const Vec3 lo = tree.lo(*part.leaf), hi = tree.hi(*part.leaf);
            for_tiles_near(lo, hi, whole, tiles, core_cells, halo_cells, reach, [&](std::size_t t) {
                add_leaf(tree, *part.leaf, part.begin, part.end, whole, tiles[t], reach, mine[t]);
            });
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

std::vector<PointRuns> point_runs(const detail::PointTree& tree, const Domain& whole, const std::vector<Tile>& tiles,
                                  const std::vector<int>& owner, int processes, int core_cells, int halo_cells,
                                  double reach, PointRange range) {
    // Each leaf's points that fall in the reach of one of a process's tiles: all of them at
    // once when the leaf lies inside one, else one by one. Kept as runs, so that the copy is
    // made once and sized (grown as it went, the 200 M-point block's 1.4 GB for the other
    // process held the first's peak at 6.37 GB); each leaf tested once for every process
    // (a walk a process took 0.2 s of the first's time on 50 M points).
    std::vector<PointRuns> runs(static_cast<std::size_t>(processes));
    const auto take = [&runs](int p, std::uint32_t begin, std::uint32_t end) {
        PointRuns& r = runs[std::size_t(p)];
        if (!r.empty() && r.back()[1] == begin) r.back()[1] = end;
        else r.push_back({begin, end});
    };
    std::vector<std::vector<std::size_t>> near(static_cast<std::size_t>(processes));
    std::vector<std::uint8_t> inside(static_cast<std::size_t>(processes));
    for_each_leaf_in(tree, range, [&](const detail::PointTree::Node& leaf, std::uint32_t begin, std::uint32_t end) {
        const Vec3 lo = tree.lo(leaf), hi = tree.hi(leaf);
        for (auto& n : near) n.clear();
        std::fill(inside.begin(), inside.end(), 0);
        for_tiles_near(lo, hi, whole, tiles, core_cells, halo_cells, reach, [&](std::size_t t) {
            const int p = owner[t];
            if (p < 1 || p >= processes || inside[std::size_t(p)]) return;
            const Reach box(whole, tiles[t].lo, tiles[t].hi, reach);
            if (box.holds(lo, hi)) inside[std::size_t(p)] = 1;
            if (box.meets(lo, hi)) near[std::size_t(p)].push_back(t);
        });
        for (int p = 1; p < processes; ++p) {
            if (inside[std::size_t(p)]) {
                take(p, begin, end);
                continue;
            }
            const std::vector<std::size_t>& tiles_near = near[std::size_t(p)];
            for (std::uint32_t k = begin; k < end && !tiles_near.empty(); ++k) {
                const Vec3 q = tree.point(k);
                for (std::size_t t : tiles_near)
                    if (Reach(whole, tiles[t].lo, tiles[t].hi, reach).holds(q)) {
                        take(p, k, k + 1);
                        break;
                    }
            }
        }
    });
    return runs;
}

std::vector<PointRuns> z_window_runs(const detail::PointTree& tree, const std::vector<std::array<double, 2>>& windows) {
    std::vector<PointRuns> runs(windows.size());
    const auto take = [&runs](std::size_t w, std::uint32_t begin, std::uint32_t end) {
        PointRuns& r = runs[w];
        if (!r.empty() && r.back()[1] == begin) r.back()[1] = end;
        else r.push_back({begin, end});
    };
    tree.for_each_leaf([](const detail::PointTree::Node&) { return true; }, [&](const detail::PointTree::Node& leaf) {
        const double lo = tree.lo(leaf)[2], hi = tree.hi(leaf)[2];
        for (std::size_t w = 0; w < windows.size(); ++w) {
            const auto [a, b] = windows[w];
            if (hi < a || lo > b) continue;
            if (lo >= a && hi <= b) {
                take(w, leaf.begin, leaf.end);
                continue;
            }
            for (std::uint32_t k = leaf.begin; k < leaf.end; ++k)
                if (const double z = tree.point(k)[2]; z >= a && z <= b) take(w, k, k + 1);
        }
    });
    return runs;
}

detail::PointArray<float> points_in(const detail::PointTree& tree, const PointRuns& runs) {
    std::size_t count = 0;
    for (const auto& r : runs) count += r[1] - r[0];
    detail::PointArray<float> xyz;
    xyz.reserve(3 * count);
    for (const auto& r : runs) xyz.insert(xyz.end(), tree.xyz[r[0]].data(), tree.xyz[r[0]].data() + 3 * std::size_t(r[1] - r[0]));
    return xyz;
}

}  // namespace snvr
