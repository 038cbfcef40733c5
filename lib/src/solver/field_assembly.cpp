// FieldAssembly (field_assembly.hpp).
#include "solver/field_assembly.hpp"

#include <algorithm>

#include "solver/brick_grid.hpp"

namespace snvr {

namespace {

template <class Real>
const std::vector<Real>& stored_of(const Field& f);
template <>
const std::vector<double>& stored_of<double>(const Field& f) {
    return f.stored_f64();
}
template <>
const std::vector<float>& stored_of<float>(const Field& f) {
    return f.stored_f32();
}

}  // namespace

template <class Real>
FieldAssembly<Real>::FieldAssembly(const Domain& whole) : whole_(whole) {
    const auto bricks = [](int n) { return std::size_t((n + kBrick - 1) / kBrick); };
    table_.assign(bricks(whole.nx) * bricks(whole.ny) * bricks(whole.nz), kMinusSlot);
    stored_.assign(std::size_t(kConstantSlots) * kBrickCells, Real(0));
    std::fill(stored_.begin() + std::ptrdiff_t(kPlusSlot) * kBrickCells,
              stored_.begin() + std::ptrdiff_t(kPlusSlot + 1) * kBrickCells, Real(1));
    std::fill(stored_.begin() + std::ptrdiff_t(kMinusSlot) * kBrickCells,
              stored_.begin() + std::ptrdiff_t(kMinusSlot + 1) * kBrickCells, Real(-1));
}

template <class Real>
void FieldAssembly<Real>::place(const Field& tile_field, const Tile& tile) {
    const std::vector<Real>& from = stored_of<Real>(tile_field);
    const std::vector<std::uint32_t>& tile_table = tile_field.brick_table();
    const int bx = (whole_.nx + kBrick - 1) / kBrick, by = (whole_.ny + kBrick - 1) / kBrick;
    const int tx = tile_field.bricks_x(), ty = tile_field.bricks_y();
    for (int k = tile.core_lo[2] / kBrick; k * kBrick < tile.core_hi[2]; ++k)
        for (int j = tile.core_lo[1] / kBrick; j * kBrick < tile.core_hi[1]; ++j)
            for (int i = tile.core_lo[0] / kBrick; i * kBrick < tile.core_hi[0]; ++i) {
                const int ti = i - tile.lo[0] / kBrick, tj = j - tile.lo[1] / kBrick, tk = k - tile.lo[2] / kBrick;
                const std::uint32_t slot = tile_table[std::size_t(ti) + std::size_t(tx) * (std::size_t(tj) + std::size_t(ty) * std::size_t(tk))];
                std::uint32_t& to = table_[std::size_t(i) + std::size_t(bx) * (std::size_t(j) + std::size_t(by) * std::size_t(k))];
                if (slot < kConstantSlots) {
                    to = slot;  // a brick placed before and now constant keeps its storage unused
                    continue;
                }
                const auto first = from.begin() + std::ptrdiff_t(slot) * kBrickCells;
                if (to < kConstantSlots) {
                    to = std::uint32_t(stored_.size() / kBrickCells);
                    stored_.insert(stored_.end(), first, first + kBrickCells);
                } else {  // placed again (a tile run again): in the same storage
                    std::copy(first, first + kBrickCells, stored_.begin() + std::ptrdiff_t(to) * kBrickCells);
                }
            }
}

template <class Real>
Field FieldAssembly<Real>::take() {
    return Field::from_bricks(whole_.nx, whole_.ny, whole_.nz, std::move(table_), std::move(stored_));
}

template class FieldAssembly<double>;
template class FieldAssembly<float>;

}  // namespace snvr
