#include "grid/brick_tiling.hpp"

#include <algorithm>

namespace snvr {

BrickTiling BrickTiling::of(int nx, int ny, int nz) {
    BrickTiling t;
    t.nx = nx;
    t.ny = ny;
    t.nz = nz;
    t.bx = (nx + kBrick - 1) / kBrick;
    t.by = (ny + kBrick - 1) / kBrick;
    t.bz = (nz + kBrick - 1) / kBrick;
    return t;
}

CellRange BrickTiling::range(std::uint32_t brick) const {
    const int bi = int(brick % std::uint32_t(bx));
    const int bj = int(brick / std::uint32_t(bx) % std::uint32_t(by));
    const int bk = int(brick / (std::uint32_t(bx) * std::uint32_t(by)));
    return {bi * kBrick, std::min(nx, (bi + 1) * kBrick), bj * kBrick, std::min(ny, (bj + 1) * kBrick),
            bk * kBrick, std::min(nz, (bk + 1) * kBrick)};
}

}  // namespace snvr
