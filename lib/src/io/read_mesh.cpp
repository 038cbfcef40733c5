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

#include "io/io_common.hpp"
#include "io/mesh_readers.hpp"
#include "io/read_whole_file.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh_io.hpp"
#include "io/text_scan.hpp"

namespace snvr {
namespace {

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

Mesh read_stl(std::string_view data, const std::string& path) {
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

// ---- PLY

enum class Type { I8, U8, I16, U16, I32, U32, F32, F64 };

bool type_of(std::string_view name, Type& t) {
    static const std::pair<const char*, Type> names[] = {
        {"char", Type::I8},   {"int8", Type::I8},   {"uchar", Type::U8},   {"uint8", Type::U8},
        {"short", Type::I16}, {"int16", Type::I16}, {"ushort", Type::U16}, {"uint16", Type::U16},
        {"int", Type::I32},   {"int32", Type::I32}, {"uint", Type::U32},   {"uint32", Type::U32},
        {"float", Type::F32}, {"float32", Type::F32}, {"double", Type::F64}, {"float64", Type::F64}};
    for (const auto& [n, type] : names)
        if (name == n) {
            t = type;
            return true;
        }
    return false;
}

struct Property {
    std::string name;
    Type type = Type::F32;
    bool list = false;
    Type count_type = Type::U8;
};

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Property> properties;
};

std::size_t type_size(Type type) {
    static const std::size_t sizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
    return sizes[int(type)];
}

// The fewest bytes a record of e can take: its binary words (a list's count alone), or
// in text a character and a separator per value.
std::uint64_t least_record_bytes(const Element& e, bool ascii) {
    std::uint64_t bytes = 0;
    for (const Property& p : e.properties) bytes += ascii ? 2 : type_size(p.list ? p.count_type : p.type);
    return std::max<std::uint64_t>(bytes, 1);
}

// The body's values one at a time, from text tokens or binary words.
class ValueReader {
public:
    ValueReader(std::string_view body, bool ascii, bool swap) : rest_(body), ascii_(ascii), swap_(swap) {}

    // False at the end of the data (or, for text, on a token that is no number).
    bool read(Type type, double& out) {
        if (ascii_) return parse_number(next_token(rest_), out);
        const std::size_t size = type_size(type);
        if (rest_.size() < size) return false;
        const char* p = rest_.data();
        switch (type) {
            case Type::I8: out = detail::load_bytes<std::int8_t>(p, false); break;
            case Type::U8: out = detail::load_bytes<std::uint8_t>(p, false); break;
            case Type::I16: out = detail::load_bytes<std::int16_t>(p, swap_); break;
            case Type::U16: out = detail::load_bytes<std::uint16_t>(p, swap_); break;
            case Type::I32: out = detail::load_bytes<std::int32_t>(p, swap_); break;
            case Type::U32: out = detail::load_bytes<std::uint32_t>(p, swap_); break;
            case Type::F32: out = detail::load_bytes<float>(p, swap_); break;
            case Type::F64: out = detail::load_bytes<double>(p, swap_); break;
        }
        rest_.remove_prefix(size);
        return true;
    }

private:
    std::string_view rest_;
    bool ascii_, swap_;
};

Mesh read_ply(std::string_view data, const std::string& path) {
    detail::LineScanner lines(data);
    std::string_view line;
    const auto header_error = [&](const std::string& what) {
        return InputError(path + ": header line " + std::to_string(lines.line_number()) + ": " + what);
    };
    if (!lines.next(line) || line != "ply") throw InputError(path + ": not a PLY file (no 'ply' on the first line)");
    std::vector<Element> elements;
    bool ascii = false, swap = false, have_format = false, ended = false;
    while (!ended && lines.next(line)) {
        std::string_view rest = line;
        const std::string_view word = next_token(rest);
        if (word == "format") {
            const std::string_view kind = next_token(rest);
            if (kind == "ascii") ascii = true;
            else if (kind == "binary_little_endian") swap = !detail::host_is_little_endian();
            else if (kind == "binary_big_endian") swap = detail::host_is_little_endian();
            else throw header_error("unknown format " + in_quotes(kind));
            have_format = true;
        } else if (word == "element") {
            Element e;
            e.name = std::string(next_token(rest));
            if (e.name.empty() || !detail::parse_count(next_token(rest), e.count))
                throw header_error("expected 'element NAME COUNT'");
            elements.push_back(e);
        } else if (word == "property") {
            if (elements.empty()) throw header_error("property before any element");
            Property p;
            std::string_view type = next_token(rest);
            if (type == "list") {
                p.list = true;
                if (!type_of(next_token(rest), p.count_type) || !type_of(next_token(rest), p.type))
                    throw header_error("expected 'property list COUNT_TYPE TYPE NAME'");
            } else if (!type_of(type, p.type)) {
                throw header_error("unknown property type " + in_quotes(type));
            }
            p.name = std::string(next_token(rest));
            if (p.name.empty()) throw header_error("property without a name");
            elements.back().properties.push_back(p);
        } else if (word == "end_header") {
            ended = true;
        } else if (word != "comment" && word != "obj_info" && !word.empty()) {
            throw header_error("unexpected " + in_quotes(word));
        }
    }
    if (!ended) throw InputError(path + ": PLY header has no 'end_header' line");
    if (!have_format) throw InputError(path + ": PLY header has no 'format' line");

    Mesh mesh;
    const std::string_view body = data.substr(lines.offset());
    ValueReader values(body, ascii, swap);
    bool have_vertices = false, have_faces = false;
    for (const Element& e : elements) {
        // A count the file cannot hold is refused before anything is reserved for it.
        const std::uint64_t room = (body.size() + (ascii ? 1 : 0)) / least_record_bytes(e, ascii);  // text may end unterminated
        if (e.count > room)
            throw InputError(path + ": the header's element '" + e.name + "' claims " + std::to_string(e.count) +
                             " records, but the " + std::to_string(body.size()) +
                             " bytes after the header hold at most " + std::to_string(room));
        const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
        std::array<int, 3> xyz{-1, -1, -1};
        int indices = -1;
        for (std::size_t k = 0; k < e.properties.size(); ++k) {
            const Property& p = e.properties[k];
            if (is_vertex && !p.list && p.name.size() == 1 && p.name[0] >= 'x' && p.name[0] <= 'z')
                xyz[p.name[0] - 'x'] = int(k);
            if (is_face && p.list && (p.name == "vertex_indices" || p.name == "vertex_index")) indices = int(k);
        }
        if (is_vertex) {
            if (std::min({xyz[0], xyz[1], xyz[2]}) < 0) throw InputError(path + ": vertex element lacks x, y or z");
            if (e.count >= kNone) throw InputError(path + ": too many vertices (" + std::to_string(e.count) + ")");
            mesh.vertices.reserve(e.count);
            have_vertices = true;
        }
        if (is_face) {
            if (indices < 0) throw InputError(path + ": face element has no 'vertex_indices' list");
            if (!have_vertices) throw InputError(path + ": face element before the vertex element");
            mesh.triangles.reserve(e.count);
            have_faces = true;
        }
        const auto ends = [&](std::uint64_t i) {
            return InputError(path + ": " + detail::ends_early(e.count, i, e.name + " records") +
                              (ascii ? " or has a malformed value" : ""));
        };
        std::vector<std::uint32_t> polygon;
        for (std::uint64_t i = 0; i < e.count; ++i) {
            Vec3 p{0, 0, 0};
            for (std::size_t k = 0; k < e.properties.size(); ++k) {
                const Property& prop = e.properties[k];
                double value;
                if (!prop.list) {
                    if (!values.read(prop.type, value)) throw ends(i);
                    for (int d = 0; d < 3; ++d)
                        if (int(k) == xyz[d]) p[d] = value;
                    continue;
                }
                double n;
                if (!values.read(prop.count_type, n)) throw ends(i);
                if (!(n >= 0) || n != std::floor(n))
                    throw InputError(path + ": " + e.name + " " + std::to_string(i) + ": bad list length");
                polygon.clear();
                for (std::uint64_t j = 0; j < std::uint64_t(n); ++j) {
                    if (!values.read(prop.type, value)) throw ends(i);
                    if (int(k) != indices) continue;
                    if (!(value >= 0 && value < double(mesh.vertices.size())) || value != std::floor(value))
                        throw InputError(path + ": face " + std::to_string(i) + ": vertex index " +
                                         detail::format_number(value) + " out of range (" +
                                         std::to_string(mesh.vertices.size()) + " vertices)");
                    polygon.push_back(std::uint32_t(value));
                }
                if (int(k) != indices) continue;
                if (polygon.size() < 3)
                    throw InputError(path + ": face " + std::to_string(i) + " has " + std::to_string(polygon.size()) +
                                     " vertices, needs 3");
                for (std::size_t j = 1; j + 1 < polygon.size(); ++j)
                    mesh.triangles.push_back({polygon[0], polygon[j], polygon[j + 1]});
            }
            if (is_vertex) {
                if (!finite(p)) throw InputError(path + ": vertex " + std::to_string(i) + ": non-finite coordinate");
                mesh.vertices.push_back(p);
            }
        }
    }
    if (!have_vertices || !have_faces) throw InputError(path + ": PLY needs a 'vertex' and a 'face' element");
    require_triangles(mesh, path);
    return mesh;
}

// ---- OBJ

Mesh read_obj(std::string_view data, const std::string& path) {
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
Mesh read_off(std::string_view data, const std::string& path) {
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

}  // namespace

Mesh detail::parse_mesh(std::string_view data, const std::string& path) {
    const std::string ext = detail::lower_extension(detail::format_name(path));
    if (ext == ".stl") return read_stl(data, path);
    if (ext == ".ply") return read_ply(data, path);
    if (ext == ".obj") return read_obj(data, path);
    if (ext == ".off") return read_off(data, path);
    throw InputError(path + ": unsupported mesh file extension '" + ext + "' (supported: .stl, .ply, .obj, .off)");
}

bool detail::has_faces(std::string_view data, const std::string& path) {
    const std::string ext = detail::lower_extension(detail::format_name(path));
    if (ext == ".stl") return true;
    detail::LineScanner lines(data);
    std::string_view line;
    if (ext == ".ply") {  // an "element face N", N > 0, with a vertex index list, in the header
        bool in_faces = false;
        while (lines.next(line)) {
            std::string_view rest = line;
            const std::string_view key = next_token(rest);
            if (key == "end_header") return false;
            std::uint64_t n = 0;
            if (key == "element")
                in_faces = next_token(rest) == "face" && detail::parse_count(next_token(rest), n) && n > 0;
            if (in_faces && key == "property" && next_token(rest) == "list") {
                next_token(rest);
                next_token(rest);
                const std::string_view name = next_token(rest);
                if (name == "vertex_indices" || name == "vertex_index") return true;
            }
        }
        return false;
    }
    if (ext == ".obj") {  // any "f" line
        while (lines.next(line)) {
            std::string_view rest = line;
            if (next_token(rest) == "f") return true;
        }
        return false;
    }
    if (ext == ".off") {  // a face count above 0 after the header
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
    return false;
}

Mesh read_mesh(const std::string& path) {
    detail::require_regular_file(path);  // before the extension: "'dir' is a directory"
    return detail::parse_mesh(detail::read_input_bytes(path), path);
}

}  // namespace snvr
