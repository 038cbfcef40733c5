// The check's shares gathered from the slabs (slab_shares.hpp).
#include "check/slab_shares.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>

#include "parallel_sizes.hpp"
#include "snvr/error.hpp"
#include "solver/sent_arrays.hpp"
#include "solver/tile_plan.hpp"

namespace snvr::detail {
namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
using Tri = std::array<std::uint32_t, 3>;

// The cell holding coordinate x along an axis of `n` cells (clamped to the grid).
int cell_of(double x, double origin, double h, int n) { return std::clamp(int(std::floor((x - origin) / h)), 0, n - 1); }

}  // namespace

// One slab's part of a share: its triangles, by their corners' places in `whole` (the
// whole mesh's vertex numbers, in the order the triangles first use them) and `at`.
struct SlabShares::Gift {
    std::vector<Tri> triangles;
    std::vector<std::uint32_t> whole;
    std::vector<Vec3> at;
    void send(TileScheduler& on, int to) const {
        send_array(on, to, triangles.data(), triangles.size());
        send_array(on, to, whole.data(), whole.size());
        send_array(on, to, at.data(), at.size());
    }
    void take(TileScheduler& on, int from) {
        receive_array(on, from, triangles);
        receive_array(on, from, whole);
        receive_array(on, from, at);
    }
    // Taken from process `from`: its parts agree, and name vertices of the mesh.
    void check(int from, std::uint64_t vertices) const {
        const std::string who = "the check's share of the slab of process " + std::to_string(from);
        if (at.size() != whole.size()) throw Error(who + " is not whole");
        for (std::uint32_t v : whole)
            if (v >= vertices) throw Error(who + " names a vertex beyond the mesh's");
        for (const Tri& t : triangles)
            for (std::uint32_t c : t)
                if (c >= whole.size()) throw Error(who + " has a triangle whose corner it lacks");
    }
    std::size_t bytes() const {
        return triangles.size() * sizeof(Tri) + whole.size() * sizeof(std::uint32_t) + at.size() * sizeof(Vec3);
    }
};

// The slab's triangles with a corner near process p (by `near`, a slot a vertex: its own,
// then the foreign ones). slot: scratch, as many slots, all kNone (and so left).
namespace {

using SlabGift = SlabShares::Gift;

SlabGift gift_for(const SlabMesh& slabs, const std::vector<std::uint64_t>& near, std::size_t p,
                  std::vector<std::uint32_t>& slot) {
    const SlabPart& part = slabs.part();
    const std::size_t own = part.vertex_count;
    const auto slot_of = [&](std::uint32_t v) { return slabs.slot(v); };
    const std::uint64_t bit = std::uint64_t(1) << p;
    const auto gives = [&](const Tri& T) {
        return ((near[slot_of(T[0])] | near[slot_of(T[1])] | near[slot_of(T[2])]) & bit) != 0;
    };
    // Sized once (counted first): a closed surface has about half as many vertices.
    std::size_t count = 0;
    for (std::size_t t = 0; t < part.triangle_count; ++t) count += gives(part.triangles[t]);
    SlabGift gift;
    gift.triangles.reserve(count);
    gift.whole.reserve(count / 2 + 1024);
    gift.at.reserve(count / 2 + 1024);
    for (std::size_t t = 0; t < part.triangle_count; ++t) {
        const Tri& T = part.triangles[t];
        const std::size_t s[3] = {slot_of(T[0]), slot_of(T[1]), slot_of(T[2])};
        if (((near[s[0]] | near[s[1]] | near[s[2]]) & bit) == 0) continue;  // gives(T), its slots kept
        Tri mine;
        for (int c = 0; c < 3; ++c) {
            std::uint32_t& at = slot[s[c]];
            if (at == kNone) {
                at = std::uint32_t(gift.whole.size());
                gift.whole.push_back(T[std::size_t(c)]);
                gift.at.push_back(s[c] < own ? part.vertices[s[c]] : slabs.foreign_at()[s[c] - own]);
            }
            mine[std::size_t(c)] = at;
        }
        gift.triangles.push_back(mine);
    }
    for (std::uint32_t v : gift.whole) slot[slot_of(v)] = kNone;
    return gift;
}

// The gifts of every slab in turn as one share: the triangles in the whole mesh's order,
// each vertex numbered where it first comes (a vertex of a slab's border comes in the gifts
// of each slab using it: the first number it took stands).
ShareMesh merged(std::vector<SlabGift>& gifts, const SlabMesh& slabs, const CheckDeal& deal) {
    const std::vector<std::uint64_t>& starts = slabs.starts();
    const std::uint64_t all = starts.back();
    // The vertices a gift has of another slab than its own: only those can come twice.
    std::vector<std::uint32_t> border;
    for (std::size_t q = 0; q < gifts.size(); ++q)
        for (std::uint32_t v : gifts[q].whole)
            if (v < starts[q] || v >= starts[q + 1]) border.push_back(v);
    std::sort(border.begin(), border.end());
    border.erase(std::unique(border.begin(), border.end()), border.end());
    std::vector<std::uint64_t> is_border((all + 63) / 64, 0);
    for (std::uint32_t v : border) is_border[v / 64] |= std::uint64_t(1) << (v % 64);
    std::vector<std::uint32_t> border_number(border.size(), kNone);
    const auto me = std::uint8_t(slabs.rank());
    ShareMesh share;
    // Sized once: grown as they came, their fresh pages and copies were most of the merge
    // (a fault costs about 0.7 s a GB here).
    std::size_t vertices = 0, triangles = 0;
    for (const SlabGift& gift : gifts) vertices += gift.whole.size(), triangles += gift.triangles.size();
    share.vertices.reserve(vertices);
    share.triangles.reserve(triangles);
    std::vector<std::uint32_t> number;
    for (SlabGift& gift : gifts) {
        number.assign(gift.whole.size(), kNone);
        for (std::size_t e = 0; e < gift.whole.size(); ++e) {
            const std::uint32_t v = gift.whole[e];
            std::uint32_t* first = nullptr;
            if (is_border[v / 64] >> (v % 64) & 1) {
                first = &border_number[std::size_t(std::lower_bound(border.begin(), border.end(), v) - border.begin())];
                if (*first != kNone) {
                    number[e] = *first;
                    continue;
                }
            }
            const auto n = std::uint32_t(share.vertices.size());
            share.vertices.push_back(gift.at[e]);
            if (deal.walls_by[deal.tile_at(gift.at[e])] == me) {
                share.measured.push_back(n);
                share.measured_whole.push_back(v);
            }
            if (first) *first = n;
            number[e] = n;
        }
        for (const Tri& t : gift.triangles) share.triangles.push_back({number[t[0]], number[t[1]], number[t[2]]});
        gift = SlabGift();
    }
    return share;
}

}  // namespace

std::uint32_t CheckDeal::tile_at(const Vec3& x) const {
    const std::array<int, 3> n{grid.nx, grid.ny, grid.nz};
    std::array<int, 3> c;
    for (std::size_t a = 0; a < 3; ++a) c[a] = cell_of(x[a], grid.origin[a], grid.h, n[a]);
    return std::uint32_t(tile_holding(grid, core, c));
}

std::uint64_t CheckDeal::near(const Vec3& x) const {
    const std::array<int, 3> n{grid.nx, grid.ny, grid.nz};
    std::array<int, 3> lo, hi;
    for (std::size_t a = 0; a < 3; ++a) {
        lo[a] = cell_of(x[a] - widened, grid.origin[a], grid.h, n[a]) / core;
        hi[a] = cell_of(x[a] + widened, grid.origin[a], grid.h, n[a]) / core;
    }
    std::uint64_t bits = 0;
    for (int k = lo[2]; k <= hi[2]; ++k)
        for (int j = lo[1]; j <= hi[1]; ++j)
            for (int i = lo[0]; i <= hi[0]; ++i) bits |= measures_in[tile_holding(grid, core, {i * core, j * core, k * core})];
    return bits;
}

std::size_t CheckDeal::tiles() const {
    const auto across = [&](int cells) { return std::size_t((cells + core - 1) / std::max(1, core)); };
    return across(grid.nx) * across(grid.ny) * across(grid.nz);
}

void send_check_grid(TileScheduler& on, const CheckDeal& deal) {
    const Domain& g = deal.grid;
    const double figures[8] = {g.origin[0], g.origin[1], g.origin[2], g.h,
                               double(g.nx), double(g.ny), double(g.nz), double(deal.core)};
    for (int q = 1; q < on.processes(); ++q) send_array(on, q, figures, 8);
}

CheckDeal take_check_grid(TileScheduler& on) {
    double figures[8];
    receive_into(on, 0, figures, 8);
    CheckDeal deal;
    deal.grid.origin = {figures[0], figures[1], figures[2]};
    deal.grid.h = figures[3];
    deal.grid.nx = int(figures[4]);
    deal.grid.ny = int(figures[5]);
    deal.grid.nz = int(figures[6]);
    deal.core = int(figures[7]);
    if (deal.core < 1 || deal.grid.nx < 1 || deal.grid.ny < 1 || deal.grid.nz < 1)
        throw Error("the first process's grid of the check is not whole");
    return deal;
}

SlabTiles count_by_tiles(const SlabMesh& slabs, const CheckDeal& deal, TileScheduler& on) {
    const SlabPart& part = slabs.part();
    SlabTiles counted;
    counted.vertices.assign(deal.tiles(), 0);
    for (std::size_t v = 0; v < part.vertex_count; ++v) ++counted.vertices[deal.tile_at(part.vertices[v])];
    on.sum(counted.vertices);
    double longest = 0;
    for (std::size_t t = 0; t < part.triangle_count; ++t)
        for (std::size_t c = 0; c < 3; ++c) {
            const Vec3& a = slabs.position(part.triangles[t][c]);
            const Vec3& b = slabs.position(part.triangles[t][(c + 1) % 3]);
            for (std::size_t k = 0; k < 3; ++k) longest = std::max(longest, std::fabs(a[k] - b[k]));
        }
    std::vector<double> least{-longest};
    on.least(least);
    counted.longest_edge = -least[0];
    return counted;
}

void send_check_deal(TileScheduler& on, const CheckDeal& deal) {
    for (int q = 1; q < on.processes(); ++q) {
        send_array(on, q, &deal.widened, 1);
        send_array(on, q, deal.measures_in.data(), deal.measures_in.size());
        send_array(on, q, deal.walls_by.data(), deal.walls_by.size());
    }
}

void take_check_deal(TileScheduler& on, CheckDeal& deal) {
    receive_into(on, 0, &deal.widened, 1);
    receive_array(on, 0, deal.measures_in);
    receive_array(on, 0, deal.walls_by);
    if (deal.measures_in.size() != deal.tiles() || deal.walls_by.size() != deal.tiles())
        throw Error("the first process's deal of the check is not whole");
}

SlabShares::SlabShares(const SlabMesh& slabs, const CheckDeal& deal, TileScheduler& on)
    : slabs_(slabs), deal_(deal) {
    const std::size_t P = slabs.processes(), me = slabs.rank();
    const SlabPart& part = slabs.part();
    // Which processes each vertex the slab's triangles use is near: its own, then the foreign.
    const std::size_t own = part.vertex_count, foreign = slabs.foreign().size();
    std::vector<std::uint64_t> near(own + foreign);
#pragma omp parallel for schedule(static) if (std::ptrdiff_t(own + foreign) > kParallelItems)
    for (std::ptrdiff_t s = 0; s < std::ptrdiff_t(own + foreign); ++s)
        near[std::size_t(s)] = deal.near(std::size_t(s) < own ? part.vertices[s] : slabs.foreign_at()[std::size_t(s) - own]);
    // Every gift made before any is sent, and those taken checked once all are in, so that
    // the processes make and check theirs at once (made and checked in turn with the
    // exchange, the 50 M-point city block's two took 1.3 s over it).
    std::vector<std::uint32_t> slot(own + foreign, kNone);
    gifts_.resize(P);
    std::vector<SlabGift> giving(P);  // to the others; this one's own among gifts_
    for (std::size_t q = 0; q < P; ++q) (q == me ? gifts_[q] : giving[q]) = gift_for(slabs, near, q, slot);
    std::uint64_t sent = 0;
    exchange_pairwise(
        on,
        [&](int q) {
            giving[std::size_t(q)].send(on, q);
            sent += giving[std::size_t(q)].bytes();
            giving[std::size_t(q)] = SlabGift();
        },
        [&](int q) { gifts_[std::size_t(q)].take(on, q); });
    for (std::size_t q = 0; q < P; ++q)
        if (q != me) gifts_[q].check(int(q), slabs.starts().back());
    std::vector<std::uint64_t> total{sent};
    on.sum(total);
    bytes_ = total[0];
}

SlabShares::~SlabShares() = default;

ShareMesh SlabShares::mine() { return merged(gifts_, slabs_, deal_); }

ShareMesh share_from_slabs(const SlabMesh& slabs, const CheckDeal& deal, TileScheduler& on, std::uint64_t& bytes) {
    SlabShares shares(slabs, deal, on);
    bytes = shares.bytes();
    return shares.mine();
}

}  // namespace snvr::detail
