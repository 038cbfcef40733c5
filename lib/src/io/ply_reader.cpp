// PLY point reader: with the header (ply_header.hpp) in elements and properties, walks
// the data section (ASCII, or binary in either byte order) up to and including
// the vertex element, taking x, y and z from wherever they sit among the
// vertex properties. Elements after the vertices are never read. Vertex records
// of fixed size are read part by part by the threads (parallel_records.hpp), ASCII lines
// parsed by parse_lines.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "io/float_origin.hpp"
#include "io/formats.hpp"
#include "io/input_source.hpp"
#include "io/io_common.hpp"
#include "io/parallel_lines.hpp"
#include "io/parallel_records.hpp"
#include "io/ply_header.hpp"
#include "io/point_readers.hpp"
#include "io/text_scan.hpp"
#include "snvr/error.hpp"

namespace snvr::detail {
namespace {

using ply::Element;
using ply::Encoding;
using ply::Header;
using ply::Property;
using ply::Scalar;
using ply::load_scalar;
using ply::scalar_size;

std::string item_noun(const Element& element) {
    return element.name == "vertex" ? std::string("vertices") : in_quotes(element.name) + " items";
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

// Bounds-checked walk over the binary data section of a file of `size` bytes. Items of
// fixed size are skipped by arithmetic; the file's bytes (`data`) are needed only where
// items are read (read_item), for lists.
class BinaryReader {
public:
    BinaryReader(std::string_view data, std::size_t size, std::size_t offset, bool swap, const std::string& path)
        : data_(data), size_(size), pos_(offset), swap_(swap), path_(path) {}

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
    std::size_t bytes_left() const { return size_ - pos_; }
    void skip(std::size_t bytes) { pos_ += bytes; }

private:
    bool take(std::size_t size, const char*& at) {
        if (size_ - pos_ < size) return false;
        at = data_.data() + pos_;
        pos_ += size;
        return true;
    }

    std::string_view data_;
    std::size_t size_, pos_;
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
    std::size_t at[3] = {};
    Scalar type[3] = {};
    bool swap = false;

    FixedVertex(const Element& vertex, bool swap_bytes) : swap(swap_bytes) {
        std::size_t offset = 0;
        for (const Property& p : vertex.properties) {
            if (p.axis >= 0) {
                at[p.axis] = offset;
                type[p.axis] = p.type;
            }
            offset += scalar_size(p.type);
        }
    }
    Vec3 operator()(const char* record) const {
        return {load_scalar(type[0], record + at[0], swap), load_scalar(type[1], record + at[1], swap),
                load_scalar(type[2], record + at[2], swap)};
    }
};

[[noreturn]] void binary_ends(const std::string& path, const Element& element, std::uint64_t got, std::size_t offset) {
    throw InputError(path + ": " + ends_early(element.count, got, item_noun(element)) + " (byte offset " +
                     std::to_string(offset) + ")");
}

// The vertices as fixed-size records, split between threads.
FloatPoints read_fixed_vertices(const Element& vertex, std::size_t size, BinaryReader& in, const InputSource& source,
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
    const RecordSpan records{in.offset(), size, std::size_t(vertex.count)};
    const FixedVertex decode(vertex, swap);
    FloatPoints points;
    if (!exact_in_float(vertex)) points.origin = choose_origin(sample_records(source, records, decode, options.origin_sample));
    // One part of them (the origin the whole file's), or all.
    points.first = records.count * options.part / options.parts;
    const std::size_t end = records.count * (options.part + 1) / options.parts;
    const RecordSpan part{records.first + points.first * size, size, end - points.first};
    const ConvertedRecords done = convert_records(source, part, decode, points.origin, points.xyz, options);
    if (done.first_refused < part.count)
        refuse_point(path, points.first + done.first_refused, record_point(source, part, decode, done.first_refused),
                     points.origin);
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

// Whether an element up to the vertices has lists: then items are walked one by one,
// from the whole file.
bool lists_before_records(const Header& header) {
    std::size_t size = 0;
    for (std::size_t e = 0; e <= header.vertex; ++e)
        if (!fixed_item_size(header.elements[e], size)) return true;
    return false;
}

FloatPoints read_binary(const Header& header, InputSource& source, const std::string& path,
                        const ParseOptions& options) {
    std::size_t record = 0;
    if (options.parts > 1 && (lists_before_records(header) || !fixed_item_size(header.elements[header.vertex], record)))
        throw Error(path + ": its points cannot be read in parts");
    const bool file_little = header.encoding == Encoding::BinaryLittle;
    const bool swap = file_little != host_is_little_endian();
    const std::string_view data = lists_before_records(header) ? source.all() : std::string_view();
    BinaryReader in(data, source.size(), header.data_offset, swap, path);
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
    if (fixed_item_size(vertex, size)) return read_fixed_vertices(vertex, size, in, source, swap, path, options);
    return read_listed_vertices(vertex, in, source.size() - header.data_offset, path, options);
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

std::size_t points_in_parts(const std::string& path) {
    require_regular_file(path);
    const Format* format = read_format(path);
    if (format_name(path) != path || !format || format->read.points != &parse_ply) return 0;
    InputSource source(path);
    const Header header = ply::read_header(source, path);
    if (header.encoding == Encoding::Ascii || lists_before_records(header)) return 0;
    std::size_t before = 0, size = 0;  // the bytes of the elements before the vertices, of a vertex
    for (std::size_t e = 0; e < header.vertex; ++e) {
        fixed_item_size(header.elements[e], size);
        before += std::size_t(header.elements[e].count) * size;
    }
    const Element& vertex = header.elements[header.vertex];
    fixed_item_size(vertex, size);
    const std::size_t data = source.size() - std::min(source.size(), header.data_offset);
    if (size == 0 || before > data || (data - before) / size < vertex.count) return 0;  // read whole: its error
    return std::size_t(vertex.count);
}

FloatPoints parse_ply(InputSource& source, const std::string& path, const ParseOptions& options) {
    const Header header = ply::read_header(source, path);
    if (options.parts > 1 && header.encoding == Encoding::Ascii) throw Error(path + ": its points cannot be read in parts");
    return header.encoding == Encoding::Ascii ? read_ascii(header, source.all(), path, options)
                                              : read_binary(header, source, path, options);
}

}  // namespace snvr::detail
