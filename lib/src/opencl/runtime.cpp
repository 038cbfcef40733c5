#include "opencl/runtime.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>
#include <tuple>

#include "opencl/kernel_sources.hpp"

namespace snvr::opencl {

std::string error_name(cl_int code) {
    static const std::pair<cl_int, const char*> names[] = {
        {CL_DEVICE_NOT_FOUND, "CL_DEVICE_NOT_FOUND"},
        {CL_DEVICE_NOT_AVAILABLE, "CL_DEVICE_NOT_AVAILABLE"},
        {CL_COMPILER_NOT_AVAILABLE, "CL_COMPILER_NOT_AVAILABLE"},
        {CL_MEM_OBJECT_ALLOCATION_FAILURE, "CL_MEM_OBJECT_ALLOCATION_FAILURE"},
        {CL_OUT_OF_RESOURCES, "CL_OUT_OF_RESOURCES"},
        {CL_OUT_OF_HOST_MEMORY, "CL_OUT_OF_HOST_MEMORY"},
        {CL_BUILD_PROGRAM_FAILURE, "CL_BUILD_PROGRAM_FAILURE"},
        {CL_INVALID_VALUE, "CL_INVALID_VALUE"},
        {CL_INVALID_PLATFORM, "CL_INVALID_PLATFORM"},
        {CL_INVALID_DEVICE, "CL_INVALID_DEVICE"},
        {CL_INVALID_CONTEXT, "CL_INVALID_CONTEXT"},
        {CL_INVALID_COMMAND_QUEUE, "CL_INVALID_COMMAND_QUEUE"},
        {CL_INVALID_MEM_OBJECT, "CL_INVALID_MEM_OBJECT"},
        {CL_INVALID_BUILD_OPTIONS, "CL_INVALID_BUILD_OPTIONS"},
        {CL_INVALID_PROGRAM, "CL_INVALID_PROGRAM"},
        {CL_INVALID_PROGRAM_EXECUTABLE, "CL_INVALID_PROGRAM_EXECUTABLE"},
        {CL_INVALID_KERNEL_NAME, "CL_INVALID_KERNEL_NAME"},
        {CL_INVALID_KERNEL, "CL_INVALID_KERNEL"},
        {CL_INVALID_ARG_INDEX, "CL_INVALID_ARG_INDEX"},
        {CL_INVALID_ARG_VALUE, "CL_INVALID_ARG_VALUE"},
        {CL_INVALID_ARG_SIZE, "CL_INVALID_ARG_SIZE"},
        {CL_INVALID_KERNEL_ARGS, "CL_INVALID_KERNEL_ARGS"},
        {CL_INVALID_WORK_GROUP_SIZE, "CL_INVALID_WORK_GROUP_SIZE"},
        {CL_INVALID_WORK_ITEM_SIZE, "CL_INVALID_WORK_ITEM_SIZE"},
        {CL_INVALID_GLOBAL_WORK_SIZE, "CL_INVALID_GLOBAL_WORK_SIZE"},
        {CL_INVALID_BUFFER_SIZE, "CL_INVALID_BUFFER_SIZE"},
        {CL_INVALID_OPERATION, "CL_INVALID_OPERATION"},
        {-1001, "CL_PLATFORM_NOT_FOUND_KHR"},
    };
    for (const auto& [c, n] : names)
        if (c == code) return std::string(n) + " (" + std::to_string(code) + ")";
    return "OpenCL error " + std::to_string(code);
}

std::string limits_block_runtime() {
    // An OpenCL runtime maps large libraries, sizes its device memory from the process's
    // limits and writes its compiled kernels to files: PoCL aborts the process (SIGABRT)
    // when the data limit leaves it under about 140 MB, cannot load under an address
    // space of 400 MB, and its compiler exits the process when a file-size limit stops
    // a kernel file.
    constexpr rlim_t kLeastBytes = rlim_t(1) << 30;
    for (const auto& [resource, what] : {std::pair{RLIMIT_DATA, "data size (ulimit -d)"},
                                         std::pair{RLIMIT_AS, "address space (ulimit -v)"},
                                         std::pair{RLIMIT_FSIZE, "file size (ulimit -f)"}}) {
        rlimit limit{};
        if (::getrlimit(resource, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY && limit.rlim_cur < kLeastBytes)
            return std::string("the process's ") + what + " is limited to " + std::to_string(limit.rlim_cur >> 20) +
                   " MiB, under the 1024 MiB an OpenCL runtime is given to start in (some abort or end the "
                   "process below their need)";
    }
    return "";
}

std::vector<DeviceEntry> devices() {
    if (!limits_block_runtime().empty()) return {};  // not even loaded
    std::vector<cl::Platform> platforms;
    // No ICD or no platform: the loader reports an error, which here means "none".
    try {
        cl::Platform::get(&platforms);
    } catch (const cl::Error&) {
        return {};
    }
    std::vector<DeviceEntry> out;
    for (std::size_t p = 0; p < platforms.size(); ++p) {
        std::vector<cl::Device> devs;
        try {
            platforms[p].getDevices(CL_DEVICE_TYPE_ALL, &devs);
        } catch (const cl::Error&) {
            continue;  // a platform with no device
        }
        for (std::size_t d = 0; d < devs.size(); ++d) {
            DeviceEntry e;
            e.platform = int(p);
            e.index = int(d);
            e.device = devs[d];
            guarded("device query", [&] {
                e.platform_name = platforms[p].getInfo<CL_PLATFORM_NAME>();
                e.name = devs[d].getInfo<CL_DEVICE_NAME>();
                e.vendor = devs[d].getInfo<CL_DEVICE_VENDOR>();
                e.version = devs[d].getInfo<CL_DEVICE_VERSION>();
                e.gpu = (devs[d].getInfo<CL_DEVICE_TYPE>() & CL_DEVICE_TYPE_GPU) != 0;
                // SNVR_OPENCL_NO_FP64=1: every device as one without double precision (tests).
                const char* no_fp64 = std::getenv("SNVR_OPENCL_NO_FP64");
                e.fp64 = devs[d].getInfo<CL_DEVICE_DOUBLE_FP_CONFIG>() != 0 && !(no_fp64 && std::string(no_fp64) == "1");
                e.memory = std::size_t(devs[d].getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>());
                e.max_alloc = std::size_t(devs[d].getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>());
                // SNVR_OPENCL_MEMORY=N: every device as one of at most N bytes (tests).
                if (const char* most = std::getenv("SNVR_OPENCL_MEMORY")) {
                    const std::size_t n = std::size_t(std::strtoull(most, nullptr, 10));
                    e.memory = std::min(e.memory, n);
                    e.max_alloc = std::min(e.max_alloc, n);
                }
                e.max_group = devs[d].getInfo<CL_DEVICE_MAX_WORK_GROUP_SIZE>();
                const std::vector<std::size_t> items = devs[d].getInfo<CL_DEVICE_MAX_WORK_ITEM_SIZES>();
                if (!items.empty()) e.max_group = std::min(e.max_group, items[0]);
                e.local_memory = std::size_t(devs[d].getInfo<CL_DEVICE_LOCAL_MEM_SIZE>());
                e.compute_units = int(devs[d].getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>());
            });
            // Strings from drivers often end in NULs or blanks.
            for (std::string* s : {&e.platform_name, &e.name, &e.vendor, &e.version})
                while (!s->empty() && (s->back() == '\0' || s->back() == ' ')) s->pop_back();
            out.push_back(std::move(e));
        }
    }
    return out;
}

DeviceEntry choose_device(const std::string& spec) {
    const std::vector<DeviceEntry> all = devices();
    if (all.empty()) {
        const std::string limited = limits_block_runtime();
        throw ParameterError("device '" + spec + "': " +
                             (limited.empty() ? "no OpenCL platform is installed on this machine"
                                              : "OpenCL not tried: " + limited));
    }
    if (spec == "opencl" || spec == "auto") {
        for (const DeviceEntry& e : all)
            if (e.gpu) return e;
        return all.front();
    }
    if (spec.rfind("opencl:", 0) == 0) {
        int p = -1, d = -1;
        char tail = 0;
        if (std::sscanf(spec.c_str() + 7, "%d:%d%c", &p, &d, &tail) != 2)
            throw ParameterError("device '" + spec + "': expected opencl:<platform>:<device>, e.g. opencl:0:0");
        for (const DeviceEntry& e : all)
            if (e.platform == p && e.index == d) return e;
        throw ParameterError("device '" + spec + "': no such OpenCL platform/device; run 'snvr-cl devices'");
    }
    for (const DeviceEntry& e : all)
        if (e.name.find(spec) != std::string::npos || e.platform_name.find(spec) != std::string::npos) return e;
    throw ParameterError("unknown device '" + spec + "'; run 'snvr-cl devices' to list what can run");
}

namespace {

struct BuiltProgram {
    cl::Context context;
    cl::Program program;
};

struct ProgramCache {
    std::mutex mutex;
    std::map<std::tuple<int, int, std::string>, BuiltProgram> built;  // (platform, device, options)
    std::atomic<std::size_t> builds{0};
};

// Never destroyed: releasing OpenCL objects from a static destructor at exit can run
// after the driver has been unloaded.
ProgramCache& program_cache() {
    static ProgramCache* cache = new ProgramCache;
    return *cache;
}

BuiltProgram build_program(const DeviceEntry& device, const std::string& options) {
    BuiltProgram b;
    guarded("set-up", [&] { b.context = cl::Context(device.device); });
    cl::Program::Sources sources;
    for (const KernelSource& s : kernel_sources()) sources.emplace_back(s.text);
    guarded("program", [&] { b.program = cl::Program(b.context, sources); });
    try {
        b.program.build(std::vector<cl::Device>{device.device}, options.c_str());
    } catch (const cl::Error& e) {
        std::string log;
        try {
            log = b.program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device.device);
        } catch (const cl::Error&) {
            log = "(no build log)";
        }
        throw ResourceError("OpenCL program build failed on '" + device.name + "' (" + error_name(e.err()) + ", options " +
                            options + "):\n" + log);
    }
    ++program_cache().builds;
    return b;
}

}  // namespace

std::size_t program_builds() { return program_cache().builds; }

Runtime::Runtime(DeviceEntry device, const std::string& real_type, const std::string& extra)
    : device_(std::move(device)) {
    if (real_type == "double" && !device_.fp64)
        throw ParameterError("OpenCL device '" + device_.name + "' has no double precision (fp64); use --precision float");
    std::string options = "-cl-std=CL1.2 -DREAL=" + real_type + (real_type == "double" ? " -DSNVR_DOUBLE" : "") + (device_.fp64 ? " -DSNVR_FP64 -DACC=double" : " -DACC=float");
    if (!extra.empty()) options += " " + extra;
    // Float division and sqrt are correctly rounded in C++; ask the same of the device.
    const cl_device_fp_config single = guarded("device query", [&] { return device_.device.getInfo<CL_DEVICE_SINGLE_FP_CONFIG>(); });
    if (single & CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT) options += " -cl-fp32-correctly-rounded-divide-sqrt";
    // Extra compiler options for experiments (and for testing the failure path).
    if (const char* extra = std::getenv("SNVR_OPENCL_OPTIONS")) options += std::string(" ") + extra;

    ProgramCache& cache = program_cache();
    {
        // Held while building: a second session on the same device waits for this build
        // instead of starting its own.
        std::lock_guard<std::mutex> lock(cache.mutex);
        const auto key = std::make_tuple(device_.platform, device_.index, options);
        auto it = cache.built.find(key);
        if (it == cache.built.end()) it = cache.built.emplace(key, build_program(device_, options)).first;
        context_ = it->second.context;
        program_ = it->second.program;
    }
    guarded("set-up", [&] { queue_ = cl::CommandQueue(context_, device_.device); });
}

cl::Kernel Runtime::kernel(const char* name) const {
    return guarded("kernel", [&] { return cl::Kernel(program_, name); });
}

std::size_t Runtime::kernel_group_limit(const cl::Kernel& kernel) const {
    return guarded("kernel query", [&] { return kernel.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(device_.device); });
}

cl::Buffer Runtime::buffer(std::size_t bytes, const char* what) {
    if (bytes > device_.max_alloc)
        throw ResourceError(std::string("OpenCL device '") + device_.name + "': " + what + " needs " + std::to_string(bytes >> 20) +
                            " MiB in one buffer, more than its limit of " + std::to_string(device_.max_alloc >> 20) + " MiB");
    return guarded(what, [&] { return cl::Buffer(context_, CL_MEM_READ_WRITE, std::max<std::size_t>(bytes, 1)); });
}

}  // namespace snvr::opencl
