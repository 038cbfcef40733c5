// read_points: picks the parser from the file extension, maps the file (parsers
// then work on memory, not streams; nothing is copied) and rejects sets that no
// later stage could use.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>

#include "io/io_common.hpp"
#include "io/read_whole_file.hpp"
#include "io/point_readers.hpp"
#include "snvr/error.hpp"
#include "snvr/io.hpp"

namespace snvr {
namespace {

using Parser = PointSet (*)(std::string_view, const std::string&);

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

void check_points(const PointSet& points, const std::string& path) {
    if (points.empty()) throw InputError(path + ": no points (the point cloud is empty)");
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Vec3& p = points[i];
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
            throw InputError(path + ": point " + std::to_string(i) + " has a non-finite coordinate (" +
                             detail::format_number(p[0]) + " " + detail::format_number(p[1]) + " " +
                             detail::format_number(p[2]) + ")");
    }
}

}  // namespace

PointSet detail::parse_points(std::string_view data, const std::string& path) {
    PointSet points = parser_for(path)(without_bom(data), path);
    check_points(points, path);
    return points;
}

PointSet read_points(const std::string& path) {
    detail::require_regular_file(path);  // before the extension: "'dir' is a directory"
    parser_for(path);                    // an unknown extension fails before any read
    const detail::InputBytes bytes(path);
    return detail::parse_points(bytes.view(), path);
}

}  // namespace snvr
