// Sparse brick-major storage. Each 8^3 brick's cells are contiguous (x fastest inside
// the brick). Only active bricks get storage of their own; every inactive brick points
// at one of three shared constant bricks (0, +1, -1), which is what its cells hold: g is
// 0 there, so nothing ever changes them, and the distance is 1-Lipschitz, so a level-0
// brick without a band cell lies wholly inside (+1) or wholly outside (-1) the shell.
//
// Why bricks: walking the active bricks of a flat x-fastest array touched one 64-byte
// row per 2 KB page and copied at 3.8 GB/s on the bunny at 256^3; contiguous 4 KB
// bricks copy at 20-30 GB/s. Why sparse: memory follows the band, not the box.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "solver/hierarchy.hpp"

namespace snvr {

constexpr int kBrickCells = kBrick * kBrick * kBrick;

// Shared constant bricks at the start of every field's storage.
enum ConstantSlot : std::uint32_t { kZeroSlot = 0, kPlusSlot = 1, kMinusSlot = 2, kConstantSlots = 3 };

struct BrickGrid {
    int nx = 0, ny = 0, nz = 0, bx = 0, by = 0, bz = 0;
    std::vector<std::uint32_t> slot;  // per brick: where its cells are stored

    // Active bricks get slots kConstantSlots, kConstantSlots + 1, ... in list order;
    // the others start at the zero brick.
    explicit BrickGrid(const Level& lv) : nx(lv.nx), ny(lv.ny), nz(lv.nz), bx(lv.bx), by(lv.by), bz(lv.bz) {
        slot.assign(lv.brick_count(), kZeroSlot);
        for (std::size_t t = 0; t < lv.bricks.size(); ++t) slot[lv.bricks[t]] = std::uint32_t(kConstantSlots + t);
    }

    std::size_t storage() const {
        std::size_t active = 0;
        for (std::uint32_t s : slot) active += s >= kConstantSlots;
        return (active + kConstantSlots) * kBrickCells;
    }
    std::size_t base(std::uint32_t brick) const { return std::size_t(slot[brick]) * kBrickCells; }
    std::uint32_t brick_of(int i, int j, int k) const {
        return std::uint32_t(i / kBrick) + std::uint32_t(bx) * (std::uint32_t(j / kBrick) + std::uint32_t(by) * std::uint32_t(k / kBrick));
    }
    static int local(int li, int lj, int lk) { return li + kBrick * (lj + kBrick * lk); }
    std::size_t at(int i, int j, int k) const {
        return base(brick_of(i, j, k)) + std::size_t(local(i % kBrick, j % kBrick, k % kBrick));
    }
};

// Storage positions of cells given by x-fastest index.
inline std::vector<std::uint32_t> storage_positions(const BrickGrid& bg, const std::vector<std::uint32_t>& cells) {
    std::vector<std::uint32_t> at;
    at.reserve(cells.size());
    for (std::uint32_t n : cells) {
        const int i = int(n % std::uint32_t(bg.nx)), j = int(n / std::uint32_t(bg.nx) % std::uint32_t(bg.ny)),
                  k = int(n / (std::uint32_t(bg.nx) * std::uint32_t(bg.ny)));
        at.push_back(std::uint32_t(bg.at(i, j, k)));
    }
    return at;
}

// Dense x-fastest field <-> brick storage. Packing writes the in-grid cells of active
// bricks only; unpacking reads every cell (inactive ones from their constant brick).
template <class Real>
void pack_active(const BrickGrid& bg, const Level& lv, const Real* dense, Real* storage) {
    for (std::uint32_t b : lv.bricks) {
        const CellRange r = lv.range(b);
        for (int k = r.k0; k < r.k1; ++k)
            for (int j = r.j0; j < r.j1; ++j)
                for (int i = r.i0; i < r.i1; ++i)
                    storage[bg.at(i, j, k)] = dense[std::size_t(i) + std::size_t(lv.nx) * (std::size_t(j) + std::size_t(lv.ny) * std::size_t(k))];
    }
}

template <class Real>
void unpack(const BrickGrid& bg, const Real* storage, Real* dense) {
#ifdef _OPENMP  // also included where OpenMP is off (tests): serial there
#pragma omp parallel for schedule(static)
#endif
    for (int k = 0; k < bg.nz; ++k)
        for (int j = 0; j < bg.ny; ++j)
            for (int i = 0; i < bg.nx; ++i)
                dense[std::size_t(i) + std::size_t(bg.nx) * (std::size_t(j) + std::size_t(bg.ny) * std::size_t(k))] = storage[bg.at(i, j, k)];
}

}  // namespace snvr
