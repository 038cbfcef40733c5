// write_points: binary PLY (float32 x y z) or text (one point per line, round-trip
// digits), through an AtomicFile like every writer of the library.
#include <memory>
#include <string>

#include "io/atomic_file.hpp"
#include "io/formats.hpp"
#include "io/io_common.hpp"
#include "io/staged_writes.hpp"
#include "io/writers.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh_io.hpp"
#include "snvr/point_io.hpp"

namespace snvr {

namespace {

void write_ply_header(std::size_t count, const std::string& comment, AtomicFile& out) {
    out.write("ply\nformat binary_little_endian 1.0\n" + (comment.empty() ? "" : "comment " + comment + "\n") +
              "element vertex " + std::to_string(count) +
              "\nproperty float x\nproperty float y\nproperty float z\nend_header\n");
}

void write_ply_records(const PointSet& points, AtomicFile& out) {
    char record[12];
    for (const Vec3& p : points) {
        for (std::size_t a = 0; a < 3; ++a) detail::store_le(float(p[a]), record + 4 * a);
        out.write(record, sizeof record);
    }
}

}  // namespace

void detail::write_ply_points(const PointSet& points, const std::string& comment, AtomicFile& out) {
    write_ply_header(points.size(), comment, out);
    write_ply_records(points, out);
}

void write_point_stream(const std::string& path, std::size_t count, const std::string& comment,
                        const std::function<void(const std::function<void(const PointSet&)>&)>& produce) {
    if (detail::lower_extension(path) != ".ply")
        throw IoError(path + ": points made as they are written go to a binary PLY (.ply), whose header holds the count");
    if (comment.find('\n') != std::string::npos) throw InputError(path + ": the comment must be one line");
    AtomicFile file(path);
    write_ply_header(count, comment, file);
    std::size_t written = 0;
    produce([&](const PointSet& chunk) {
        written += chunk.size();
        if (written <= count) write_ply_records(chunk, file);
    });
    if (written != count)
        throw IoError(path + ": " + std::to_string(written) + " points were made where " + std::to_string(count) +
                      " were announced; nothing written");
    file.commit();
}

void detail::write_text_points(const PointSet& points, const std::string&, AtomicFile& out) {  // text has no comment
    std::string line;
    for (const Vec3& p : points) {
        line.clear();
        for (std::size_t a = 0; a < 3; ++a) {
            if (a) line += ' ';
            detail::append_number(line, p[a]);
        }
        line += '\n';
        out.write(line);
    }
}

std::unique_ptr<AtomicFile> detail::stage_points(const PointSet& points, const std::string& path,
                                                 const std::string& comment) {
    const PointsWriter write = format_for(path, FormatUse::WritePoints).write.points;
    if (comment.find('\n') != std::string::npos) throw InputError(path + ": the comment must be one line");
    auto file = std::make_unique<AtomicFile>(path);
    write(points, comment, *file);
    file->finish();
    return file;
}

void write_points(const PointSet& points, const std::string& path, const std::string& comment) {
    detail::stage_points(points, path, comment)->commit();
}

}  // namespace snvr
