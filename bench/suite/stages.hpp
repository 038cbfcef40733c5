// snvr-bench's stages section (issue 36): each stage of a whole run of snvr-cl by the unit
// of work it grows with (a band cell, a band cell a step, a triangle: its --report's
// per_unit) beside its floor, the bytes it must touch at this machine's stream rate (an
// OpenMP triad taken at the section's start), and the whole process beside the OpenVDB
// peer's at the same voxel and offset, the two in turn.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "record.hpp"

namespace snvr::bench {

struct StagesOptions {
    std::vector<std::string> cases;  // SCAN@CELLS, a scan of the data folder; empty: bunny@256, bunny@1024
    std::string data, scratch, device;
    int repeat = 2;       // pairs, ours then the peer's
    bool quick = false;   // bunny@96, one pair
};

void run_stages(const StagesOptions& options, const std::string& snvr_cl, const std::string& openvdb_peer,
                const std::function<void(const Record&)>& keep);

// The section's tables ("" when no record is of it).
std::string stages_markdown(const std::vector<Record>& records);

}  // namespace snvr::bench
