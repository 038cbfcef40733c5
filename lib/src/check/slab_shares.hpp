// The mesh of each process's share of the check (CheckShare's vertices, triangles and
// measured vertices), gathered from the slabs the processes hold, so that the first need
// not cut every share out of the whole mesh: each slab gives every other process its own
// triangles with a corner near a tile where that process measures, in the whole mesh's
// order; the process numbers their vertices as they first come. The share is the one the
// whole mesh would give, to the bit: the same triangles in the same order, the same vertex
// numbers, so that its walls and depths are the whole's.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "check/slab_mesh.hpp"
#include "snvr/domain.hpp"
#include "snvr/geometry.hpp"
#include "snvr/tiles.hpp"

namespace snvr::detail {

// The first's word on who measures where, by tiles of the grid.
struct CheckDeal {
    Domain grid;    // its origin, voxel and cells
    int core = 0;   // a tile's core, in cells
    // A triangle with a corner this near a tile (along every axis) where a process
    // measures is in that process's share.
    double widened = 0;
    std::vector<std::uint64_t> measures_in;  // each tile's: bit p where process p measures there
    std::vector<std::uint8_t> walls_by;      // each tile's: the process measuring its vertices' walls
    // The tile whose core holds x (clamped to the grid).
    std::uint32_t tile_at(const Vec3& x) const;
    // Bit p: process p measures in a tile within `widened` of x.
    std::uint64_t near(const Vec3& x) const;
    std::size_t tiles() const;
};

// The deal from the first to every other process, in two steps: its grid first (the
// others take it as a deal with no tiles yet), then, once dealt, the tiles' part.
void send_check_grid(TileScheduler& on, const CheckDeal& deal);
CheckDeal take_check_grid(TileScheduler& on);
void send_check_deal(TileScheduler& on, const CheckDeal& deal);
void take_check_deal(TileScheduler& on, CheckDeal& deal);

// What the first deals by, counted by the slabs (every process at once): the whole mesh's
// vertices in each tile, and its longest edge (along an axis).
struct SlabTiles {
    std::vector<std::uint64_t> vertices;
    double longest_edge = 0;
};
SlabTiles count_by_tiles(const SlabMesh& slabs, const CheckDeal& deal, TileScheduler& on);

// A share's mesh, and its measured vertices' numbers in the whole mesh (for the walls back).
struct ShareMesh {
    std::vector<Vec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<std::uint32_t> measured, measured_whole;
};

// In two steps, so that a process can give the others what they wait for between them:
// made, every process (all at once) has given every other its slab's triangles near it and
// taken theirs; mine() then merges this process's share (once).
class SlabShares {
public:
    SlabShares(const SlabMesh& slabs, const CheckDeal& deal, TileScheduler& on);
    ~SlabShares();
    std::uint64_t bytes() const { return bytes_; }  // what all sent, summed
    ShareMesh mine();

    struct Gift;  // one slab's part of a share (slab_shares.cpp)

private:
    const SlabMesh& slabs_;
    const CheckDeal& deal_;
    std::vector<Gift> gifts_;
    std::uint64_t bytes_ = 0;
};
// Both steps at once. `bytes`: what all sent, summed.
ShareMesh share_from_slabs(const SlabMesh& slabs, const CheckDeal& deal, TileScheduler& on, std::uint64_t& bytes);

}  // namespace snvr::detail
