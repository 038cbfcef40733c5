// PLY point reader: parses the header into elements and properties, then walks
// the data section (ASCII, or binary in either byte order) up to and including
// the vertex element, taking x, y and z from wherever they sit among the
// vertex properties. Elements after the vertices are never read. Vertex records
// of fixed size are split between threads, ASCII lines parsed by parse_lines.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "io/float_origin.hpp"
#include "io/io_common.hpp"
#include "io/parallel_lines.hpp"
#include "io/parallel_records.hpp"
#include "io/point_readers.hpp"
#include "io/text_scan.hpp"
#include "snvr/error.hpp"

namespace snvr::detail {
namespace {

enum class Scalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };
enum class Format { Ascii, BinaryLittle, BinaryBig };

struct Property {
    std::string name;
    Scalar type = Scalar::Float32;  // of the items, for a list
    bool is_list = false;
    Scalar count_type = Scalar::UInt8;
    int axis = -1;  // 0, 1, 2 for the vertex x, y, z
};

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::size_t line = 0;  // header line that declared it
    std::vector<Property> properties;
};

struct Header {
    Format format = Format::Ascii;
    std::vector<Element> elements;
    std::size_t vertex = 0;       // index of the vertex element
    std::size_t data_offset = 0;  // first byte after "end_header\n"
    std::size_t lines = 0;        // header lines, so data lines are numbered as in the file
};

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

std::size_t scalar_size(Scalar type) {
    switch (type) {
        case Scalar::Int8: case Scalar::UInt8: return 1;
        case Scalar::Int16: case Scalar::UInt16: return 2;
        case Scalar::Int32: case Scalar::UInt32: case Scalar::Float32: return 4;
        case Scalar::Float64: return 8;
    }
    return 0;
}

bool is_integer(Scalar type) { return type != Scalar::Float32 && type != Scalar::Float64; }

double load_scalar(Scalar type, const char* p, bool swap) {
    switch (type) {
        case Scalar::Int8: return load_bytes<std::int8_t>(p, swap);
        case Scalar::UInt8: return load_bytes<std::uint8_t>(p, swap);
        case Scalar::Int16: return load_bytes<std::int16_t>(p, swap);
        case Scalar::UInt16: return load_bytes<std::uint16_t>(p, swap);
        case Scalar::Int32: return load_bytes<std::int32_t>(p, swap);
        case Scalar::UInt32: return load_bytes<std::uint32_t>(p, swap);
        case Scalar::Float32: return load_bytes<float>(p, swap);
        case Scalar::Float64: return load_bytes<double>(p, swap);
    }
    return 0;
}

std::string item_noun(const Element& element) {
    return element.name == "vertex" ? std::string("vertices") : in_quotes(element.name) + " items";
}

// ---- header ----

[[noreturn]] void header_error(const std::string& path, std::size_t line, const std::string& what) {
    throw InputError(path + ": header line " + std::to_string(line) + ": " + what);
}

Format parse_format(std::string_view name, const std::string& path, std::size_t line) {
    if (name == "ascii") return Format::Ascii;
    if (name == "binary_little_endian") return Format::BinaryLittle;
    if (name == "binary_big_endian") return Format::BinaryBig;
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
            header.format = parse_format(next_token(line), path, n);
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

// Never reserve more than the remaining bytes could hold: the count is untrusted.
std::size_t plausible_count(std::uint64_t count, std::size_t bytes_left) {
    return std::size_t(std::min<std::uint64_t>(count, bytes_left / 3));
}

// Coordinates of these types are floats already: held exactly with origin 0.
bool exact_in_float(Scalar type) {
    return type != Scalar::Float64 && type != Scalar::Int32 && type != Scalar::UInt32;
}

bool exact_in_float(const Element& vertex) {
    for (const Property& p : vertex.properties)
        if (p.axis >= 0 && !exact_in_float(p.type)) return false;
    return true;
}

// ---- binary data ----

// Bounds-checked walk over the binary data section.
class BinaryReader {
public:
    BinaryReader(std::string_view data, std::size_t offset, bool swap, const std::string& path)
        : data_(data), pos_(offset), swap_(swap), path_(path) {}

    // Reads one item, storing its x, y, z (if any) in xyz; false if the data ends first.
    bool read_item(const Element& element, Vec3& xyz) {
        for (const Property& p : element.properties) {
            const char* at = nullptr;
            if (p.is_list) {
                if (!take(scalar_size(p.count_type), at)) return false;
                const double count = load_scalar(p.count_type, at, swap_);
                if (count < 0)
                    throw InputError(path_ + ": negative list length at byte offset " + std::to_string(pos_));
                if (!take(std::size_t(count) * scalar_size(p.type), at)) return false;
            } else {
                if (!take(scalar_size(p.type), at)) return false;
                if (p.axis >= 0) xyz[std::size_t(p.axis)] = load_scalar(p.type, at, swap_);
            }
        }
        return true;
    }
    std::size_t offset() const { return pos_; }
    std::size_t bytes_left() const { return data_.size() - pos_; }
    void skip(std::size_t bytes) { pos_ += bytes; }

private:
    bool take(std::size_t size, const char*& at) {
        if (data_.size() - pos_ < size) return false;
        at = data_.data() + pos_;
        pos_ += size;
        return true;
    }

    std::string_view data_;
    std::size_t pos_;
    bool swap_;
    const std::string& path_;
};

// Bytes per item of an element without lists (false if it has one).
bool fixed_item_size(const Element& element, std::size_t& size) {
    size = 0;
    for (const Property& p : element.properties) {
        if (p.is_list) return false;
        size += scalar_size(p.type);
    }
    return true;
}

// Where x, y and z sit in a vertex record of fixed size: records decode directly.
struct FixedVertex {
    const char* first = nullptr;  // the first record
    std::size_t size = 0;
    std::size_t at[3] = {};
    Scalar type[3] = {};
    bool swap = false;

    FixedVertex(const Element& vertex, const char* records, std::size_t record_size, bool swap_bytes)
        : first(records), size(record_size), swap(swap_bytes) {
        std::size_t offset = 0;
        for (const Property& p : vertex.properties) {
            if (p.axis >= 0) {
                at[p.axis] = offset;
                type[p.axis] = p.type;
            }
            offset += scalar_size(p.type);
        }
    }
    Vec3 operator()(std::size_t i) const {
        const char* record = first + i * size;
        return {load_scalar(type[0], record + at[0], swap), load_scalar(type[1], record + at[1], swap),
                load_scalar(type[2], record + at[2], swap)};
    }
};

[[noreturn]] void binary_ends(const std::string& path, const Element& element, std::uint64_t got, std::size_t offset) {
    throw InputError(path + ": " + ends_early(element.count, got, item_noun(element)) + " (byte offset " +
                     std::to_string(offset) + ")");
}

// The vertices as fixed-size records, split between threads.
FloatPoints read_fixed_vertices(const Element& vertex, std::size_t size, BinaryReader& in, std::string_view data,
                                bool swap, const std::string& path, const ParseOptions& options) {
    const std::uint64_t fit = in.bytes_left() / size;
    if (fit < vertex.count) {
        // The offset where an item by item walk stops: after the last whole property.
        std::size_t left = in.bytes_left() - std::size_t(fit) * size, offset = in.offset() + std::size_t(fit) * size;
        for (const Property& p : vertex.properties) {
            if (left < scalar_size(p.type)) break;
            left -= scalar_size(p.type);
            offset += scalar_size(p.type);
        }
        binary_ends(path, vertex, fit, offset);
    }
    const std::size_t count = std::size_t(vertex.count);
    const FixedVertex decode(vertex, data.data() + in.offset(), size, swap);
    FloatPoints points;
    if (!exact_in_float(vertex)) points.origin = choose_origin(sample_records(count, decode, options.origin_sample));
    const ConvertedRecords done = convert_records(count, decode, points.origin, points.xyz, options.threads);
    if (done.first_refused < count) refuse_point(path, done.first_refused, decode(done.first_refused), points.origin);
    return points;
}

// The vertices item by item, where lists make their sizes vary.
FloatPoints read_listed_vertices(const Element& vertex, BinaryReader& in, std::size_t data_size,
                                 const std::string& path, const ParseOptions& options) {
    FloatPoints points;
    if (!exact_in_float(vertex)) {
        BinaryReader ahead = in;
        SampleBox sample;
        Vec3 xyz{};
        for (std::uint64_t i = 0; i < std::min<std::uint64_t>(vertex.count, options.origin_sample); ++i) {
            if (!ahead.read_item(vertex, xyz)) break;  // reported below, in order
            sample.add(xyz);
        }
        points.origin = choose_origin(sample);
    }
    points.xyz.reserve(plausible_count(vertex.count, data_size));
    std::uint64_t refused = vertex.count;
    Vec3 refused_point{};
    Vec3 xyz{};
    for (std::uint64_t i = 0; i < vertex.count; ++i) {
        if (!in.read_item(vertex, xyz)) binary_ends(path, vertex, i, in.offset());
        Float3 q;
        if (!to_float(xyz, points.origin, q) && refused == vertex.count) {
            refused = i;
            refused_point = xyz;
        }
        points.xyz.push_back(q);
    }
    if (refused < vertex.count) refuse_point(path, refused, refused_point, points.origin);
    return points;
}

FloatPoints read_binary(const Header& header, std::string_view data, const std::string& path,
                        const ParseOptions& options) {
    const bool file_little = header.format == Format::BinaryLittle;
    const bool swap = file_little != host_is_little_endian();
    BinaryReader in(data, header.data_offset, swap, path);
    for (std::size_t e = 0; e < header.vertex; ++e) {
        const Element& element = header.elements[e];
        std::size_t size = 0;
        if (fixed_item_size(element, size)) {
            // Skipped in one step: a loop over a huge count of empty items would not end.
            const std::uint64_t fit = size ? in.bytes_left() / size : element.count;
            if (fit < element.count) binary_ends(path, element, fit, in.offset() + std::size_t(fit) * size);
            in.skip(std::size_t(element.count * size));
            continue;
        }
        Vec3 ignored{};
        for (std::uint64_t i = 0; i < element.count; ++i)
            if (!in.read_item(element, ignored)) binary_ends(path, element, i, in.offset());
    }
    const Element& vertex = header.elements[header.vertex];
    std::size_t size = 0;
    if (fixed_item_size(vertex, size)) return read_fixed_vertices(vertex, size, in, data, swap, path, options);
    return read_listed_vertices(vertex, in, data.size() - header.data_offset, path, options);
}

// ---- ASCII data ----

// A data line of the vertex element, for parse_lines; every value must be a number.
class AsciiVertex {
public:
    explicit AsciiVertex(const Element& element) : element_(element) {}

    LineKind operator()(std::string_view line, Vec3& xyz, std::string& what) const {
        std::string_view rest = line;
        if (next_token(rest).empty()) return LineKind::Skip;  // blank
        rest = line;
        for (const Property& p : element_.properties) {
            double value = 0;
            if (!number(rest, p, p.is_list, value, what)) return LineKind::Error;
            if (p.is_list) {
                // Negated so that NaN fails too; the bound keeps the cast defined.
                if (!(value >= 0 && value <= 1e15 && value == std::floor(value))) {
                    what = "bad list length for " + in_quotes(p.name);
                    return LineKind::Error;
                }
                double item = 0;
                for (std::uint64_t k = 0; k < std::uint64_t(value); ++k)
                    if (!number(rest, p, false, item, what)) return LineKind::Error;
            } else if (p.axis >= 0) {
                xyz[std::size_t(p.axis)] = value;
            }
        }
        if (!next_token(rest).empty()) {
            what = "more values than the vertex element's properties";
            return LineKind::Error;
        }
        return LineKind::Point;
    }
    std::string item_prefix(std::uint64_t item) const { return "vertex " + std::to_string(item) + ": "; }

private:
    // The next value, for property p (its list length when `length`).
    static bool number(std::string_view& rest, const Property& p, bool length, double& value, std::string& what) {
        const std::string_view token = next_token(rest);
        if (!token.empty() && parse_number(token, value)) return true;
        const std::string name = in_quotes(length ? p.name + " (list length)" : p.name);
        what = token.empty() ? "too few values (missing " + name + ")"
                             : "expected a number for " + name + ", found " + in_quotes(token);
        return false;
    }

    const Element& element_;
};

bool is_blank(std::string_view line) { return next_token(line).empty(); }

FloatPoints read_ascii(const Header& header, std::string_view data, const std::string& path,
                       const ParseOptions& options) {
    const std::string_view body = data.substr(header.data_offset);
    LineScanner lines(body, header.lines);
    for (std::size_t e = 0; e < header.vertex; ++e) {  // the elements before the vertices: a line an item
        const Element& element = header.elements[e];
        for (std::uint64_t i = 0; i < element.count; ++i) {
            std::string_view line;
            do {
                if (!lines.next(line))
                    throw InputError(path + ": " + ends_early(element.count, i, item_noun(element)) + " (line " +
                                     std::to_string(lines.line_number()) + ")");
            } while (is_blank(line));
        }
    }
    const Element& vertex = header.elements[header.vertex];
    LineRegion region;
    region.text = body;
    region.begin = lines.offset();
    region.lines_before = header.lines;
    region.limit = vertex.count;
    region.items = item_noun(vertex);
    return parse_lines(region, AsciiVertex(vertex), path, options);
}

}  // namespace

FloatPoints parse_ply(std::string_view data, const std::string& path, const ParseOptions& options) {
    const Header header = parse_header(data, path);
    return header.format == Format::Ascii ? read_ascii(header, data, path, options)
                                          : read_binary(header, data, path, options);
}

}  // namespace snvr::detail
