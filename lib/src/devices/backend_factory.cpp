// The backends behind the solver's interface (solver/backend.hpp): make_backend picks one for
// --device, list_devices (snvr/devices.hpp) says what this machine can run. Above the
// solver and both backends, which know nothing of each other.
#include <omp.h>

#include "solver/backend.hpp"
#include "opencl/opencl_backend.hpp"
#include "opencl/runtime.hpp"
#include "openmp/openmp_backend.hpp"
#include "snvr/devices.hpp"
#include "snvr/error.hpp"

namespace snvr {

template <class Real>
std::unique_ptr<Backend<Real>> make_backend(const std::string& device, std::vector<std::string>& notes) {
    if (device == "openmp" || device == "omp") return make_openmp_backend<Real>();
    if (device == "auto") {
        // Any OpenCL device (a GPU first); no platform, no fp64 or a failed build is not
        // an error here: the reference backend runs instead.
        try {
            return make_opencl_backend<Real>("auto");
        } catch (const Error& e) {
            const std::string why = e.what();  // its first line: a build log can be long
            notes.push_back("OpenCL not usable (" + why.substr(0, why.find('\n')) +
                            "); running on the OpenMP reference backend");
            return make_openmp_backend<Real>();
        }
    }
    return make_opencl_backend<Real>(device);
}

template <class Real>
void setup_backend(std::unique_ptr<Backend<Real>>& backend, const std::string& device, const BrickLayout& layout,
                   std::vector<std::string>& notes) {
    try {
        backend->setup(layout);
    } catch (const ResourceError& e) {
        if (device != "auto" || backend->name().rfind("opencl", 0) != 0) throw;
        notes.push_back(std::string(e.what()) + "; running on the OpenMP reference backend");
        backend = make_openmp_backend<Real>();
        backend->setup(layout);
    }
}

template std::unique_ptr<Backend<double>> make_backend<double>(const std::string&, std::vector<std::string>&);
template std::unique_ptr<Backend<float>> make_backend<float>(const std::string&, std::vector<std::string>&);
template void setup_backend<double>(std::unique_ptr<Backend<double>>&, const std::string&, const BrickLayout&,
                                    std::vector<std::string>&);
template void setup_backend<float>(std::unique_ptr<Backend<float>>&, const std::string&, const BrickLayout&,
                                   std::vector<std::string>&);

std::vector<DeviceInfo> list_devices() {
    DeviceInfo omp;
    omp.id = "openmp";
    omp.name = "OpenMP reference backend";
    omp.kind = "cpu";
    omp.compute_units = omp_get_max_threads();
    omp.fp64 = true;
    omp.note = "reference and fallback";
    const std::string limited = opencl::limits_block_runtime();
    if (!limited.empty()) omp.note += "; OpenCL not tried: " + limited;
    std::vector<DeviceInfo> out{omp};
    for (const opencl::DeviceEntry& e : opencl::devices()) {
        DeviceInfo d;
        d.id = "opencl:" + std::to_string(e.platform) + ":" + std::to_string(e.index);
        d.name = e.name;
        d.kind = e.gpu ? "gpu" : "cpu/other";
        d.compute_units = e.compute_units;
        d.memory_bytes = e.memory;
        d.fp64 = e.fp64;
        d.note = e.platform_name + ", " + e.version;
        out.push_back(d);
    }
    return out;
}

}  // namespace snvr
