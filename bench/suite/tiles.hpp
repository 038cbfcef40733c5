// snvr-bench's tiles section (issue 35): a run cut into tiles (snvr-cl --tile-cells)
// against the same run whole, both as a user runs them, in turn: wall and CPU seconds and
// peak memory from outside (wait4), the stages and the tiles from --report, and how far
// the tiled shell is from the whole one (vertex_distance, in voxels), its pieces and genus.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "record.hpp"

namespace snvr::bench {

struct TilesOptions {
    // CLOUD@CELLS/TILE: a scan of the data folder (bunny) or a sampler's shape with its
    // spacing (lidar, noisy-sphere-0.00025); empty: bunny@256/128, bunny@512/128, lidar@256/64.
    std::vector<std::string> cases;
    std::string data, scratch, device;
    int repeat = 3;       // pairs run, whole and tiled in turn (the median ratio kept)
    bool quick = false;   // bunny@128/64, one pair
};

void run_tiles(const TilesOptions& options, const std::string& snvr_cl, const std::function<void(const Record&)>& keep);

// The section's table ("" when no record is of it).
std::string tiles_markdown(const std::vector<Record>& records);

}  // namespace snvr::bench
