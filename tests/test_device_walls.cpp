// The check's walls on an OpenCL device (PoCL in CI; kernels/wall_rays.cl) against the
// host's rays: every vertex's wall the same to the bit, on shells of the scans and of the
// sampler's shapes, whatever order the vertices come in. The small shell's case is also
// run under Oclgrind (tests/CMakeLists.txt).
#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

#include "check/walls.hpp"
#include "devices/check_device.hpp"
#include "mesh/triangle_grid.hpp"
#include "opencl/device_walls.hpp"
#include "opencl/runtime.hpp"
#include "snvr/point_io.hpp"
#include "snvr/quality.hpp"
#include "snvr/report.hpp"
#include "snvr/shapes.hpp"
#include "snvr/shell.hpp"

using namespace snvr;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Mesh shell_of(const PointCloud& points, int resolution) {
    ShellSettings s;
    s.params.resolution = resolution;
    s.params.device = "openmp";
    return make_shell(points, s).mesh;
}

// Every wall on the device and on the host, compared bit for bit; how many are finite.
std::size_t same_walls(const Mesh& m) {
    const TriangleGrid grid(m);
    const std::vector<Vec3> normals = detail::unit_normals(m);
    const double eps = detail::wall_epsilon(m);
    const std::size_t nv = m.vertices.size();
    std::vector<std::uint32_t> in_order(nv);
    std::iota(in_order.begin(), in_order.end(), 0u);
    std::vector<double> host(nv, kInf);
    detail::wall_thickness(m, grid, normals, eps, in_order, 0, nv, host);
    std::size_t finite = 0, differ = 0;
    for (const std::vector<std::uint32_t>& order : {detail::wall_order(m), in_order}) {
        std::vector<double> device(nv, -1.0);
        opencl::device_walls("opencl", m, grid, normals, eps, order, device);
        for (std::size_t v = 0; v < nv; ++v) differ += std::memcmp(&device[v], &host[v], sizeof(double)) != 0;
    }
    for (double w : host) finite += std::isfinite(w);
    CHECK(differ == 0);
    return finite;
}

bool device_has_fp64() { return opencl::choose_device("opencl").fp64; }

}  // namespace

TEST_CASE("the walls on an OpenCL device: a small shell, to the bit") {
    if (!device_has_fp64()) return;  // the walls stay on the host there (tested below)
    const Mesh m = shell_of(PointCloud(shapes::sphere({0.5, 0.5, 0.5}, 0.3, 0.03)), 32);
    REQUIRE(m.vertices.size() > 500);
    CHECK(same_walls(m) == m.vertices.size());  // a closed shell: every ray meets its other wall
}

TEST_CASE("the walls on an OpenCL device: the scans and the sampler's shapes, to the bit") {
    if (!device_has_fp64()) return;
    for (const char* scan : {"bunny", "horse"}) {
        CAPTURE(scan);
        const PointCloud points = read_point_cloud(std::string(SNVR_DATA_DIR) + "/" + scan + ".ply");
        for (int resolution : {64, 128}) {
            CAPTURE(resolution);
            const Mesh m = shell_of(points, resolution);
            CHECK(same_walls(m) > m.vertices.size() * 9 / 10);
        }
    }
    for (const std::string& shape : {std::string("torus"), std::string("sheets"), std::string("lidar")}) {
        CAPTURE(shape);
        CHECK(same_walls(shell_of(PointCloud(shapes::by_name(shape, 0.01)), 64)) > 0);
    }
    // A lone triangle: the rays from its corners meet nothing.
    Mesh flat;
    flat.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    flat.triangles = {{0, 1, 2}};
    CHECK(same_walls(flat) == 0);
}

TEST_CASE("make_shell's check with its walls on the device: the same figures, the device named") {
    if (!device_has_fp64()) return;
    const PointCloud points = read_point_cloud(std::string(SNVR_DATA_DIR) + "/bunny.ply");
    ShellSettings s;
    s.params.resolution = 64;
    s.params.device = "opencl";  // PoCL: a CPU, whose walls the rule leaves to the host
    const Shell host = make_shell(points, s);
    CHECK(host.quality.walls_on == "host");
    ::setenv("SNVR_CHECK_WALLS", "device", 1);
    const Shell device = make_shell(points, s);
    ::unsetenv("SNVR_CHECK_WALLS");
    CHECK(device.quality.walls_on.rfind("opencl:", 0) == 0);
    const auto figures = [](const MeshQuality& q) {
        const std::string j = quality_json(q);
        return j.substr(0, j.find("\"seconds\""));
    };
    CHECK(figures(device.quality) == figures(host.quality));
    CHECK(device.quality.wall_p01 == host.quality.wall_p01);
    const std::string report = report_json(make_report(device));
    CHECK(report.find("\"walls_on\": \"opencl:") != std::string::npos);
    CHECK(report_summary(make_report(device)).find("rays cast on opencl:") != std::string::npos);
}

TEST_CASE("the walls on a device too small for them: refused with the sizes, cast on the host instead") {
    if (!device_has_fp64()) return;
    const Mesh m = shell_of(PointCloud(shapes::sphere({0.5, 0.5, 0.5}, 0.3, 0.03)), 32);
    const PointCloud points(shapes::sphere({0.5, 0.5, 0.5}, 0.3, 0.03));
    ::setenv("SNVR_OPENCL_MEMORY", "65536", 1);  // 64 KiB: the solver's device, but not its walls
    ::setenv("SNVR_CHECK_WALLS", "device", 1);
    const TriangleGrid grid(m);
    std::vector<double> wall(m.vertices.size(), kInf);
    CHECK_THROWS_WITH_AS(opencl::device_walls("opencl", m, grid, detail::unit_normals(m), detail::wall_epsilon(m),
                                              detail::wall_order(m), wall),
                         doctest::Contains("MiB on OpenCL device"), ResourceError);
    const detail::WallRays rays = detail::wall_rays_for("opencl:0:0 (the test's)");
    REQUIRE(rays);  // the rule sends them there; the device cannot take them
    const MeshQuality fallen = detail::measure_told(m, points, 0.03, 0.01, false, nullptr, rays);
    ::unsetenv("SNVR_CHECK_WALLS");
    ::unsetenv("SNVR_OPENCL_MEMORY");
    const MeshQuality host = detail::measure_told(m, points, 0.03, 0.01, false, nullptr);
    CHECK(fallen.walls_on == "host");
    CHECK(fallen.wall_p01 == host.wall_p01);
    CHECK(fallen.wall_min == host.wall_min);
    CHECK(fallen.wall_misses == host.wall_misses);
}

TEST_CASE("the walls on an OpenCL device: refused by name without double precision") {
    if (device_has_fp64()) return;  // SNVR_OPENCL_NO_FP64=1 hides it (tests/CMakeLists.txt)
    Mesh flat;
    flat.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    flat.triangles = {{0, 1, 2}};
    const TriangleGrid grid(flat);
    std::vector<double> wall(3, kInf);
    CHECK_THROWS_WITH_AS(opencl::device_walls("opencl", flat, grid, detail::unit_normals(flat), 1e-9, {0, 1, 2}, wall),
                         doctest::Contains("no double precision"), ParameterError);
}
