// read_float_points, read_points and read_points_or_mesh: pick the parser by the format
// table, open the file as an InputSource for it, and reject sets no later stage could
// use and files changed while read.
#include <cstddef>
#include <string>
#include <utility>

#include "geometry/point_tree.hpp"
#include "io/formats.hpp"
#include "io/io_common.hpp"
#include "io/point_readers.hpp"
#include "io/input_source.hpp"
#include "snvr/error.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/point_io.hpp"

namespace snvr {

detail::FloatPoints detail::parse_points(InputSource& source, const ParseOptions& options) {
    const std::string& path = source.path();
    const PointParser parse = format_for(path, FormatUse::ReadPoints).read.points;
    source.skip_bom();
    FloatPoints points;
    try {
        points = parse(source, path, options);
    } catch (...) {
        source.finish();  // where the file changed, that is the reason (a parse of a cut part fails too)
        throw;
    }
    source.finish();
    if (points.xyz.empty()) throw InputError(path + ": no points (the point cloud is empty)");
    return points;
}

detail::FloatPoints detail::parse_points(std::string_view data, const std::string& path, const ParseOptions& options) {
    InputSource source(data, path);
    return parse_points(source, options);
}

detail::FloatPoints detail::read_float_points(const std::string& path, const ParseOptions& options,
                                              const std::string& temp_folder) {
    require_regular_file(path);               // before the extension: "'dir' is a directory"
    format_for(path, FormatUse::ReadPoints);  // an unknown extension fails before any read
    InputSource source(path, temp_folder);
    return parse_points(source, options);  // the file's bytes released on the way out
}

detail::PointsOrMesh detail::read_points_or_mesh(const std::string& path, const std::string& temp_folder) {
    require_regular_file(path);
    const Format* format = read_format(path);
    PointsOrMesh content;
    if (!format || !format->read.mesh) {
        content.points = read_float_points(path, {}, temp_folder);
        return content;
    }
    InputSource source(path, temp_folder);
    source.skip_bom();
    content.is_mesh = format->read.faces && format->read.faces(source, path);
    if (content.is_mesh) {
        source.skip_bom(false);  // the mesh readers take every byte: a binary STL's may start so
        content.mesh = format->read.mesh(source.all(), path);
    } else {
        content.points = parse_points(source);
    }
    return content;  // the file's bytes released on the way out
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
    return detail::cloud_of(std::move(points.xyz), points.origin);
}

}  // namespace snvr
