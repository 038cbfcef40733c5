// The PLY header parser shared by the point reader, the mesh reader and the faces check.
#include "io/ply_header.hpp"

#include <algorithm>
#include <utility>

#include "io/input_source.hpp"
#include "io/io_common.hpp"
#include "io/text_scan.hpp"
#include "snvr/error.hpp"

namespace snvr::detail::ply {
namespace {

bool scalar_from_name(std::string_view name, Scalar& out) {
    static const std::pair<std::string_view, Scalar> names[] = {
        {"char", Scalar::Int8},     {"int8", Scalar::Int8},       {"uchar", Scalar::UInt8},
        {"uint8", Scalar::UInt8},   {"short", Scalar::Int16},     {"int16", Scalar::Int16},
        {"ushort", Scalar::UInt16}, {"uint16", Scalar::UInt16},   {"int", Scalar::Int32},
        {"int32", Scalar::Int32},   {"uint", Scalar::UInt32},     {"uint32", Scalar::UInt32},
        {"float", Scalar::Float32}, {"float32", Scalar::Float32}, {"double", Scalar::Float64},
        {"float64", Scalar::Float64}};
    for (const auto& [text, type] : names) {
        if (text == name) {
            out = type;
            return true;
        }
    }
    return false;
}

bool is_integer(Scalar type) { return type != Scalar::Float32 && type != Scalar::Float64; }

[[noreturn]] void header_error(const std::string& path, std::size_t line, const std::string& what) {
    throw InputError(path + ": header line " + std::to_string(line) + ": " + what);
}

Encoding parse_encoding(std::string_view name, const std::string& path, std::size_t line) {
    if (name == "ascii") return Encoding::Ascii;
    if (name == "binary_little_endian") return Encoding::BinaryLittle;
    if (name == "binary_big_endian") return Encoding::BinaryBig;
    header_error(path, line, "unknown format " + in_quotes(name) +
                                 " (expected ascii, binary_little_endian or binary_big_endian)");
}

Element parse_element(std::string_view rest, const std::string& path, std::size_t line) {
    Element element;
    element.name = std::string(next_token(rest));
    element.line = line;
    const std::string_view count = next_token(rest);
    if (element.name.empty() || !parse_count(count, element.count))
        header_error(path, line, "expected 'element <name> <count>'");
    return element;
}

Property parse_property(std::string_view rest, const std::string& path, std::size_t line) {
    Property property;
    std::string_view type = next_token(rest);
    if (type == "list") {
        property.is_list = true;
        const std::string_view count_type = next_token(rest);
        if (!scalar_from_name(count_type, property.count_type) || !is_integer(property.count_type))
            header_error(path, line, "list count type " + in_quotes(count_type) + " is not an integer type");
        type = next_token(rest);
    }
    if (!scalar_from_name(type, property.type)) header_error(path, line, "unknown property type " + in_quotes(type));
    property.name = std::string(next_token(rest));
    if (property.name.empty()) header_error(path, line, "property has no name");
    return property;
}

// Finds the vertex element and marks its x, y, z properties.
void locate_vertex(Header& header, const std::string& path) {
    const auto found = std::find_if(header.elements.begin(), header.elements.end(),
                                    [](const Element& e) { return e.name == "vertex"; });
    if (found == header.elements.end()) throw InputError(path + ": no 'vertex' element in the PLY header");
    header.vertex = std::size_t(found - header.elements.begin());
    const char* axes[] = {"x", "y", "z"};
    for (int axis = 0; axis < 3; ++axis) {
        auto& props = found->properties;
        const auto p = std::find_if(props.begin(), props.end(), [&](const Property& q) { return q.name == axes[axis]; });
        if (p == props.end()) header_error(path, found->line, "vertex element has no " + in_quotes(axes[axis]) + " property");
        if (p->is_list) header_error(path, found->line, "vertex property " + in_quotes(axes[axis]) + " is a list");
        p->axis = axis;
    }
}

}  // namespace

Header parse_header(std::string_view data, const std::string& path) {
    LineScanner lines(data);
    std::string_view line;
    std::string_view magic;
    if (lines.next(line)) magic = next_token(line);
    if (magic != "ply" || !next_token(line).empty()) header_error(path, 1, "missing 'ply' magic");
    Header header;
    bool have_format = false;
    for (;;) {
        if (!lines.next(line)) throw InputError(path + ": PLY header has no 'end_header' line");
        const std::size_t n = lines.line_number();
        const std::string_view key = next_token(line);
        if (key == "end_header") break;
        if (key == "format") {
            header.encoding = parse_encoding(next_token(line), path, n);
            have_format = true;
        } else if (key == "element") {
            header.elements.push_back(parse_element(line, path, n));
        } else if (key == "property") {
            if (header.elements.empty()) header_error(path, n, "property before any element");
            header.elements.back().properties.push_back(parse_property(line, path, n));
        } else if (!key.empty() && key != "comment" && key != "obj_info") {
            header_error(path, n, "unexpected keyword " + in_quotes(key));
        }
    }
    if (!have_format) header_error(path, lines.line_number(), "no 'format' line before end_header");
    header.data_offset = lines.offset();
    header.lines = lines.line_number();
    locate_vertex(header, path);
    return header;
}

Header read_header(InputSource& source, const std::string& path) {
    constexpr std::size_t kHead = std::size_t(64) << 10;
    if (source.size() > kHead) {
        std::string_view head = source.head(kHead);
        head = head.substr(0, head.rfind('\n') + 1);  // whole lines (none: empty)
        try {
            return parse_header(head, path);  // parsed line by line up to end_header: as from the whole
        } catch (const InputError&) {
            // A header longer than the head, or a wrong one: the whole file says which.
        }
    }
    return parse_header(source.all(), path);
}

const Property* face_indices(const Element& face) {
    for (const Property& p : face.properties)
        if (p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index")) return &p;
    return nullptr;
}

bool has_faces(const Header& header) {
    return std::any_of(header.elements.begin(), header.elements.end(), [](const Element& e) {
        return e.name == "face" && e.count > 0 && face_indices(e) != nullptr;
    });
}

}  // namespace snvr::detail::ply
