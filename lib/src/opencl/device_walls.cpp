#include "opencl/device_walls.hpp"

#include <algorithm>
#include <limits>
#include <string>

#include "opencl/runtime.hpp"
#include "opencl/work_groups.hpp"

namespace snvr::opencl {

namespace {

// Work-items a group: rays are independent; a GPU's warps want a few of them.
constexpr std::size_t kRaysAGroup = 64;

}  // namespace

std::size_t device_walls_bytes(const Mesh& m, const TriangleGrid& grid) {
    const TriangleGrid::Cells c = grid.cells();
    const std::size_t nv = m.vertices.size();
    return nv * (2 * sizeof(Vec3) + sizeof(std::uint32_t) + sizeof(double)) + m.triangles.size() * sizeof(m.triangles[0]) +
           (c.cells + 1) * sizeof(std::uint32_t) + c.stride * (sizeof(std::uint32_t) + 6);
}

void device_walls(const std::string& spec, const Mesh& m, const TriangleGrid& grid, const std::vector<Vec3>& normals,
                  double eps, const std::vector<std::uint32_t>& order, std::vector<double>& wall) {
    const std::size_t count = order.size();
    const TriangleGrid::Cells c = grid.cells();
    if (count == 0) return;
    if (c.cells == 0) {  // no triangle: no wall anywhere
        for (std::uint32_t v : order) wall[v] = std::numeric_limits<double>::infinity();
        return;
    }
    if (count > std::numeric_limits<std::uint32_t>::max() || normals.size() != m.vertices.size())
        throw ParameterError("the walls on a device: one normal a vertex, fewer than 2^32 of them");
    const DeviceEntry device = choose_device(spec);
    if (!device.fp64) throw ParameterError("OpenCL device '" + device.name + "' has no double precision: the walls stay on the host");
    // Fail before allocating, with the sizes, rather than at an upload.
    const std::size_t need = device_walls_bytes(m, grid);
    if (need > device.memory)
        throw ResourceError("the walls need " + std::to_string(need >> 20) + " MiB on OpenCL device '" + device.name +
                            "', which has " + std::to_string(device.memory >> 20) + " MiB");
    // The solver's program (a float run's build options): built once a process.
    Runtime rt(device, "float", work_groups(device, sizeof(float)).build_options());
    guarded("the walls", [&] {
        cl::Kernel kernel = rt.kernel("wall_rays");
        const auto upload = [&](const void* data, std::size_t bytes, const char* what) {
            cl::Buffer b = rt.buffer(bytes, what);
            rt.queue().enqueueWriteBuffer(b, CL_TRUE, 0, bytes, data);
            return b;
        };
        const std::size_t nv = m.vertices.size();
        const cl::Buffer order_b = upload(order.data(), count * sizeof(std::uint32_t), "the walls' vertex order");
        const cl::Buffer vertices = upload(m.vertices.data(), nv * sizeof(Vec3), "the walls' vertices");
        const cl::Buffer triangles = upload(m.triangles.data(), m.triangles.size() * sizeof(m.triangles[0]), "the walls' triangles");
        const cl::Buffer normal_b = upload(normals.data(), nv * sizeof(Vec3), "the walls' normals");
        const cl::Buffer start = upload(c.start, (c.cells + 1) * sizeof(std::uint32_t), "the walls' grid cells");
        const cl::Buffer items = upload(c.items, c.stride * sizeof(std::uint32_t), "the walls' grid items");
        const cl::Buffer boxes = upload(c.boxes, 6 * c.stride, "the walls' grid boxes");
        cl::Buffer out = rt.buffer(count * sizeof(double), "the walls");
        const std::size_t group = std::min(kRaysAGroup, rt.kernel_group_limit(kernel));
        int a = 0;
        kernel.setArg(a++, cl_uint(count));
        kernel.setArg(a++, order_b);
        kernel.setArg(a++, vertices);
        kernel.setArg(a++, triangles);
        kernel.setArg(a++, normal_b);
        kernel.setArg(a++, start);
        kernel.setArg(a++, items);
        kernel.setArg(a++, boxes);
        kernel.setArg(a++, cl_ulong(c.stride));
        for (double x : {c.lo[0], c.lo[1], c.lo[2], c.size, c.inv_size, c.margin}) kernel.setArg(a++, x);
        for (int n : c.n) kernel.setArg(a++, cl_int(n));
        kernel.setArg(a++, eps);
        kernel.setArg(a++, out);
        rt.queue().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange((count + group - 1) / group * group),
                                        cl::NDRange(group));
        std::vector<double> got(count);
        rt.queue().enqueueReadBuffer(out, CL_TRUE, 0, count * sizeof(double), got.data());
        for (std::size_t k = 0; k < count; ++k) wall[order[k]] = got[k];
    });
}

}  // namespace snvr::opencl
