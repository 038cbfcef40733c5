// Line-based point formats: XYZ/PTS/TXT/CSV columns as scanners export them, OBJ "v"
// lines and OFF vertex blocks. '#' starts a comment in all of them. Each is a line parser
// for parse_lines (parallel_lines.hpp); only what comes before the points (a header of
// names, OFF's counts) is read serially.
#include <cstdint>
#include <string>

#include "io/input_source.hpp"
#include "io/parallel_lines.hpp"
#include "io/point_readers.hpp"
#include "io/text_scan.hpp"
#include "snvr/error.hpp"

namespace snvr::detail {
namespace {

[[noreturn]] void line_error(const std::string& path, std::size_t line, const std::string& what) {
    throw InputError(path + ": line " + std::to_string(line) + ": " + what);
}

// Splits off up to `max` leading tokens of a line, comments removed; returns
// how many. One pass per line keeps large files fast.
std::size_t leading_tokens(std::string_view line, std::string_view* tokens, std::size_t max) {
    line = strip_comment(line);
    std::size_t n = 0;
    while (n < max && !(tokens[n] = next_token(line)).empty()) ++n;
    return n;
}

// Leading tokens of the next line that has any; 0 at the end of the data.
std::size_t next_tokens(LineScanner& lines, std::string_view* tokens, std::size_t max) {
    std::string_view line;
    std::size_t count = 0;
    while (count == 0 && lines.next(line)) count = leading_tokens(line, tokens, max);
    return count;
}

// A number whose decimal mark may be a comma ("2,5" in semicolon-separated exports).
bool parse_field(std::string_view token, bool decimal_comma, double& out) {
    if (!decimal_comma || token.find(',') == std::string_view::npos) return parse_number(token, out);
    char copy[64];
    if (token.size() >= sizeof copy) return false;
    for (std::size_t i = 0; i < token.size(); ++i) copy[i] = token[i] == ',' ? '.' : token[i];
    return parse_number(std::string_view(copy, token.size()), out);
}

// The first three of `count` tokens as a point, or Error with the reason.
LineKind to_point(const std::string_view* tokens, std::size_t count, Vec3& point, std::string& what,
                  bool decimal_comma = false) {
    if (count < 3) {
        what = "expected x y z, found " + std::to_string(count) + " value(s)";
        return LineKind::Error;
    }
    for (std::size_t axis = 0; axis < 3; ++axis) {
        if (!parse_field(tokens[axis], decimal_comma, point[axis])) {
            what = "expected a number, found " + in_quotes(tokens[axis]);
            return LineKind::Error;
        }
    }
    return LineKind::Point;
}

// Up to `max` leading fields of a scanner's text line: separated by spaces, tabs, commas
// or semicolons, where a line with semicolons takes commas for decimal marks; '#' and a
// leading "//" start comments. Returns how many; decimal_comma tells how to read them.
std::size_t scanner_fields(std::string_view line, std::string_view* fields, std::size_t max, bool& decimal_comma) {
    line = strip_comment(line);
    std::size_t first = 0;
    while (first < line.size() && is_space(line[first])) ++first;
    if (line.compare(first, 2, "//") == 0) return 0;
    decimal_comma = line.find(';') != std::string_view::npos;
    const auto separates = [decimal_comma](char c) { return is_space(c) || c == ';' || (c == ',' && !decimal_comma); };
    std::size_t n = 0, i = first;
    while (n < max) {
        while (i < line.size() && separates(line[i])) ++i;
        if (i == line.size()) break;
        const std::size_t start = i;
        while (i < line.size() && !separates(line[i])) ++i;
        fields[n++] = line.substr(start, i - start);
    }
    return n;
}

// A scanner's line: x y z and perhaps more columns, or a lone number (a PTS point count).
struct ScannerLine {
    LineKind operator()(std::string_view line, Vec3& point, std::string& what) const {
        std::string_view tokens[3];
        bool decimal_comma = false;
        const std::size_t count = scanner_fields(line, tokens, 3, decimal_comma);
        if (count == 0) return LineKind::Skip;
        if (count == 1) {  // a lone number is a PTS point count, not a point
            double value = 0;
            if (parse_field(tokens[0], decimal_comma, value)) return LineKind::Skip;
            what = "expected a number, found " + in_quotes(tokens[0]);
            return LineKind::Error;
        }
        return to_point(tokens, count, point, what, decimal_comma);
    }
    std::string item_prefix(std::uint64_t) const { return {}; }
};

// Where a scanner's points start: after a first line of names ("X Y Z", "x,y,z,r,g,b"),
// if the first line with fields is one; at the start otherwise.
std::size_t after_header_of_names(std::string_view data) {
    LineScanner lines(data);
    std::string_view line, tokens[1];
    bool decimal_comma = false;
    while (lines.next(line)) {
        if (scanner_fields(line, tokens, 1, decimal_comma) == 0) continue;
        double value = 0;
        return parse_field(tokens[0], decimal_comma, value) ? 0 : lines.offset();
    }
    return data.size();
}

struct ObjLine {
    LineKind operator()(std::string_view line, Vec3& point, std::string& what) const {
        std::string_view tokens[4];
        const std::size_t count = leading_tokens(line, tokens, 4);
        if (count == 0 || tokens[0] != "v") return LineKind::Skip;  // only "v" lines count
        return to_point(tokens + 1, count - 1, point, what);
    }
    std::string item_prefix(std::uint64_t) const { return {}; }
};

struct OffVertexLine {
    LineKind operator()(std::string_view line, Vec3& point, std::string& what) const {
        std::string_view tokens[3];
        const std::size_t count = leading_tokens(line, tokens, 3);
        return count == 0 ? LineKind::Skip : to_point(tokens, count, point, what);
    }
    std::string item_prefix(std::uint64_t) const { return {}; }
};

// OFF, COFF, NOFF, STOFF, ...: optional prefixes whose vertex lines still start with x y z.
bool is_off_keyword(std::string_view token) {
    if (token.size() < 3 || token.substr(token.size() - 3) != "OFF") return false;
    const std::string_view prefix = token.substr(0, token.size() - 3);
    return prefix.find_first_not_of("STCN") == std::string_view::npos;
}

}  // namespace

FloatPoints parse_xyz(InputSource& source, const std::string& path, const ParseOptions& options) {
    const std::string_view data = source.all();
    LineRegion region;
    region.text = data;
    region.begin = after_header_of_names(data);
    return parse_lines(region, ScannerLine{}, path, options);
}

FloatPoints parse_obj(InputSource& source, const std::string& path, const ParseOptions& options) {
    const std::string_view data = source.all();
    LineRegion region;
    region.text = data;
    return parse_lines(region, ObjLine{}, path, options);
}

FloatPoints parse_off(InputSource& source, const std::string& path, const ParseOptions& options) {
    const std::string_view data = source.all();
    LineScanner lines(data);
    std::string_view tokens[3];
    std::size_t count = next_tokens(lines, tokens, 2);
    if (count == 0 || !is_off_keyword(tokens[0])) throw InputError(path + ": missing 'OFF' header on the first line");
    // The counts may share the header line ("OFF 8 6 12") or follow it.
    std::string_view vertex_count = tokens[1];
    if (count == 1) {
        if (next_tokens(lines, tokens, 1) == 0)
            throw InputError(path + ": missing vertex/face counts after the 'OFF' header");
        vertex_count = tokens[0];
    }
    LineRegion region;
    region.text = data;
    region.begin = lines.offset();
    if (!parse_count(vertex_count, region.limit))
        line_error(path, lines.line_number(), "expected the vertex count, found " + in_quotes(vertex_count));
    return parse_lines(region, OffVertexLine{}, path, options);
}

}  // namespace snvr::detail
