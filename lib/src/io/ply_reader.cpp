// PLY point reader: parses the header into elements and properties, then walks
// the data section (ASCII, or binary in either byte order) up to and including
// the vertex element, taking x, y and z from wherever they sit among the
// vertex properties. Elements after the vertices are never read.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "io/io_common.hpp"
#include "io/point_readers.hpp"
#include "snvr/error.hpp"
#include "io/text_scan.hpp"

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

PointSet read_binary(const Header& header, std::string_view data, const std::string& path) {
    const bool file_little = header.format == Format::BinaryLittle;
    BinaryReader in(data, header.data_offset, file_little != host_is_little_endian(), path);
    PointSet points;
    for (std::size_t e = 0; e <= header.vertex; ++e) {
        const Element& element = header.elements[e];
        const bool keep = e == header.vertex;
        if (keep) points.reserve(plausible_count(element.count, data.size() - header.data_offset));
        std::size_t size = 0;
        if (!keep && fixed_item_size(element, size)) {
            // Skipped in one step: a loop over a huge count of empty items would not end.
            const std::uint64_t fit = size ? in.bytes_left() / size : element.count;
            if (fit < element.count)
                throw InputError(path + ": " + ends_early(element.count, fit, item_noun(element)) + " (byte offset " +
                                 std::to_string(in.offset() + fit * size) + ")");
            in.skip(std::size_t(element.count * size));
            continue;
        }
        Vec3 xyz{};
        for (std::uint64_t i = 0; i < element.count; ++i) {
            if (!in.read_item(element, xyz))
                throw InputError(path + ": " + ends_early(element.count, i, item_noun(element)) +
                                 " (byte offset " + std::to_string(in.offset()) + ")");
            if (keep) points.push_back(xyz);
        }
    }
    return points;
}

// ---- ASCII data ----

// Parses one data line of the vertex element; every value must be a number.
class AsciiItem {
public:
    AsciiItem(std::string_view line, std::size_t line_number, std::uint64_t index, const std::string& path)
        : rest_(line), line_(line_number), index_(index), path_(path) {}

    Vec3 parse(const Element& element) {
        Vec3 xyz{};
        for (const Property& p : element.properties) {
            if (p.is_list) {
                const double count = number(p.name + " (list length)");
                // Negated so that NaN fails too; the bound keeps the cast defined.
                if (!(count >= 0 && count <= 1e15 && count == std::floor(count)))
                    fail("bad list length for " + in_quotes(p.name));
                for (std::uint64_t k = 0; k < std::uint64_t(count); ++k) number(p.name);
            } else {
                const double value = number(p.name);
                if (p.axis >= 0) xyz[std::size_t(p.axis)] = value;
            }
        }
        if (!next_token(rest_).empty()) fail("more values than the vertex element's properties");
        return xyz;
    }

private:
    double number(const std::string& property) {
        const std::string_view token = next_token(rest_);
        if (token.empty()) fail("too few values (missing " + in_quotes(property) + ")");
        double value = 0;
        if (!parse_number(token, value)) fail("expected a number for " + in_quotes(property) + ", found " + in_quotes(token));
        return value;
    }
    [[noreturn]] void fail(const std::string& what) {
        throw InputError(path_ + ": line " + std::to_string(line_) + ": vertex " + std::to_string(index_) + ": " + what);
    }

    std::string_view rest_;
    std::size_t line_;
    std::uint64_t index_;
    const std::string& path_;
};

bool is_blank(std::string_view line) { return next_token(line).empty(); }

PointSet read_ascii(const Header& header, std::string_view data, const std::string& path) {
    LineScanner lines(data.substr(header.data_offset), header.lines);
    PointSet points;
    for (std::size_t e = 0; e <= header.vertex; ++e) {
        const Element& element = header.elements[e];
        const bool keep = e == header.vertex;
        if (keep) points.reserve(plausible_count(element.count, data.size() - header.data_offset));
        for (std::uint64_t i = 0; i < element.count; ++i) {
            std::string_view line;
            do {
                if (!lines.next(line))
                    throw InputError(path + ": " + ends_early(element.count, i, item_noun(element)) + " (line " +
                                     std::to_string(lines.line_number()) + ")");
            } while (is_blank(line));
            if (keep) points.push_back(AsciiItem(line, lines.line_number(), i, path).parse(element));
        }
    }
    return points;
}

}  // namespace

PointSet parse_ply(std::string_view data, const std::string& path) {
    const Header header = parse_header(data, path);
    return header.format == Format::Ascii ? read_ascii(header, data, path) : read_binary(header, data, path);
}

}  // namespace snvr::detail
