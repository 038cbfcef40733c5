// The writers of each format, each streaming into an AtomicFile; the format table
// (formats.hpp) holds them per format.
#pragma once
#include <string>

#include "io/atomic_file.hpp"
#include "snvr/domain.hpp"
#include "snvr/field.hpp"
#include "snvr/geometry.hpp"

namespace snvr::detail {

// Meshes (write_mesh.cpp, write_3mf.cpp).
void write_stl(const Mesh& mesh, AtomicFile& out);  // binary
void write_ply(const Mesh& mesh, AtomicFile& out);  // binary little endian, float32
void write_obj(const Mesh& mesh, AtomicFile& out);  // every digit
void write_3mf(const Mesh& mesh, AtomicFile& out);  // lib3mf, millimetres

// Points (write_points.cpp): binary PLY with `comment` in its header; text, one line a point.
void write_ply_points(const PointSet& points, const std::string& comment, AtomicFile& out);
void write_text_points(const PointSet& points, const std::string& comment, AtomicFile& out);

// Fields (write_field.cpp).
void write_vti(const Field& field, const Domain& domain, AtomicFile& out);
void write_nrrd(const Field& field, const Domain& domain, AtomicFile& out);

}  // namespace snvr::detail
