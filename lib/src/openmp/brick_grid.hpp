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

#include "hierarchy.hpp"

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

}  // namespace snvr
