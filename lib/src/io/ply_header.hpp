// The PLY header, parsed once for every reader of PLY: the point reader, the mesh reader
// and the faces check (whether a PLY input is a mesh or points).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "io/io_common.hpp"

namespace snvr::detail {
class InputSource;
}  // namespace snvr::detail

namespace snvr::detail::ply {

enum class Scalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };
enum class Encoding { Ascii, BinaryLittle, BinaryBig };

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
    Encoding encoding = Encoding::Ascii;
    std::vector<Element> elements;
    std::size_t vertex = 0;       // index of the vertex element
    std::size_t data_offset = 0;  // first byte after "end_header\n"
    std::size_t lines = 0;        // header lines, so data lines are numbered as in the file
};

// Throws InputError naming the file and the header line; a header without a vertex
// element with x, y and z (not lists) is refused too, since every reader needs them.
Header parse_header(std::string_view data, const std::string& path);
// The same from a file: from its first bytes where they hold the header (a binary file's
// records need not be read to know it), else from the whole file.
Header read_header(InputSource& source, const std::string& path);

// The face element's vertex index list ("vertex_indices" or "vertex_index"), or null.
const Property* face_indices(const Element& face);

// Whether the header declares faces: a "face" element with items and an index list.
bool has_faces(const Header& header);

// Inline: the readers call these per value.
inline std::size_t scalar_size(Scalar type) {
    switch (type) {
        case Scalar::Int8: case Scalar::UInt8: return 1;
        case Scalar::Int16: case Scalar::UInt16: return 2;
        case Scalar::Int32: case Scalar::UInt32: case Scalar::Float32: return 4;
        case Scalar::Float64: return 8;
    }
    return 0;
}

inline double load_scalar(Scalar type, const char* p, bool swap) {
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


}  // namespace snvr::detail::ply
