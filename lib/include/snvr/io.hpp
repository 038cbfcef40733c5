// Reading point sets and writing meshes and fields. Every writer writes to a
// temporary file next to the target and renames it on success, so a failure
// never leaves a half-written output.
#pragma once
#include <string>

#include "snvr/domain.hpp"
#include "snvr/field.hpp"
#include "snvr/geometry.hpp"

namespace snvr {

// Chooses the reader from the extension: .ply (ASCII, binary little/big endian,
// float or double x/y/z among any other properties), .xyz/.pts/.txt (whitespace
// separated x y z per line, extra columns ignored), .obj ("v" lines), .off.
// Throws IoError (cannot open) or InputError (malformed, names file and place);
// non-finite coordinates and empty sets are InputErrors.
PointSet read_points(const std::string& path);

// Reads a triangle mesh, choosing the parser from the extension: .stl (binary or
// ASCII; corners with identical coordinates become one vertex), .ply (ASCII or
// binary, a vertex element with x/y/z and a face element with a vertex_indices
// list), .obj ("v" and "f" lines). Polygons become fans of triangles. Throws
// IoError (cannot open or read) or InputError (malformed, names file and place).
Mesh read_mesh(const std::string& path);

// Chooses the format from the extension: .stl (binary), .ply (binary little endian), .obj.
void write_mesh(const Mesh& mesh, const std::string& path);

// Writes points as binary little-endian PLY (.ply, float32 x y z, `comment` in the
// header) or text (.xyz/.pts/.txt, one "x y z" line each, digits that read back
// exactly), atomically like write_mesh. Throws InputError for another extension.
void write_points(const PointSet& points, const std::string& path, const std::string& comment = "");

// Writes the field as VTK image data (.vti, raw appended binary) or NRRD (.nrrd),
// with the origin at the centre of cell (0,0,0) (domain.origin + h/2) and spacing h.
void write_field(const Field& field, const Domain& domain, const std::string& path);

}  // namespace snvr
