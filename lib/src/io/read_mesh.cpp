// read_mesh: triangle meshes written by other programs, to thicken them or to compare
// them with ours. STL (binary or ASCII; corners welded where their coordinates are
// equal), PLY (ASCII or binary, any byte order, vertex x/y/z and a face index list),
// OBJ ("v" and "f" lines) and OFF. Polygons are cut into fans of triangles.
#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "io/formats.hpp"
#include "io/io_common.hpp"
#include "io/mesh_readers.hpp"
#include "io/ply_header.hpp"
#include "io/input_source.hpp"
#include "io/text_scan.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh_io.hpp"

namespace snvr {
namespace {

namespace ply = detail::ply;
using detail::in_quotes;
using detail::next_token;
using detail::parse_number;
constexpr std::uint32_t kNone = std::uint32_t(-1);

// Gives equal coordinate triples one shared vertex: open addressing on the bits
// of the three doubles (-0 counts as 0), growing to stay at most half full.
class Welder {
public:
    explicit Welder(std::vector<Vec3>& vertices) : vertices_(vertices) { slots_.assign(1024, kNone); }

    std::uint32_t index(Vec3 p) {
        for (double& x : p) x += 0.0;  // -0 + 0 = +0
        if (2 * (vertices_.size() + 1) > slots_.size()) grow();
        for (std::size_t s = hash(p) & (slots_.size() - 1);; s = (s + 1) & (slots_.size() - 1)) {
            if (slots_[s] == kNone) {
                slots_[s] = std::uint32_t(vertices_.size());
                vertices_.push_back(p);
                return slots_[s];
            }
            if (vertices_[slots_[s]] == p) return slots_[s];
        }
    }

private:
    static std::uint64_t hash(const Vec3& p) {
        std::uint64_t h = 0x9e3779b97f4a7c15ull;
        for (double x : p) {
            std::uint64_t bits;
            std::memcpy(&bits, &x, sizeof bits);
            h = (h ^ bits) * 0xbf58476d1ce4e5b9ull;  // splitmix64-style mixing
            h ^= h >> 31;
        }
        return h;
    }
    void grow() {
        slots_.assign(2 * slots_.size(), kNone);
        for (std::uint32_t v = 0; v < vertices_.size(); ++v) {
            std::size_t s = hash(vertices_[v]) & (slots_.size() - 1);
            while (slots_[s] != kNone) s = (s + 1) & (slots_.size() - 1);
            slots_[s] = v;
        }
    }

    std::vector<Vec3>& vertices_;
    std::vector<std::uint32_t> slots_;
};

bool finite(const Vec3& p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

void require_triangles(const Mesh& mesh, const std::string& path) {
    if (mesh.triangles.empty()) throw InputError(path + ": no triangles");
}

// ---- STL

Mesh read_binary_stl(std::string_view data, const std::string& path) {
    const auto n = detail::load_bytes<std::uint32_t>(data.data() + 80, !detail::host_is_little_endian());
    Mesh mesh;
    mesh.triangles.resize(n);
    Welder weld(mesh.vertices);
    for (std::uint32_t t = 0; t < n; ++t) {
        const char* record = data.data() + 84 + 50 * std::size_t(t);
        for (int c = 0; c < 3; ++c) {
            Vec3 p;
            for (int d = 0; d < 3; ++d)
                p[d] = detail::load_bytes<float>(record + 12 + 12 * c + 4 * d, !detail::host_is_little_endian());
            if (!finite(p)) throw InputError(path + ": triangle " + std::to_string(t) + ": non-finite coordinate");
            mesh.triangles[t][c] = weld.index(p);
        }
    }
    return mesh;
}

Mesh read_ascii_stl(std::string_view data, const std::string& path) {
    Mesh mesh;
    Welder weld(mesh.vertices);
    detail::LineScanner lines(data);
    std::string_view line;
    std::vector<std::uint32_t> loop;
    bool in_loop = false, in_facet = false;
    const auto fail = [&](const std::string& what) -> InputError {
        return InputError(path + ": line " + std::to_string(lines.line_number()) + ": " + what);
    };
    while (lines.next(line)) {
        std::string_view rest = line;
        const std::string_view word = next_token(rest);
        if (word == "vertex") {
            if (!in_loop) throw fail("'vertex' outside 'outer loop'");
            Vec3 p;
            for (double& x : p)
                if (!parse_number(next_token(rest), x)) throw fail("expected three numbers after 'vertex'");
            if (!finite(p)) throw fail("non-finite coordinate");
            loop.push_back(weld.index(p));
        } else if (word == "outer") {
            if (in_loop) throw fail("'outer loop' inside another loop");
            in_loop = true;
            loop.clear();
        } else if (word == "endloop") {
            if (!in_loop) throw fail("'endloop' without 'outer loop'");
            if (loop.size() < 3) throw fail("a facet needs 3 vertices, this one has " + std::to_string(loop.size()));
            for (std::size_t k = 1; k + 1 < loop.size(); ++k) mesh.triangles.push_back({loop[0], loop[k], loop[k + 1]});
            in_loop = false;
        } else if (word == "facet") {
            if (in_facet) throw fail("'facet' inside another facet (the one before has no 'endfacet')");
            in_facet = true;
        } else if (word == "endfacet") {
            if (!in_facet) throw fail("'endfacet' without 'facet'");
            if (in_loop) throw fail("'endfacet' inside 'outer loop'");
            in_facet = false;
        } else if (word != "solid" && word != "endsolid" && !word.empty()) {
            throw fail("unexpected " + in_quotes(word.substr(0, 40)) + " in ASCII STL");
        }
    }
    // A file cut short mostly ends inside a facet: the last one would be half read.
    if (in_loop || in_facet) throw InputError(path + ": file ends inside a facet (no 'endfacet'): cut short?");
    require_triangles(mesh, path);
    return mesh;
}

}  // namespace

Mesh detail::read_stl_mesh(std::string_view data, const std::string& path) {
    if (data.size() >= 84) {
        const auto n = detail::load_bytes<std::uint32_t>(data.data() + 80, !detail::host_is_little_endian());
        const std::uint64_t expected = 84 + 50 * std::uint64_t(n);
        if (data.size() == expected) {
            Mesh mesh = read_binary_stl(data, path);
            require_triangles(mesh, path);
            return mesh;
        }
        // A binary header may begin with "solid" too, but text has no NUL bytes.
        const std::string_view head = data.substr(0, 1024);
        const bool text = data.substr(0, 5) == "solid" && head.find('\0') == std::string_view::npos;
        if (!text)
            throw InputError(path + ": binary STL of " + std::to_string(n) + " triangles should have " +
                             std::to_string(expected) + " bytes, the file has " + std::to_string(data.size()) +
                             (data.size() < expected ? " (truncated)" : ""));
    } else if (data.substr(0, 5) != "solid") {
        throw InputError(path + ": " + std::to_string(data.size()) +
                         " bytes: too short for a binary STL and not ASCII STL (no 'solid')");
    }
    return read_ascii_stl(data, path);
}

namespace {

// ---- PLY

// The fewest bytes a record of e can take: its binary words (a list's count alone), or
// in text a character and a separator per value.
std::uint64_t least_record_bytes(const ply::Element& e, bool ascii) {
    std::uint64_t bytes = 0;
    for (const ply::Property& p : e.properties) bytes += ascii ? 2 : ply::scalar_size(p.is_list ? p.count_type : p.type);
    return std::max<std::uint64_t>(bytes, 1);
}

// The body's values one at a time, from text tokens or binary words.
class ValueReader {
public:
    ValueReader(std::string_view body, bool ascii, bool swap) : rest_(body), ascii_(ascii), swap_(swap) {}

    // False at the end of the data (or, for text, on a token that is no number).
    bool read(ply::Scalar type, double& out) {
        if (ascii_) return parse_number(next_token(rest_), out);
        const std::size_t size = ply::scalar_size(type);
        if (rest_.size() < size) return false;
        out = ply::load_scalar(type, rest_.data(), swap_);
        rest_.remove_prefix(size);
        return true;
    }

private:
    std::string_view rest_;
    bool ascii_, swap_;
};

// A PLY mesh, its elements read in file order: the vertices' x, y, z and the faces'
// index lists, every other value skipped.
class PlyMeshReader {
public:
    PlyMeshReader(std::string_view data, const std::string& path)
        : header_(ply::parse_header(data, path)),
          ascii_(header_.encoding == ply::Encoding::Ascii),
          body_(data.substr(header_.data_offset)),
          values_(body_, ascii_, !ascii_ && (header_.encoding == ply::Encoding::BinaryLittle) != detail::host_is_little_endian()),
          path_(path) {}

    Mesh read() {
        for (const ply::Element& e : header_.elements) {
            require_room(e);
            const ply::Property* indices = start(e);
            const bool is_vertex = &e == &header_.elements[header_.vertex];
            for (std::uint64_t i = 0; i < e.count; ++i) read_record(e, is_vertex, indices, i);
        }
        if (!have_vertices_ || !have_faces_) throw InputError(path_ + ": PLY needs a 'vertex' and a 'face' element");
        require_triangles(mesh_, path_);
        return std::move(mesh_);
    }

private:
    // A count the file cannot hold is refused before anything is reserved for it.
    void require_room(const ply::Element& e) const {
        const std::uint64_t room = (body_.size() + (ascii_ ? 1 : 0)) / least_record_bytes(e, ascii_);  // text may end unterminated
        if (e.count > room)
            throw InputError(path_ + ": the header's element '" + e.name + "' claims " + std::to_string(e.count) +
                             " records, but the " + std::to_string(body_.size()) +
                             " bytes after the header hold at most " + std::to_string(room));
    }

    // Checks and reserves for the vertex or face element; the face's index list, if it is that.
    const ply::Property* start(const ply::Element& e) {
        if (e.name == "vertex") {
            if (e.count >= kNone) throw InputError(path_ + ": too many vertices (" + std::to_string(e.count) + ")");
            mesh_.vertices.reserve(e.count);
            have_vertices_ = true;
        }
        if (e.name != "face") return nullptr;
        const ply::Property* indices = ply::face_indices(e);
        if (!indices) throw InputError(path_ + ": face element has no 'vertex_indices' list");
        if (!have_vertices_) throw InputError(path_ + ": face element before the vertex element");
        mesh_.triangles.reserve(e.count);
        have_faces_ = true;
        return indices;
    }

    InputError ends(const ply::Element& e, std::uint64_t i) const {
        return InputError(path_ + ": " + detail::ends_early(e.count, i, e.name + " records") +
                          (ascii_ ? " or has a malformed value" : ""));
    }

    void read_record(const ply::Element& e, bool is_vertex, const ply::Property* indices, std::uint64_t i) {
        Vec3 p{0, 0, 0};
        for (const ply::Property& prop : e.properties) {
            double value;
            if (prop.is_list) {
                read_list(e, prop, &prop == indices, i);
                continue;
            }
            if (!values_.read(prop.type, value)) throw ends(e, i);
            if (is_vertex && prop.axis >= 0) p[std::size_t(prop.axis)] = value;
        }
        if (!is_vertex) return;
        if (!finite(p)) throw InputError(path_ + ": vertex " + std::to_string(i) + ": non-finite coordinate");
        mesh_.vertices.push_back(p);
    }

    // A list's values; a face's index list becomes a fan of triangles.
    void read_list(const ply::Element& e, const ply::Property& prop, bool is_indices, std::uint64_t i) {
        double n, value;
        if (!values_.read(prop.count_type, n)) throw ends(e, i);
        if (!(n >= 0) || n != std::floor(n))
            throw InputError(path_ + ": " + e.name + " " + std::to_string(i) + ": bad list length");
        polygon_.clear();
        for (std::uint64_t j = 0; j < std::uint64_t(n); ++j) {
            if (!values_.read(prop.type, value)) throw ends(e, i);
            if (!is_indices) continue;
            if (!(value >= 0 && value < double(mesh_.vertices.size())) || value != std::floor(value))
                throw InputError(path_ + ": face " + std::to_string(i) + ": vertex index " + detail::format_number(value) +
                                 " out of range (" + std::to_string(mesh_.vertices.size()) + " vertices)");
            polygon_.push_back(std::uint32_t(value));
        }
        if (!is_indices) return;
        if (polygon_.size() < 3)
            throw InputError(path_ + ": face " + std::to_string(i) + " has " + std::to_string(polygon_.size()) +
                             " vertices, needs 3");
        for (std::size_t j = 1; j + 1 < polygon_.size(); ++j)
            mesh_.triangles.push_back({polygon_[0], polygon_[j], polygon_[j + 1]});
    }

    const ply::Header header_;
    const bool ascii_;
    const std::string_view body_;
    ValueReader values_;
    const std::string& path_;
    Mesh mesh_;
    std::vector<std::uint32_t> polygon_;
    bool have_vertices_ = false, have_faces_ = false;
};

}  // namespace

Mesh detail::read_ply_mesh(std::string_view data, const std::string& path) { return PlyMeshReader(data, path).read(); }

bool detail::ply_has_faces(InputSource& source, const std::string& path) {
    return ply::has_faces(ply::read_header(source, path));
}

// ---- OBJ

Mesh detail::read_obj_mesh(std::string_view data, const std::string& path) {
    Mesh mesh;
    detail::LineScanner lines(data);
    std::string_view line;
    std::vector<std::uint32_t> polygon;
    const auto fail = [&](const std::string& what) {
        return InputError(path + ": line " + std::to_string(lines.line_number()) + ": " + what);
    };
    while (lines.next(line)) {
        std::string_view rest = detail::strip_comment(line);
        const std::string_view word = next_token(rest);
        if (word == "v") {
            Vec3 p;
            for (double& x : p)
                if (!parse_number(next_token(rest), x)) throw fail("expected three numbers after 'v'");
            if (!finite(p)) throw fail("non-finite coordinate");
            if (mesh.vertices.size() >= kNone) throw fail("too many vertices");
            mesh.vertices.push_back(p);
        } else if (word == "f") {
            polygon.clear();
            for (std::string_view token = next_token(rest); !token.empty(); token = next_token(rest)) {
                const std::string_view first = token.substr(0, token.find('/'));  // "i/t/n": the vertex is i
                double i;
                if (!parse_number(first, i) || i != std::floor(i) || i == 0)
                    throw fail("bad vertex reference " + in_quotes(token));
                const double n = double(mesh.vertices.size());
                const double index = i > 0 ? i - 1 : n + i;  // negative: counted back from the last vertex
                if (!(index >= 0 && index < n))
                    throw fail("vertex " + in_quotes(token) + " out of range (" + std::to_string(mesh.vertices.size()) +
                               " vertices so far)");
                polygon.push_back(std::uint32_t(index));
            }
            if (polygon.size() < 3) throw fail("a face needs 3 vertices, this one has " + std::to_string(polygon.size()));
            for (std::size_t j = 1; j + 1 < polygon.size(); ++j)
                mesh.triangles.push_back({polygon[0], polygon[j], polygon[j + 1]});
        }
        // Normals, texture coordinates, groups and materials do not matter here.
    }
    require_triangles(mesh, path);
    return mesh;
}

// ---- OFF

// "OFF" (or COFF, NOFF, ...), the counts, the vertices, then "k i1 .. ik" per face.
Mesh detail::read_off_mesh(std::string_view data, const std::string& path) {
    detail::LineScanner lines(data);
    std::string_view line;
    const auto fail = [&](const std::string& what) {
        return InputError(path + ": line " + std::to_string(lines.line_number()) + ": " + what);
    };
    const auto blank = [](std::string_view text) { return next_token(text).empty(); };
    const auto next_line = [&](const char* what) {
        do {
            if (!lines.next(line)) throw fail(std::string("file ends before ") + what);
            line = detail::strip_comment(line);
        } while (blank(line));
    };
    next_line("the 'OFF' header");
    std::string_view rest = line, word = next_token(rest);
    if (word.size() < 3 || word.substr(word.size() - 3) != "OFF") throw fail("missing 'OFF' header");
    if (blank(rest)) {
        next_line("the counts");
        rest = line;
    }
    std::uint64_t nv = 0, nf = 0;
    if (!detail::parse_count(next_token(rest), nv) || !detail::parse_count(next_token(rest), nf))
        throw fail("expected the vertex and face counts");
    Mesh mesh;
    mesh.vertices.reserve(std::size_t(std::min<std::uint64_t>(nv, data.size() / 6)));
    for (std::uint64_t v = 0; v < nv; ++v) {
        next_line("every vertex");
        rest = line;
        Vec3 p{};
        for (double& x : p)
            if (!parse_number(next_token(rest), x)) throw fail("expected x y z of vertex " + std::to_string(v));
        mesh.vertices.push_back(p);
    }
    std::vector<std::uint32_t> polygon;
    for (std::uint64_t f = 0; f < nf; ++f) {
        next_line("every face");
        rest = line;
        std::uint64_t k = 0;
        if (!detail::parse_count(next_token(rest), k) || k > rest.size()) throw fail("bad corner count");
        polygon.clear();
        for (std::uint64_t c = 0; c < k; ++c) {
            std::uint64_t i = 0;
            if (!detail::parse_count(next_token(rest), i) || i >= nv)
                throw fail("face " + std::to_string(f) + ": expected vertex indices below " + std::to_string(nv));
            polygon.push_back(std::uint32_t(i));
        }
        for (std::size_t j = 1; j + 1 < polygon.size(); ++j) mesh.triangles.push_back({polygon[0], polygon[j], polygon[j + 1]});
    }
    require_triangles(mesh, path);
    return mesh;
}

bool detail::obj_has_faces(InputSource& source, const std::string&) {  // any "f" line
    detail::LineScanner lines(source.all());
    std::string_view line;
    while (lines.next(line)) {
        std::string_view rest = line;
        if (next_token(rest) == "f") return true;
    }
    return false;
}

bool detail::off_has_faces(InputSource& source, const std::string&) {  // a face count above 0 after the header
    detail::LineScanner lines(source.all());
    std::string_view line;
    std::string_view tokens[4];
    std::size_t n = 0;
    while (n < 3 && lines.next(line)) {
        std::string_view rest = detail::strip_comment(line);
        for (std::string_view t = next_token(rest); !t.empty() && n < 4; t = next_token(rest)) tokens[n++] = t;
    }
    // A count that is not one (-1, garbage) goes to the mesh reader, which names it.
    std::uint64_t faces = 0;
    return n >= 3 && (!detail::parse_count(tokens[2], faces) || faces > 0);
}

Mesh detail::parse_mesh(std::string_view data, const std::string& path) {
    return format_for(path, FormatUse::ReadMesh).read.mesh(data, path);
}

Mesh read_mesh(const std::string& path) {
    detail::require_regular_file(path);  // before the extension: "'dir' is a directory"
    detail::InputSource source(path);
    return detail::parse_mesh(source.all(), path);
}

}  // namespace snvr
