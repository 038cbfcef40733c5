// read_float_points and read_points: pick the parser from the file extension, map the
// file (parsers work on memory, not streams), and reject sets no later stage could use.
#include <cstddef>
#include <string>
#include <utility>

#include "io/io_common.hpp"
#include "io/point_readers.hpp"
#include "io/read_whole_file.hpp"
#include "snvr/error.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/point_io.hpp"

namespace snvr {
namespace {

using Parser = detail::FloatPoints (*)(std::string_view, const std::string&, const detail::ParseOptions&);

Parser parser_for(const std::string& path) {
    const std::string ext = detail::lower_extension(detail::format_name(path));  // "a.xyz.gz": ".xyz"
    if (ext == ".ply") return detail::parse_ply;
    if (ext == ".xyz" || ext == ".pts" || ext == ".txt" || ext == ".csv") return detail::parse_xyz;
    if (ext == ".obj") return detail::parse_obj;
    if (ext == ".off") return detail::parse_off;
    if (ext == ".las") return detail::parse_las;
    if (ext == ".laz")
        throw InputError(path + ": LAZ (compressed LAS) is not read; decompress it first, e.g. laszip -i " + path +
                         " -o points.las");
    throw InputError(path + ": unsupported point file extension '" + ext +
                     "' (supported: .ply, .xyz, .pts, .txt, .csv, .obj, .off, .las, each also gzipped as .gz)");
}

// A UTF-8 byte-order mark, as some Windows tools write before text.
std::string_view without_bom(std::string_view data) {
    return data.substr(0, 3) == "\xEF\xBB\xBF" ? data.substr(3) : data;
}

}  // namespace

detail::FloatPoints detail::parse_points(std::string_view data, const std::string& path, const ParseOptions& options) {
    FloatPoints points = parser_for(path)(without_bom(data), path, options);
    if (points.xyz.empty()) throw InputError(path + ": no points (the point cloud is empty)");
    return points;
}

detail::FloatPoints detail::read_float_points(const std::string& path, const ParseOptions& options) {
    require_regular_file(path);  // before the extension: "'dir' is a directory"
    parser_for(path);            // an unknown extension fails before any read
    const InputBytes bytes(path);
    return parse_points(bytes.view(), path, options);  // unmapped on the way out
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
