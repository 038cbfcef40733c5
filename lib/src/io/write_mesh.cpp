// write_mesh: binary STL, binary little endian PLY and OBJ as their parts come (whole, or a
// slab at a time), 3MF whole; each streamed through an AtomicFile so a failure never
// leaves a half-written mesh.
#include <algorithm>
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

// Each triangle of `part` (the mesh's from `first_triangle`) names a vertex of the mesh.
void require_vertices(const MeshPart& part, std::uint64_t vertices, std::uint64_t first_triangle,
                      const std::string& path) {
    for (std::size_t t = 0; t < part.triangle_count; ++t)
        for (const std::uint32_t v : part.triangles[t])
            if (v >= vertices)
                throw InputError(path + ": triangle " + std::to_string(first_triangle + t) + " uses vertex " +
                                 std::to_string(v) + " but the mesh has " + std::to_string(vertices) + " vertices");
}

// What every mesh writer checks as the parts come: a mesh with triangles, each naming
// vertices the mesh has, and the parts' vertices in order, all of them.
class WritingSink : public MeshSink {
public:
    explicit WritingSink(AtomicFile& out) : out_(out) {}
    void begin(std::uint64_t vertices, std::uint64_t triangles) final {
        if (!triangles) throw InputError(out_.target() + ": mesh has no triangles");
        vertices_ = vertices;
        head(vertices, triangles);
    }
    void vertices(const MeshPart& part) final {
        if (part.first_vertex != next_vertex_ || next_vertex_ + part.vertex_count > vertices_)
            throw InputError(out_.target() + ": a part's vertices are not the mesh's next ones");
        next_vertex_ += part.vertex_count;
        write_vertices(part);
    }
    void triangles(const MeshPart& part) final {
        require_vertices(part, vertices_, next_triangle_, out_.target());
        write_triangles(part);
        next_triangle_ += part.triangle_count;
    }
    void finish() final {}

protected:
    virtual void head(std::uint64_t vertices, std::uint64_t triangles) = 0;
    virtual void write_vertices(const MeshPart&) {}
    virtual void write_triangles(const MeshPart& part) = 0;
    AtomicFile& out_;

private:
    std::uint64_t vertices_ = 0, next_vertex_ = 0, next_triangle_ = 0;
};

class StlSink final : public WritingSink {
public:
    using WritingSink::WritingSink;
    bool wants_corners() const override { return true; }

private:
    void head(std::uint64_t, std::uint64_t triangles) override {
        if (triangles > std::numeric_limits<std::uint32_t>::max())
            throw InputError(out_.target() + ": too many triangles for binary STL");
        // The header must not begin with "solid", or readers take the file for ASCII STL.
        char header[80] = {};
        const std::string label = "binary STL written by libsnvr";
        label.copy(header, label.size());
        out_.write(header, sizeof header);
        char count[4];
        detail::store_le(std::uint32_t(triangles), count);
        out_.write(count, sizeof count);
    }
    void write_triangles(const MeshPart& part) override {
        char record[50] = {};  // normal, 3 vertices, then a zero attribute word
        for (std::size_t k = 0; k < part.triangle_count; ++k) {
            const auto& t = part.triangles[k];
            const Vec3 &a = part.position(t[0]), &b = part.position(t[1]), &c = part.position(t[2]);
            store_vec3_f32(triangle_normal(a, b, c), record);
            store_vec3_f32(a, record + 12);
            store_vec3_f32(b, record + 24);
            store_vec3_f32(c, record + 36);
            out_.write(record, sizeof record);
        }
    }
};

class PlySink final : public WritingSink {
public:
    using WritingSink::WritingSink;
    bool wants_corners() const override { return false; }

private:
    void head(std::uint64_t vertices, std::uint64_t triangles) override {
        if (vertices > std::uint64_t(std::numeric_limits<std::int32_t>::max()))
            throw InputError(out_.target() + ": too many vertices for PLY 'int' vertex indices");
        out_.write("ply\nformat binary_little_endian 1.0\ncomment written by libsnvr\nelement vertex " +
                   std::to_string(vertices) +
                   "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                   std::to_string(triangles) + "\nproperty list uchar int vertex_indices\nend_header\n");
    }
    void write_vertices(const MeshPart& part) override {
        char vertex[12];
        for (std::size_t k = 0; k < part.vertex_count; ++k) {
            store_vec3_f32(part.vertices[k], vertex);
            out_.write(vertex, sizeof vertex);
        }
    }
    void write_triangles(const MeshPart& part) override {
        char face[13] = {3};  // list length, then three int32 indices
        for (std::size_t k = 0; k < part.triangle_count; ++k) {
            for (std::size_t i = 0; i < 3; ++i) detail::store_le(std::int32_t(part.triangles[k][i]), face + 1 + 4 * i);
            out_.write(face, sizeof face);
        }
    }
};

class ObjSink final : public WritingSink {
public:
    using WritingSink::WritingSink;
    bool wants_corners() const override { return false; }

private:
    void head(std::uint64_t, std::uint64_t) override { out_.write("# written by libsnvr\n"); }
    void write_vertices(const MeshPart& part) override {
        for (std::size_t k = 0; k < part.vertex_count; ++k) {
            line_ = "v";
            for (const double x : part.vertices[k]) {
                line_ += ' ';
                detail::append_number(line_, x);
            }
            line_ += '\n';
            out_.write(line_);
        }
    }
    void write_triangles(const MeshPart& part) override {
        for (std::size_t k = 0; k < part.triangle_count; ++k) {
            line_ = "f";
            for (const std::uint32_t i : part.triangles[k]) line_ += ' ' + std::to_string(std::uint64_t(i) + 1);  // OBJ counts from 1
            line_ += '\n';
            out_.write(line_);
        }
    }
    std::string line_;  // reused so that each line costs no allocation
};

MeshPart whole_part(const Mesh& mesh) {
    MeshPart whole;
    whole.vertices = mesh.vertices.data();
    whole.vertex_count = mesh.vertices.size();
    whole.triangles = mesh.triangles.data();
    whole.triangle_count = mesh.triangles.size();
    return whole;
}

}  // namespace

const Vec3& MeshPart::position(std::uint32_t v) const {
    if (v >= first_vertex && v - first_vertex < vertex_count) return vertices[v - first_vertex];
    const std::uint32_t* at = std::lower_bound(foreign, foreign + foreign_count, v);
    if (at == foreign + foreign_count || *at != v)
        throw InputError("a mesh part's triangle uses vertex " + std::to_string(v) + ", neither its own nor given");
    return foreign_at[at - foreign];
}

void hand_mesh(const Mesh& mesh, MeshSink& sink) {
    const MeshPart whole = whole_part(mesh);
    sink.begin(mesh.vertices.size(), mesh.triangles.size());
    if (!sink.wants_corners()) sink.vertices(whole);
    sink.triangles(whole);
    sink.finish();
}

std::unique_ptr<MeshSink> detail::stl_sink(AtomicFile& out) { return std::make_unique<StlSink>(out); }
std::unique_ptr<MeshSink> detail::ply_sink(AtomicFile& out) { return std::make_unique<PlySink>(out); }
std::unique_ptr<MeshSink> detail::obj_sink(AtomicFile& out) { return std::make_unique<ObjSink>(out); }

std::unique_ptr<AtomicFile> detail::stage_mesh(const Mesh& mesh, const std::string& path) {
    const detail::Writing& write = detail::format_for(path, FormatUse::WriteMesh).write;
    auto out = std::make_unique<AtomicFile>(path);
    if (write.parts) {
        hand_mesh(mesh, *write.parts(*out));
    } else {
        if (mesh.triangles.empty()) throw InputError(path + ": mesh has no triangles");
        require_vertices(whole_part(mesh), mesh.vertices.size(), 0, path);
        write.mesh(mesh, *out);
    }
    out->finish();
    return out;
}

void write_mesh(const Mesh& mesh, const std::string& path) { detail::stage_mesh(mesh, path)->commit(); }

}  // namespace snvr
