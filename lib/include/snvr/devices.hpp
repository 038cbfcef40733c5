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

}  // namespace snvr
