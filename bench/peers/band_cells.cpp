#include "band_cells.hpp"

#include <algorithm>
#include <cmath>

namespace snvr::peers {

namespace {

using Mask = BandCells::Mask;
constexpr std::uint32_t kNone = BandCells::kNone;

struct Cell {
    int i, j, k;
};

Cell cell_of(const Vec3& p, const Domain& g) {
    const auto axis = [&](int a, int n) { return int(std::clamp(std::floor((p[a] - g.origin[a]) / g.h), 0.0, double(n - 1))); };
    return {axis(0, g.nx), axis(1, g.ny), axis(2, g.nz)};
}

// A cell's bit in its brick's mask: word z, byte y, bit x.
int bit_of(const Cell& c) { return c.i % 8 + 8 * (c.j % 8 + 8 * (c.k % 8)); }

// The rows of a ball of `radius` cells around a cell: dy and dz away, the cells
// within half_width along x.
struct DiscRow {
    int dy, dz, half_width;
};

std::vector<DiscRow> ball_rows(double radius) {
    const int r = int(std::floor(radius));
    std::vector<DiscRow> rows;
    for (int dz = -r; dz <= r; ++dz)
        for (int dy = -r; dy <= r; ++dy) {
            const double left = radius * radius - double(dy * dy + dz * dz);
            if (left >= 0) rows.push_back({dy, dz, int(std::floor(std::sqrt(left)))});
        }
    return rows;
}

// Of the 8 cells of a brick row that starts `offset` cells after the row whose cells
// `row` marks, those within half_width of a marked one.
std::uint8_t dilated_slice(unsigned row, int half_width, int offset) {
    unsigned out = 0;
    for (unsigned bits = row; bits; bits &= bits - 1) {
        const int x = __builtin_ctz(bits);
        const int lo = std::max(0, x - half_width - offset), hi = std::min(7, x + half_width - offset);
        if (lo <= hi) out |= ((2u << (hi - lo)) - 1) << lo;
    }
    return std::uint8_t(out);
}

}  // namespace

std::size_t BandCells::cells() const {
    std::size_t n = 0;
    for (const Mask& m : masks)
        for (std::uint64_t w : m) n += std::size_t(__builtin_popcountll(w));
    return n;
}

BandCells band_cells(const PointSet& points, const Domain& g, double reach) {
    BandCells band;
    band.bricks_x = (g.nx + 7) / 8;
    band.bricks_y = (g.ny + 7) / 8;
    band.bricks_z = (g.nz + 7) / 8;
    const std::size_t bricks = std::size_t(band.bricks_x) * std::size_t(band.bricks_y) * std::size_t(band.bricks_z);
    const auto brick_of = [&](int ib, int jb, int kb) {
        return std::size_t(ib) + std::size_t(band.bricks_x) * (std::size_t(jb) + std::size_t(band.bricks_y) * std::size_t(kb));
    };
    const std::int64_t count = std::int64_t(points.size());

    // The bricks that hold points (seeds), then the cells of theirs that do. Two passes
    // over the points, so that only the seed bricks get masks.
    std::vector<std::uint8_t> has_points(bricks, 0);
#pragma omp parallel for schedule(static)
    for (std::int64_t n = 0; n < count; ++n) {
        const Cell c = cell_of(points[std::size_t(n)], g);
        const std::size_t b = brick_of(c.i / 8, c.j / 8, c.k / 8);
#pragma omp atomic write
        has_points[b] = 1;
    }
    std::vector<std::uint32_t> seed_slot(bricks, kNone), seed_brick;
    for (std::size_t b = 0; b < bricks; ++b)
        if (has_points[b]) {
            seed_slot[b] = std::uint32_t(seed_brick.size());
            seed_brick.push_back(std::uint32_t(b));
        }
    std::vector<Mask> seeds(seed_brick.size(), Mask{});
#pragma omp parallel for schedule(static)
    for (std::int64_t n = 0; n < count; ++n) {
        const Cell c = cell_of(points[std::size_t(n)], g);
        const int bit = bit_of(c);
        std::uint64_t& word = seeds[seed_slot[brick_of(c.i / 8, c.j / 8, c.k / 8)]][bit >> 6];
        const std::uint64_t flag = std::uint64_t(1) << (bit & 63);
        std::uint64_t now;
#pragma omp atomic read
        now = word;
        if (now & flag) continue;  // dense clouds put dozens of points in a cell: read before writing
#pragma omp atomic
        word |= flag;
    }

    // A cell is reached from a seed cell whose centre is within the reach plus half a
    // cell's diagonal (where in its cell the point sits is no longer known).
    const double radius = reach / g.h + std::sqrt(3.0) / 2;
    const int brick_reach = (int(std::floor(radius)) + 7) / 8;
    band.slot.assign(bricks, kNone);
    std::vector<std::uint8_t> touched(bricks, 0);
    for (const std::uint32_t b : seed_brick) {
        const int ib = int(b % std::uint32_t(band.bricks_x)), jb = int(b / std::uint32_t(band.bricks_x) % std::uint32_t(band.bricks_y)),
                  kb = int(b / std::uint32_t(band.bricks_x) / std::uint32_t(band.bricks_y));
        for (int k = std::max(0, kb - brick_reach); k <= std::min(band.bricks_z - 1, kb + brick_reach); ++k)
            for (int j = std::max(0, jb - brick_reach); j <= std::min(band.bricks_y - 1, jb + brick_reach); ++j)
                for (int i = std::max(0, ib - brick_reach); i <= std::min(band.bricks_x - 1, ib + brick_reach); ++i)
                    touched[brick_of(i, j, k)] = 1;
    }
    std::vector<Mask> reached;
    std::vector<std::uint32_t> reached_slot(bricks, kNone);
    for (std::size_t b = 0; b < bricks; ++b)
        if (touched[b]) reached_slot[b] = std::uint32_t(reached.size()), reached.push_back(Mask{});

    // Each seed row spreads over the rows of the ball around it, a brick row (one
    // byte of a mask) at a time.
    const std::vector<DiscRow> ball = ball_rows(radius);
#pragma omp parallel for schedule(dynamic, 4)
    for (std::int64_t s = 0; s < std::int64_t(seed_brick.size()); ++s) {
        const std::uint32_t b = seed_brick[std::size_t(s)];
        const int ib = int(b % std::uint32_t(band.bricks_x)), jb = int(b / std::uint32_t(band.bricks_x) % std::uint32_t(band.bricks_y)),
                  kb = int(b / std::uint32_t(band.bricks_x) / std::uint32_t(band.bricks_y));
        for (int lk = 0; lk < 8; ++lk)
            for (int lj = 0; lj < 8; ++lj) {
                const unsigned row = unsigned(seeds[std::size_t(s)][std::size_t(lk)] >> (8 * lj)) & 0xffu;
                if (!row) continue;
                const int first = __builtin_ctz(row), last = 31 - __builtin_clz(row);
                for (const DiscRow& d : ball) {
                    const int j = jb * 8 + lj + d.dy, k = kb * 8 + lk + d.dz;
                    if (j < 0 || j >= g.ny || k < 0 || k >= g.nz) continue;
                    const int x_lo = std::max(0, ib * 8 + first - d.half_width), x_hi = std::min(g.nx - 1, ib * 8 + last + d.half_width);
                    for (int tib = x_lo / 8; tib <= x_hi / 8; ++tib) {
                        unsigned bits = dilated_slice(row, d.half_width, 8 * (tib - ib));
                        if (tib * 8 + 8 > g.nx) bits &= (1u << (g.nx - tib * 8)) - 1;  // cells beyond the grid
                        if (!bits) continue;
                        std::uint64_t& word = reached[reached_slot[brick_of(tib, j / 8, k / 8)]][std::size_t(k % 8)];
                        const std::uint64_t add = std::uint64_t(bits) << (8 * (j % 8));
#pragma omp atomic
                        word |= add;
                    }
                }
            }
    }

    // Only the bricks the ball reached keep a slot.
    for (std::size_t b = 0; b < bricks; ++b) {
        if (reached_slot[b] == kNone) continue;
        const Mask& m = reached[reached_slot[b]];
        if (std::all_of(m.begin(), m.end(), [](std::uint64_t w) { return w == 0; })) continue;
        band.slot[b] = std::uint32_t(band.masks.size());
        band.brick.push_back(std::uint32_t(b));
        band.masks.push_back(m);
    }
    return band;
}

}  // namespace snvr::peers
