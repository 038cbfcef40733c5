// Small encoding helpers shared by the point readers and the mesh/field
// writers: byte order, exact number formatting (number_text.hpp) and extension matching.
#pragma once
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>

#include "number_text.hpp"

namespace snvr::detail {

inline bool host_is_little_endian() {
    const std::uint16_t one = 1;
    unsigned char first = 0;
    std::memcpy(&first, &one, 1);
    return first == 1;
}

// Reads a T stored at p (possibly unaligned), reversing its bytes when the
// data's byte order differs from the host's.
template <typename T>
T load_bytes(const char* p, bool swap) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, p, sizeof(T));
    if (swap) std::reverse(bytes, bytes + sizeof(T));
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return value;
}

// Stores value at p in little endian order, whatever the host's order.
template <typename T>
void store_le(T value, char* p) {
    std::memcpy(p, &value, sizeof(T));
    if (!host_is_little_endian()) std::reverse(p, p + sizeof(T));
}


// ".PLY" and ".ply" select the same format.
inline std::string lower_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

}  // namespace snvr::detail
