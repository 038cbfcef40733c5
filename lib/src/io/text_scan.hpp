// Line and token scanning over a whole file held in memory. The text readers
// parse with std::from_chars rather than iostreams so that millions of points
// load quickly.
#pragma once
#include <charconv>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <locale.h>
#include <stdlib.h>
#include <string>
#include <string_view>

namespace snvr::detail {

// The byte that ends a text's lines: '\n', except in a text with no "\n" at all but
// some "\r" (old Mac files), whose lines "\r" ends.
inline char line_end_of(std::string_view text) {
    return text.find('\n') == std::string_view::npos && text.find('\r') != std::string_view::npos ? '\r' : '\n';
}

// Hands out one line at a time (without "\n" or "\r\n") and counts lines, ended as
// line_end_of says.
class LineScanner {
public:
    // lines_before: how many file lines precede `text`, so numbers match the file.
    explicit LineScanner(std::string_view text, std::size_t lines_before = 0)
        : text_(text), end_(line_end_of(text)), line_(lines_before) {}

    bool next(std::string_view& line) {
        if (pos_ >= text_.size()) return false;
        std::size_t end = text_.find(end_, pos_);
        if (end == std::string_view::npos) end = text_.size();
        line = text_.substr(pos_, end - pos_);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        pos_ = end < text_.size() ? end + 1 : end;
        ++line_;
        return true;
    }
    std::size_t line_number() const { return line_; }  // of the line last returned
    std::size_t offset() const { return pos_; }         // first byte after it

private:
    std::string_view text_;
    char end_;
    std::size_t pos_ = 0;
    std::size_t line_ = 0;
};

inline bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
}

// Removes and returns the next whitespace-separated token (empty at the end).
inline std::string_view next_token(std::string_view& rest) {
    std::size_t begin = 0;
    while (begin < rest.size() && is_space(rest[begin])) ++begin;
    std::size_t end = begin;
    while (end < rest.size() && !is_space(rest[end])) ++end;
    const std::string_view token = rest.substr(begin, end - begin);
    rest.remove_prefix(end);
    return token;
}

inline std::string_view strip_comment(std::string_view line) {
    return line.substr(0, line.find('#'));
}

// The whole token must be a number; a leading '+' is allowed (from_chars rejects it).
// A number beyond a double's range is still a number: 1e-400 reads as 0 and 1e400
// as infinity (which the readers then report as a non-finite coordinate).
inline bool parse_number(std::string_view token, double& out) {
    if (token.size() > 1 && token[0] == '+' && token[1] != '-' && token[1] != '+') token.remove_prefix(1);
    if (token.empty()) return false;
    const char* end = token.data() + token.size();
    const auto result = std::from_chars(token.data(), end, out);
    if (result.ptr != end) return false;
    if (result.ec == std::errc::result_out_of_range) {
        // strtod rounds where from_chars refuses; in the C locale, whatever the caller's.
        static const locale_t c_locale = ::newlocale(LC_ALL_MASK, "C", locale_t(0));
        const std::string copy(token);
        out = ::strtod_l(copy.c_str(), nullptr, c_locale);
        return true;
    }
    return result.ec == std::errc();
}

inline bool parse_count(std::string_view token, std::uint64_t& out) {
    if (token.empty()) return false;
    const char* end = token.data() + token.size();
    const auto result = std::from_chars(token.data(), end, out);
    return result.ec == std::errc() && result.ptr == end;
}

inline std::string in_quotes(std::string_view text) { return "'" + std::string(text) + "'"; }

// "expected 5 vertices, file ends after 3": shared wording for truncated data.
inline std::string ends_early(std::uint64_t expected, std::uint64_t got, const std::string& items) {
    return "expected " + std::to_string(expected) + " " + items + ", file ends after " + std::to_string(got);
}

}  // namespace snvr::detail
