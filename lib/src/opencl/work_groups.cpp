#include "opencl/work_groups.hpp"

#include <algorithm>
#include <cstdlib>
#include <string>

#include "snvr/error.hpp"

namespace snvr::opencl {

namespace {

constexpr const char* kVariable = "SNVR_OPENCL_WORK_GROUP";
constexpr const char* kShapeVariable = "SNVR_OPENCL_KERNELS";

// The size SNVR_OPENCL_WORK_GROUP asks for, or 0.
std::size_t asked_size() {
    const char* text = std::getenv(kVariable);
    if (!text || !*text) return 0;
    char* end = nullptr;
    const unsigned long long n = std::strtoull(text, &end, 10);
    if (*end != '\0' || n < 8 || n > 1024 || (n & (n - 1)) != 0)
        throw ParameterError(std::string(kVariable) + " must be a power of two from 8 to 1024, got '" + text + "'");
    return std::size_t(n);
}

// The variant SNVR_OPENCL_KERNELS asks for, else the device's type's.
KernelShape asked_shape(const DeviceEntry& device) {
    const char* text = std::getenv(kShapeVariable);
    if (!text || !*text) return device.gpu ? KernelShape::Rows : KernelShape::Planes;
    const std::string s = text;
    if (s == "planes") return KernelShape::Planes;
    if (s == "rows") return KernelShape::Rows;
    throw ParameterError(std::string(kShapeVariable) + " must be 'planes' or 'rows', got '" + s + "'");
}

}  // namespace

std::string WorkGroups::build_options() const {
    return std::string(shape == KernelShape::Rows ? "-DSNVR_ROW_KERNELS " : "") + "-DPLANES_PER_GROUP=" +
           std::to_string(planes) + " -DROWS_PER_GROUP=" + std::to_string(brick_rows) +
           " -DREDUCE_GROUP=" + std::to_string(reduce);
}

std::string WorkGroups::describe() const {
    return shape == KernelShape::Rows ? "row kernels, groups of " + std::to_string(brick_rows)
                                      : "plane kernels, groups of " + std::to_string(planes);
}

std::size_t plane_group_local_bytes(std::size_t planes, std::size_t real_bytes) {
    return planes / 8 * 512 * real_bytes;
}

std::size_t row_group_local_bytes(std::size_t rows, std::size_t real_bytes) {
    return rows / 64 * 512 * real_bytes;
}

std::size_t fit_group(std::size_t wanted, std::size_t limit) {
    std::size_t n = 1;
    while (n * 2 <= wanted && n * 2 <= limit) n *= 2;
    return n;
}

namespace {

// fit_group, then halved while the group's local memory (`bytes(n)`) exceeds the
// device's; below `least` when no group of `least` fits.
template <class Bytes>
std::size_t fit_local(std::size_t wanted, std::size_t least, const DeviceEntry& device, const Bytes& bytes) {
    std::size_t n = fit_group(std::max(wanted, least), device.max_group);
    while (n >= least && bytes(n) > device.local_memory) n /= 2;
    return n;
}

}  // namespace

WorkGroups work_groups(const DeviceEntry& device, std::size_t real_bytes) {
    WorkGroups w;
    const std::size_t asked = asked_size();
    const std::size_t most = device.max_group;
    if (asked) w.planes = w.rows = w.bricks = w.cells = w.reduce = asked;
    w.rows = fit_group(w.rows, most);
    w.bricks = fit_group(w.bricks, most);
    w.cells = fit_group(w.cells, most);
    w.reduce = fit_group(std::min<std::size_t>(w.reduce, 256), most);
    const std::size_t planes =
        fit_local(w.planes, 8, device, [&](std::size_t n) { return plane_group_local_bytes(n, real_bytes); });
    if (planes < 8)
        throw ResourceError("OpenCL device '" + device.name + "' allows work-groups of " + std::to_string(most) +
                            " work-items and " + std::to_string(device.local_memory) +
                            " bytes of local memory; the kernels need 8 work-items and " +
                            std::to_string(plane_group_local_bytes(8, real_bytes)) + " bytes");
    w.planes = planes;
    w.shape = asked_shape(device);
    const std::size_t rows = fit_local(asked ? asked : w.brick_rows, 64, device,
                                       [&](std::size_t n) { return row_group_local_bytes(n, real_bytes); });
    if (rows < 64) w.shape = KernelShape::Planes;  // not even one brick's rows: planes
    w.brick_rows = std::max<std::size_t>(rows, 64);
    return w;
}

}  // namespace snvr::opencl
