#include <omp.h>

#include "backend.hpp"
#include "openmp/openmp_backend.hpp"
#include "snvr/devices.hpp"
#include "snvr/error.hpp"

namespace snvr {

template <class Real>
std::unique_ptr<Backend<Real>> make_backend(const std::string& device, std::string& notice) {
    if (device == "auto") {
        notice = "no OpenCL backend in this build: running on the OpenMP reference backend";
        return make_openmp_backend<Real>();
    }
    if (device == "openmp" || device == "omp") return make_openmp_backend<Real>();
    if (device.rfind("opencl", 0) == 0)
        throw ParameterError("device '" + device + "': the OpenCL backend is not part of this build yet; use --device openmp or auto");
    throw ParameterError("unknown device '" + device + "'; run 'snvr-cl devices' to list what can run");
}

template std::unique_ptr<Backend<double>> make_backend<double>(const std::string&, std::string&);
template std::unique_ptr<Backend<float>> make_backend<float>(const std::string&, std::string&);

std::vector<DeviceInfo> list_devices() {
    DeviceInfo omp;
    omp.id = "openmp";
    omp.name = "OpenMP reference backend";
    omp.kind = "cpu";
    omp.compute_units = omp_get_max_threads();
    omp.fp64 = true;
    omp.note = "reference and fallback";
    return {omp};
}

}  // namespace snvr
