// The tiles' needs and points by the processes' ranges (ranged_tile_points.hpp). What goes
// between them: the first tells each other its range (its size, the first's origin, the
// scale factors since the filing); the needs are summed; each process's count of points
// for each other is summed into a table that all hold; then, one process at a time, the
// others send it their points for it, which it takes in the ranges' order (each sender
// sends once a turn, the taker takes them in rank order: no two wait on each other).
#include "solver/ranged_tile_points.hpp"

#include <algorithm>
#include <cstdint>
#include <string>

#include "snvr/error.hpp"
#include "solver/sent_arrays.hpp"
#include "solver/shared_filing.hpp"

namespace snvr {

namespace {

constexpr std::size_t kToldHead = 4;  // the range's size, the first's origin; then the scale factors

std::size_t count_of(const PointRuns& runs) {
    std::size_t n = 0;
    for (const auto& r : runs) n += r[1] - r[0];
    return n;
}

}  // namespace

bool tiles_by_ranges(const detail::PointTree& tree, int processes) {
    return processes > 1 && tree.shared_ranges.size() == std::size_t(processes) + 1;
}

OwnRange tell_ranges(TileScheduler& on, const detail::PointTree& tree) {
    for (int p = 1; p < on.processes(); ++p) {
        const std::size_t b = tree.shared_ranges[std::size_t(p)], e = tree.shared_ranges[std::size_t(p) + 1];
        std::vector<double> told{double(e - b), tree.origin[0], tree.origin[1], tree.origin[2]};
        told.insert(told.end(), tree.scaled_since.begin(), tree.scaled_since.end());
        detail::send_array(on, p, told.data(), told.size());
    }
    return {&tree, {0, std::uint32_t(tree.shared_ranges[1])}};
}

OwnRange told_range(TileScheduler& on, detail::KeptRange* kept) {
    std::vector<double> told;
    detail::receive_array(on, 0, told);
    if (told.size() < kToldHead) throw Error("tiles: the first process's word on this process's range is not whole");
    const std::vector<double> scaled(told.begin() + kToldHead, told.end());
    const detail::PointTree& tree =
        detail::kept_as_first(kept, std::size_t(told[0]), scaled, {told[1], told[2], told[3]});
    return {&tree, {0, std::uint32_t(tree.size())}};
}

std::vector<TileNeeds> ranged_needs(TileScheduler& on, const OwnRange& own, const Domain& whole,
                                    const std::vector<Tile>& tiles, int core_cells, int halo_cells, double reach) {
    std::vector<TileNeeds> needs = needs_of(*own.tree, whole, tiles, core_cells, halo_cells, reach, own.range);
    const std::size_t n = needs.size();
    std::vector<std::uint64_t> sums(2 * n);
    for (std::size_t t = 0; t < n; ++t) {
        sums[t] = needs[t].points;
        sums[n + t] = needs[t].core_near ? 1 : 0;
    }
    on.sum(sums);
    for (std::size_t t = 0; t < n; ++t) needs[t] = {std::size_t(sums[t]), sums[n + t] > 0};
    return needs;
}

detail::PointArray<Vec3f> ranged_points(TileScheduler& on, const OwnRange& own, const Domain& whole,
                                        const std::vector<Tile>& tiles, const std::vector<int>& owner,
                                        int core_cells, int halo_cells, double reach, RangedPointsFacts& facts) {
    const int processes = on.processes(), me = on.rank();
    const std::size_t np = std::size_t(processes);
    std::vector<PointRuns> runs =
        point_runs(*own.tree, whole, tiles, owner, processes, core_cells, halo_cells, reach, own.range);
    // counted[q * processes + p]: the points of q's range for p's tiles.
    std::vector<std::uint64_t> counted(np * np, 0);
    for (std::size_t p = 1; p < np; ++p) counted[std::size_t(me) * np + p] = count_of(runs[p]);
    on.sum(counted);
    detail::PointArray<Vec3f> mine;
    for (int p = 1; p < processes; ++p) {
        const std::size_t to = std::size_t(p);
        if (p != me) {
            if (const std::uint64_t n = counted[std::size_t(me) * np + to]) {
                const detail::PointArray<float> xyz = points_in(*own.tree, runs[to]);
                if (xyz.size() != 3 * n) throw Error("tiles: a range's points for another process are not its count");
                detail::send_array(on, p, xyz.data(), xyz.size());
            }
            runs[to] = PointRuns();
            continue;
        }
        std::size_t total = 0;
        for (std::size_t q = 0; q < np; ++q) total += counted[q * np + to];
        mine.resize(total);
        std::size_t at = 0;
        for (std::size_t q = 0; q < np; ++q) {
            const std::size_t n = counted[q * np + to];
            if (q == std::size_t(me)) {
                for (const auto& r : runs[to]) {
                    std::copy(own.tree->xyz.begin() + std::ptrdiff_t(r[0]), own.tree->xyz.begin() + std::ptrdiff_t(r[1]),
                              mine.begin() + std::ptrdiff_t(at));
                    at += r[1] - r[0];
                }
            } else if (n) {
                detail::receive_into(on, int(q), mine.data() + at, n);
                at += n;
            }
        }
        runs[to] = PointRuns();
    }
    facts = {};
    for (std::size_t p = 1; p < np; ++p)
        for (std::size_t q = 0; q < np; ++q) (q == p ? facts.own : facts.given) += counted[q * np + p];
    return mine;
}

}  // namespace snvr
