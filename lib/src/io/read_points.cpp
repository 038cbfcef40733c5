// read_float_points, read_points and read_points_or_mesh: pick the parser by the format
// table, map the file (parsers work on memory, not streams), and reject sets no later
// stage could use.
#include <cstddef>
#include <string>
#include <utility>

#include "io/formats.hpp"
#include "io/io_common.hpp"
#include "io/point_readers.hpp"
#include "io/read_whole_file.hpp"
#include "snvr/error.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/point_io.hpp"

namespace snvr {
namespace {

// A UTF-8 byte-order mark, as some Windows tools write before text.
std::string_view without_bom(std::string_view data) {
    return data.substr(0, 3) == "\xEF\xBB\xBF" ? data.substr(3) : data;
}

}  // namespace

detail::FloatPoints detail::parse_points(std::string_view data, const std::string& path, const ParseOptions& options) {
    FloatPoints points = format_for(path, FormatUse::ReadPoints).read.points(without_bom(data), path, options);
    if (points.xyz.empty()) throw InputError(path + ": no points (the point cloud is empty)");
    return points;
}

detail::FloatPoints detail::read_float_points(const std::string& path, const ParseOptions& options) {
    require_regular_file(path);               // before the extension: "'dir' is a directory"
    format_for(path, FormatUse::ReadPoints);  // an unknown extension fails before any read
    const InputBytes bytes(path);
    return parse_points(bytes.view(), path, options);  // unmapped on the way out
}

detail::PointsOrMesh detail::read_points_or_mesh(const std::string& path) {
    require_regular_file(path);
    const Format* format = read_format(path);
    PointsOrMesh content;
    if (!format || !format->read.mesh) {
        content.points = read_float_points(path);
        return content;
    }
    const InputBytes bytes(path);
    const std::string_view data = bytes.view();
    content.is_mesh = format->read.faces && format->read.faces(without_bom(data), path);
    if (content.is_mesh)
        content.mesh = format->read.mesh(data, path);
    else
        content.points = parse_points(data, path);
    return content;  // unmapped on the way out
}

PointSet detail::world_points(const FloatPoints& points) {
    PointSet world(points.xyz.size());
    const Vec3& o = points.origin;
    const std::ptrdiff_t n = std::ptrdiff_t(world.size());
#pragma omp parallel for schedule(static) if (n >= (1 << 15))
    for (std::ptrdiff_t i = 0; i < n; ++i) {
        const auto& p = points.xyz[std::size_t(i)];
        world[std::size_t(i)] = {o[0] + double(p[0]), o[1] + double(p[1]), o[2] + double(p[2])};
    }
    return world;
}

PointSet read_points(const std::string& path) { return detail::world_points(detail::read_float_points(path)); }

PointCloud read_point_cloud(const std::string& path) {
    detail::FloatPoints points = detail::read_float_points(path);
    return PointCloud(std::move(points.xyz), points.origin);
}

}  // namespace snvr
