// write_mesh: binary STL, binary little endian PLY, OBJ and 3MF, each streamed
// through an AtomicFile so a failure never leaves a half-written mesh.
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>

#include "io/atomic_file.hpp"
#include "io/formats.hpp"
#include "io/io_common.hpp"
#include "io/staged_writes.hpp"
#include "io/writers.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh_io.hpp"

namespace snvr {
namespace {

void validate_mesh(const Mesh& mesh, const std::string& path) {
    if (mesh.triangles.empty()) throw InputError(path + ": mesh has no triangles");
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (const std::uint32_t v : mesh.triangles[t]) {
            if (v >= mesh.vertices.size())
                throw InputError(path + ": triangle " + std::to_string(t) + " uses vertex " + std::to_string(v) +
                                 " but the mesh has " + std::to_string(mesh.vertices.size()) + " vertices");
        }
    }
}

// Unit normal from the counter-clockwise vertex order; zero for a degenerate triangle.
Vec3 triangle_normal(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 u{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const Vec3 v{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    Vec3 n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (length > 0) {
        for (double& x : n) x /= length;
    }
    return n;
}

void store_vec3_f32(const Vec3& v, char* p) {
    for (std::size_t i = 0; i < 3; ++i) detail::store_le(float(v[i]), p + 4 * i);
}

}  // namespace

void detail::write_stl(const Mesh& mesh, AtomicFile& out) {
    // The header must not begin with "solid", or readers take the file for ASCII STL.
    char header[80] = {};
    const std::string label = "binary STL written by libsnvr";
    label.copy(header, label.size());
    out.write(header, sizeof header);
    char count[4];
    detail::store_le(std::uint32_t(mesh.triangles.size()), count);
    out.write(count, sizeof count);
    char record[50] = {};  // normal, 3 vertices, then a zero attribute word
    for (const auto& t : mesh.triangles) {
        const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
        store_vec3_f32(triangle_normal(a, b, c), record);
        store_vec3_f32(a, record + 12);
        store_vec3_f32(b, record + 24);
        store_vec3_f32(c, record + 36);
        out.write(record, sizeof record);
    }
}

void detail::write_ply(const Mesh& mesh, AtomicFile& out) {
    if (mesh.vertices.size() > std::size_t(std::numeric_limits<std::int32_t>::max()))
        throw InputError(out.target() + ": too many vertices for PLY 'int' vertex indices");
    out.write("ply\nformat binary_little_endian 1.0\ncomment written by libsnvr\nelement vertex " +
              std::to_string(mesh.vertices.size()) +
              "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
              std::to_string(mesh.triangles.size()) + "\nproperty list uchar int vertex_indices\nend_header\n");
    char vertex[12];
    for (const Vec3& v : mesh.vertices) {
        store_vec3_f32(v, vertex);
        out.write(vertex, sizeof vertex);
    }
    char face[13] = {3};  // list length, then three int32 indices
    for (const auto& t : mesh.triangles) {
        for (std::size_t i = 0; i < 3; ++i) detail::store_le(std::int32_t(t[i]), face + 1 + 4 * i);
        out.write(face, sizeof face);
    }
}

void detail::write_obj(const Mesh& mesh, AtomicFile& out) {
    out.write("# written by libsnvr\n");
    std::string line;  // reused so that each line costs no allocation
    for (const Vec3& v : mesh.vertices) {
        line = "v";
        for (const double x : v) {
            line += ' ';
            detail::append_number(line, x);
        }
        line += '\n';
        out.write(line);
    }
    for (const auto& t : mesh.triangles) {
        line = "f";
        for (const std::uint32_t i : t) line += ' ' + std::to_string(std::uint64_t(i) + 1);  // OBJ counts from 1
        line += '\n';
        out.write(line);
    }
}

std::unique_ptr<AtomicFile> detail::stage_mesh(const Mesh& mesh, const std::string& path) {
    const detail::MeshWriter write = detail::format_for(path, FormatUse::WriteMesh).write.mesh;
    validate_mesh(mesh, path);
    auto out = std::make_unique<AtomicFile>(path);
    write(mesh, *out);
    out->finish();
    return out;
}

void write_mesh(const Mesh& mesh, const std::string& path) { detail::stage_mesh(mesh, path)->commit(); }

}  // namespace snvr
