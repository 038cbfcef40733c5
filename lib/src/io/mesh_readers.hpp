// Meshes from memory, for read_mesh and for thickening a mesh given as input. The
// format table (formats.hpp) holds these per format.
#pragma once
#include <string>
#include <string_view>

#include "snvr/geometry.hpp"

namespace snvr::detail {

class InputSource;

// Parses .stl, .ply, .obj or .off data (the format by format_name(path)); throws InputError
// naming the file and the place.
Mesh parse_mesh(std::string_view data, const std::string& path);

// The parsers, each throwing InputError naming the file and the place.
Mesh read_stl_mesh(std::string_view data, const std::string& path);  // binary or ASCII
Mesh read_ply_mesh(std::string_view data, const std::string& path);
Mesh read_obj_mesh(std::string_view data, const std::string& path);
Mesh read_off_mesh(std::string_view data, const std::string& path);

// Whether the file holds faces (and is read as a mesh, not as points): a face element
// with items and an index list in a PLY header (which must parse), an "f" line in OBJ,
// a face count above 0 in OFF.
bool ply_has_faces(InputSource& source, const std::string& path);
bool obj_has_faces(InputSource& source, const std::string& path);
bool off_has_faces(InputSource& source, const std::string& path);

}  // namespace snvr::detail
