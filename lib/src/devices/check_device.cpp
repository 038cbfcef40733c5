#include "devices/check_device.hpp"

#include <cstdlib>

#include "opencl/device_walls.hpp"
#include "opencl/runtime.hpp"

namespace snvr::detail {

WallRays wall_rays_for(const std::string& backend) {
    const char* asked = std::getenv("SNVR_CHECK_WALLS");
    const std::string rule = asked ? asked : "";
    if (rule == "host" || backend.rfind("opencl:", 0) != 0) return nullptr;
    const std::string spec = backend.substr(0, backend.find(' '));
    opencl::DeviceEntry device;
    try {
        device = opencl::choose_device(spec);
    } catch (const Error&) {
        return nullptr;
    }
    if (!device.fp64 || (!device.gpu && rule != "device")) return nullptr;
    const std::string on = spec + " (" + device.name + ")";
    return [spec, on](const Mesh& m, const TriangleGrid& grid, const std::vector<Vec3>& normals, double eps,
                      const std::vector<std::uint32_t>& order, std::vector<double>& wall) -> std::string {
        try {
            opencl::device_walls(spec, m, grid, normals, eps, order, wall);
            return on;
        } catch (const ResourceError&) {  // its memory, its build: the host casts them
            return "";
        }
    };
}

}  // namespace snvr::detail
