// read_input (shell.hpp): the points to reconstruct from, read from a point file or
// sampled from a mesh's triangles at half a voxel.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "geometry/vec3_math.hpp"
#include "io/io_common.hpp"
#include "io/mesh_readers.hpp"
#include "io/point_readers.hpp"
#include "io/read_whole_file.hpp"
#include "snvr/error.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/point_io.hpp"
#include "snvr/shell.hpp"
#include "snvr/reconstruct.hpp"

namespace snvr {
namespace {

// Half the voxel the run will have at most: resolution cells span at least the box.
double half_voxel(const Mesh& mesh, const Parameters& params) {
    if (params.voxel) return *params.voxel / 2;
    const Bounds box = params.box ? Bounds{(*params.box)[0], (*params.box)[1]} : bounds(mesh.vertices);
    return box.longest() / params.resolution / 2;
}

}  // namespace

InputPoints read_input(const std::string& path, const Parameters& params) {
    detail::require_regular_file(path);
    const std::string ext = detail::lower_extension(detail::format_name(path));
    if (ext != ".stl" && ext != ".ply" && ext != ".obj" && ext != ".off") return {read_point_cloud(path), 0, 0};
    detail::InputBytes bytes(path);
    const std::string_view data = bytes.view();
    if (!detail::has_faces(data, path)) {
        detail::FloatPoints points = detail::parse_points(data, path);
        bytes.release();  // before the cloud is filed: the file and the cloud never together
        return {PointCloud(std::move(points.xyz), points.origin), 0, 0};
    }
    const Mesh mesh = detail::parse_mesh(data, path);
    bytes.release();
    // Its samples become float points, as a point file's do: the same range holds.
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
        for (double x : mesh.vertices[i])
            if (!(std::abs(x) <= std::numeric_limits<float>::max()))
                throw InputError(path + ": vertex " + std::to_string(i) + " (" + detail::format_number(mesh.vertices[i][0]) +
                                 ", " + detail::format_number(mesh.vertices[i][1]) + ", " +
                                 detail::format_number(mesh.vertices[i][2]) + ") " +
                                 (std::isfinite(x) ? "lies beyond 32-bit float range" : "has a non-finite coordinate"));
    InputPoints in;
    in.triangles = mesh.triangles.size();
    in.spacing = half_voxel(mesh, params);
    if (!(in.spacing > 0)) return {PointCloud(mesh.vertices), in.triangles, 0};  // all at one place: the vertices will do
    in.points = PointCloud(sample_triangles(mesh, in.spacing));
    return in;
}

}  // namespace snvr
