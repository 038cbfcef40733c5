// snvr-bench's points section (issue 21): how the cost of a run grows with the number
// of points at a fixed grid. The sampler's shapes at growing density and the real
// scans, each reconstructed by snvr-cl at each grid as a user runs it, beside the
// plain distance + marching cubes peer and the OpenVDB peer at the same voxel and
// offset. Every program runs as a process of its own: its seconds and peak memory are
// taken from outside (wait4), ours per stage from its --report. Runs under 10 s are
// repeated (--repeat) and the median kept: they are the noisiest, and the smallest
// clouds are the base of the cost per extra point.
#pragma once
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "record.hpp"

namespace snvr::bench {

struct PointsOptions {
    std::vector<std::string> clouds;  // families (noisy-sphere, torus, helicoid) and scans (bunny, ...); empty: all
    double max_points = 7e6;          // clouds above this many points are skipped (the 24.6 M sphere by default)
    std::vector<int> grids{256, 512};  // cells on the longest axis (snvr-cl --resolution)
    std::string scratch;  // generated clouds and every program's outputs, removed as the section goes
    std::string device;   // snvr-cl --device; empty: its own choice
    std::string data;     // the scans' directory
    int repeat = 3;       // runs of a program whose first run is short (median kept)
    bool quick = false;   // two tiny spheres at 64 cells, for CI
};

// The programs the section runs; an empty path is a program this build lacks.
struct PointsPrograms {
    std::string snvr_cl, distance_mc_peer, openvdb_peer;
};

// Runs the section, handing each row (a cloud at a grid, every program) to `keep` as
// soon as it is measured.
void run_points(const PointsOptions& options, const PointsPrograms& programs, const std::function<void(const Record&)>& keep);

}  // namespace snvr::bench
