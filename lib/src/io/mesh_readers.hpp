// Meshes from memory, for read_mesh and for thickening a mesh given as input.
#pragma once
#include <string>
#include <string_view>

#include "snvr/geometry.hpp"

namespace snvr::detail {

// Parses .stl, .ply, .obj or .off data (chosen by format_name(path)); throws InputError
// naming the file and the place.
Mesh parse_mesh(std::string_view data, const std::string& path);

// Whether the data holds faces: always for STL; a face element with items in a PLY
// header, an "f" line in OBJ, a face count above 0 in OFF.
bool has_faces(std::string_view data, const std::string& path);

}  // namespace snvr::detail
