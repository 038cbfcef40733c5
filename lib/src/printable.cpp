// printable(): messages made safe to print (see snvr/error.hpp).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "snvr/error.hpp"

namespace snvr {
namespace {

// Length of the valid UTF-8 sequence at s[i] (0 if none starts there, or one that is a
// C1 control, U+0080 to U+009F: some terminals act on those as on ESC): no overlong
// forms, no surrogates, nothing above U+10FFFF.
std::size_t utf8_length(std::string_view s, std::size_t i) {
    const auto byte = [&](std::size_t k) { return std::uint8_t(s[k]); };
    const std::uint8_t b = byte(i);
    std::size_t n;
    std::uint32_t code, least;
    if (b >= 0xC2 && b <= 0xDF) n = 2, code = b & 0x1F, least = 0x80;
    else if (b >= 0xE0 && b <= 0xEF) n = 3, code = b & 0x0F, least = 0x800;
    else if (b >= 0xF0 && b <= 0xF4) n = 4, code = b & 0x07, least = 0x10000;
    else return 0;
    if (i + n > s.size()) return 0;
    for (std::size_t k = 1; k < n; ++k) {
        if ((byte(i + k) & 0xC0) != 0x80) return 0;
        code = code << 6 | (byte(i + k) & 0x3F);
    }
    if (code < least || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF) || code <= 0x9F) return 0;
    return n;
}

}  // namespace

std::string printable(std::string_view text) {
    static const char hex[] = "0123456789abcdef";
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size();) {
        const std::uint8_t b = std::uint8_t(text[i]);
        if ((b >= 0x20 && b < 0x7F) || b == '\n' || b == '\t') {
            out += char(b);
            ++i;
        } else if (const std::size_t n = b >= 0x80 ? utf8_length(text, i) : 0) {
            out.append(text.substr(i, n));
            i += n;
        } else {
            out += "\\x";
            out += hex[b >> 4];
            out += hex[b & 15];
            ++i;
        }
    }
    return out;
}

}  // namespace snvr
