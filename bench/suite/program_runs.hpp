// The programs the benchmarks time as whole processes, as a user runs them: snvr-cl
// (its stages, and each stage's cost a unit of work, from its --report) and the peers at
// the voxel and offset it chose. Each figure is set in a Record under the program's name.
#pragma once
#include <optional>
#include <string>

#include "record.hpp"
#include "spawn.hpp"

namespace snvr::bench {

// What a run of ours gives the peers: the voxel and offset, in the input's units.
struct Lengths {
    double voxel = 0, offset = 0;
};

// A number as the programs' options take it, to the last bit.
std::string exact(double v);

// snvr-cl at one grid (`device`: its --device, empty for its own choice): process seconds,
// CPU seconds and peak memory, the stages' seconds ("snvr_<stage>_s") and, for each stage
// its report prices by a unit, the nanoseconds a unit and the bytes it must touch
// ("snvr_<stage>_ns", "snvr_<stage>_floor_bytes", "snvr_<stage>_units"), and where the
// check's walls were cast ("snvr_walls_on"). False when it failed (the record says why).
bool measure_ours(const std::string& snvr_cl, const std::string& device, const std::string& cloud, int grid,
                  const std::string& dir, Record& r, Lengths& lengths);

// A peer at our voxel and offset (`name` prefixes its figures: process seconds, CPU
// seconds, peak memory, or the error); the run when it succeeded.
std::optional<ProgramRun> run_peer(const std::string& name, const std::string& program, const std::string& cloud,
                                   const Lengths& l, const std::string& dir, Record& r);

// The OpenVDB peer (`program` empty: not built, which the record says), its triangles.
void measure_openvdb_peer(const std::string& program, const std::string& cloud, const Lengths& l, const std::string& dir,
                          Record& r);

}  // namespace snvr::bench
