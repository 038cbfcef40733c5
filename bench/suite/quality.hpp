// snvr-bench's quality section: real scans and hard synthetic inputs reconstructed by
// libsnvr and by the OpenVDB peer at the same voxel and offset, both judged by the
// same measure_quality call, with PNG previews where the renderer is built.
#pragma once
#include <string>
#include <vector>

#include "record.hpp"
#include "snvr/shapes.hpp"

namespace snvr::bench {

// One input. Lengths are in voxels of the reference grid (`reference` cells on the
// points' longest axis), so that the offset stays fixed in world units at every
// resolution: a scan's 2.5 voxels at 256 are 5 voxels at 512.
struct QualityCase {
    std::string name;      // the row's label: a scan's file stem or a shape's name
    std::string file;      // a scan in the data directory, or
    std::string shape;     // a shapes::by_name shape (with its exact distance)
    double spacing = 1;    // shapes: sample spacing, in reference voxels
    double offset = 2.5;   // l, in reference voxels (sheets: see offset_from_gap)
    bool offset_from_gap = false;  // l = a third of the sheets' gap (their z extent)
    std::string why;       // how the offset and spacing were chosen, for the record
};

struct QualityRun {
    QualityCase c;
    int resolution = 256;  // cells on the longest axis of the points
    int reference = 256;   // the grid the case's lengths are given in
    std::string tool;      // "snvr" or "openvdb"
    std::string device;    // ours: Parameters::device
    std::string png_dir;   // empty: no previews
    int png_size = 1024;
};

// The scans in `data_dir` (bunny, igea, armadillo first; with `all_scans` every
// .ply there) and the synthetic cases.
std::vector<QualityCase> quality_cases(const std::string& data_dir, bool all_scans);

// Whether this build has the OpenVDB peer.
bool quality_has_openvdb();

// Runs one tool on one case (inside a child process): reconstruction, meshing,
// measure_quality and, with png_dir set, a full view and a 3x zoom.
Record measure_quality_run(const QualityRun& run, const std::string& data_dir);

}  // namespace snvr::bench
