// The thin OpenCL runtime: device discovery and choice, context and in-order queue, the
// program built once per context (with the scalar type as a build option), and errors
// that name the call and the OpenCL error. Uses the Khronos C++ bindings with their
// exceptions on; `guarded` turns them into snvr errors at the backend's edge.
#pragma once
#define CL_HPP_TARGET_OPENCL_VERSION 120
#define CL_HPP_MINIMUM_OPENCL_VERSION 120
#define CL_HPP_ENABLE_EXCEPTIONS
#include <CL/opencl.hpp>

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "snvr/error.hpp"

namespace snvr::opencl {

// Name of an OpenCL error code, e.g. "CL_OUT_OF_RESOURCES (-5)".
std::string error_name(cl_int code);

// Runs f; an OpenCL failure becomes a ResourceError naming `what`, the call and the code.
template <class F>
auto guarded(const char* what, F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const cl::Error& e) {
        throw ResourceError(std::string("OpenCL ") + what + ": " + e.what() + " failed with " + error_name(e.err()));
    }
}

struct DeviceEntry {
    int platform = 0, index = 0;  // as in --device opencl:P:D
    std::string platform_name, name, vendor, version;
    cl::Device device;
    bool gpu = false, fp64 = false;
    std::size_t memory = 0, max_alloc = 0;
    std::size_t max_group = 0;     // the largest work-group along the first dimension
    std::size_t local_memory = 0;  // bytes of local memory a work-group may use
    int compute_units = 0;
};

// Why this process should not load an OpenCL runtime at all (its memory or file-size
// limits are too low for one to start and build kernels without ending the process),
// or "" when it may.
std::string limits_block_runtime();

// Every device of every platform; empty when there is no OpenCL platform at all, or
// when limits_block_runtime() says not to look.
std::vector<DeviceEntry> devices();

// The device a --device spec names: "opencl" (first GPU, else first device), "opencl:P:D",
// or a substring of the device or platform name. Throws ParameterError when none matches.
DeviceEntry choose_device(const std::string& spec);

// How many times this process has built the kernels' program (the cache's misses).
std::size_t program_builds();

// A queue of its own, and the context and program for one precision on one device.
// The context and the built program are made once per device and build options in a
// process and shared by every Runtime after (building costs 0.2-0.5 s under PoCL).
class Runtime {
public:
    // real_type: "double" or "float"; options: more build options (the work-group sizes).
    // Throws ResourceError with the build log on failure, ParameterError when double is
    // asked of a device without fp64.
    Runtime(DeviceEntry device, const std::string& real_type, const std::string& options = "");

    const DeviceEntry& device() const { return device_; }
    cl::Context& context() { return context_; }
    cl::CommandQueue& queue() { return queue_; }
    cl::Kernel kernel(const char* name) const;
    // The largest work-group this device runs `kernel` in (its registers may allow less
    // than the device's limit).
    std::size_t kernel_group_limit(const cl::Kernel& kernel) const;
    bool double_accumulator() const { return device_.fp64; }

    // A device buffer of `bytes`, checked against the device's allocation limit first.
    cl::Buffer buffer(std::size_t bytes, const char* what);

private:
    DeviceEntry device_;
    cl::Context context_;  // shared through the program cache
    cl::CommandQueue queue_;
    cl::Program program_;
};

}  // namespace snvr::opencl
