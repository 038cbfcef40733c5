// read_input (shell.hpp): the points to reconstruct from, read from a point file or
// sampled from a mesh's triangles at half a voxel. What the file holds comes from
// io's read_points_or_mesh; here is only the policy for a mesh.
#include <cmath>
#include <limits>
#include <new>
#include <string>
#include <utility>

#include "geometry/point_tree.hpp"
#include "geometry/vec3_math.hpp"
#include "io/io_common.hpp"
#include "io/point_readers.hpp"
#include "process_limits.hpp"
#include "solver/shared_filing.hpp"
#include "spilled_memory.hpp"
#include "snvr/error.hpp"
#include "snvr/point_cloud.hpp"
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

// Its samples become float points, as a point file's do: the same range holds.
void require_float_range(const Mesh& mesh, const std::string& path) {
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
        for (double x : mesh.vertices[i])
            if (!(std::abs(x) <= std::numeric_limits<float>::max()))
                throw InputError(path + ": vertex " + std::to_string(i) + " (" + detail::format_number(mesh.vertices[i][0]) +
                                 ", " + detail::format_number(mesh.vertices[i][1]) + ", " +
                                 detail::format_number(mesh.vertices[i][2]) + ") " +
                                 (std::isfinite(x) ? "lies beyond 32-bit float range" : "has a non-finite coordinate"));
}

// The file's points (filed with the others where given), or its mesh sampled at half
// the run's voxel.
InputPoints read_or_sample(const std::string& path, const Parameters& params, TileScheduler* others) {
    if (const std::size_t n = detail::parts_to_read(others, path)) {  // each process reads its own part
        detail::FloatPoints part = detail::read_my_part(*others, path, n, params.temp_dir);
        return {detail::cloud_read_with(*others, std::move(part), n), 0, 0};
    }
    detail::PointsOrMesh content = detail::read_points_or_mesh(path, params.temp_dir);
    if (!content.is_mesh) {
        detail::PointArray<Vec3f>& xyz = content.points.xyz;
        const Vec3& origin = content.points.origin;
        return {others ? detail::cloud_filed_with(*others, std::move(xyz), origin) : detail::cloud_of(std::move(xyz), origin),
                0, 0};
    }
    if (others) detail::no_shared_filing(*others);
    const Mesh& mesh = content.mesh;
    require_float_range(mesh, path);
    InputPoints in;
    in.triangles = mesh.triangles.size();
    in.spacing = half_voxel(mesh, params);
    if (!(in.spacing > 0)) return {PointCloud(mesh.vertices), in.triangles, 0};  // all at one place: the vertices will do
    in.points = PointCloud(sample_triangles(mesh, in.spacing));
    return in;
}

}  // namespace

InputPoints read_input(const std::string& path, const Parameters& params, TileScheduler* others) {
    // Under a budget, points beyond it are read into a file (make_shell's rule).
    const detail::SpillScope spill(params.max_memory.value_or(0), 0, params.temp_dir);
    try {
        return read_or_sample(path, params, others);
    } catch (const std::bad_alloc&) {
        const std::string limit = detail::memory_limit_text();
        throw ResourceError(path + ": out of memory reading the points" + (limit.empty() ? "" : " (" + limit + ")"));
    }
}

}  // namespace snvr
