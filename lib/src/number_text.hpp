// Numbers in messages, reports and text files: the shortest text that reads back as
// exactly the same double, for every layer that writes one.
#pragma once
#include <charconv>
#include <string>

namespace snvr::detail {

inline void append_number(std::string& out, double value) {
    char buf[32];
    const auto result = std::to_chars(buf, buf + sizeof buf, value);
    out.append(buf, result.ptr);
}

inline std::string format_number(double value) {
    std::string text;
    append_number(text, value);
    return text;
}

}  // namespace snvr::detail
