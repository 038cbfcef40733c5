// What can run the solver on this machine.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace snvr {

struct DeviceInfo {
    std::string id;           // what --device accepts to pick it, e.g. "openmp"
    std::string name;         // human-readable
    std::string kind;         // "cpu (OpenMP)", "gpu", ...
    int compute_units = 0;    // threads or compute units
    std::size_t memory_bytes = 0;
    bool fp64 = true;
    bool available = true;
    std::string note;         // e.g. why it is unavailable
};

std::vector<DeviceInfo> list_devices();

// Readies a device for reconstruct(): builds the OpenCL program (once per device and
// precision in a process) and runs every kernel once on a small sphere, so that later
// runs do not pay the compilation. For benchmarks and long-lived services; a plain
// reconstruct() does the same on its own the first time. Takes the same device names
// as Parameters::device; single: the float program instead of the double one.
// Throws what reconstruct() would throw for that device.
void warmup(const std::string& device = "auto", bool single = false);

}  // namespace snvr
