// The kernels' OpenCL C, embedded at build time (cmake/embed_kernels.cmake).
#pragma once
#include <vector>

namespace snvr {

struct KernelSource {
    const char* file;  // kernels/<file>
    const char* text;
};

// common.cl first, then one file per operation.
const std::vector<KernelSource>& kernel_sources();

}  // namespace snvr
