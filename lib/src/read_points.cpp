// read_points: picks the parser from the file extension, loads the whole file
// with one read (parsers then work on memory, not streams) and rejects sets
// that no later stage could use.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>

#include "io_common.hpp"
#include "point_readers.hpp"
#include "snvr/error.hpp"
#include "snvr/io.hpp"

namespace snvr {
namespace {

using Parser = PointSet (*)(std::string_view, const std::string&);

Parser parser_for(const std::string& path) {
    const std::string ext = detail::lower_extension(path);
    if (ext == ".ply") return detail::parse_ply;
    if (ext == ".xyz" || ext == ".pts" || ext == ".txt") return detail::parse_xyz;
    if (ext == ".obj") return detail::parse_obj;
    if (ext == ".off") return detail::parse_off;
    throw InputError(path + ": unsupported point file extension '" + ext +
                     "' (supported: .ply, .xyz, .pts, .txt, .obj, .off)");
}

struct FileCloser {
    void operator()(std::FILE* file) const { std::fclose(file); }
};

std::string read_whole_file(const std::string& path) {
    errno = 0;
    const std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
    if (!file) throw IoError("cannot open '" + path + "': " + std::strerror(errno != 0 ? errno : EIO));
    // Sized from the file system so a regular file takes one fread; the loop
    // still copes with files that grow or report no size.
    std::error_code ignored;
    const std::uintmax_t size = std::filesystem::file_size(path, ignored);
    std::size_t block = ignored ? std::size_t(1) << 20 : std::size_t(size) + 1;
    std::string data;
    for (;;) {
        const std::size_t old = data.size();
        data.resize(old + block);
        errno = 0;
        const std::size_t got = std::fread(&data[old], 1, block, file.get());
        data.resize(old + got);
        if (got < block) break;
        block = std::max(block, data.size());
    }
    if (std::ferror(file.get())) throw IoError("cannot read '" + path + "': " + std::strerror(errno != 0 ? errno : EIO));
    return data;
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

PointSet read_points(const std::string& path) {
    const Parser parse = parser_for(path);
    const std::string data = read_whole_file(path);
    PointSet points = parse(data, path);
    check_points(points, path);
    return points;
}

}  // namespace snvr
