// The writers of each format, each streaming into an AtomicFile; the format table
// (formats.hpp) holds them per format.
#pragma once
#include <memory>
#include <string>

#include "io/atomic_file.hpp"
#include "snvr/domain.hpp"
#include "snvr/field.hpp"
#include "snvr/geometry.hpp"
#include "snvr/mesh_io.hpp"

namespace snvr::detail {

// Meshes, as their parts come (write_mesh.cpp; each checks the triangles' vertex numbers)
// or whole (write_3mf.cpp).
std::unique_ptr<MeshSink> stl_sink(AtomicFile& out);  // binary
std::unique_ptr<MeshSink> ply_sink(AtomicFile& out);  // binary little endian, float32
std::unique_ptr<MeshSink> obj_sink(AtomicFile& out);  // every digit
void write_3mf(const Mesh& mesh, AtomicFile& out);    // lib3mf, millimetres

// Points (write_points.cpp): binary PLY with `comment` in its header; text, one line a point.
void write_ply_points(const PointSet& points, const std::string& comment, AtomicFile& out);
void write_text_points(const PointSet& points, const std::string& comment, AtomicFile& out);

// Fields (write_field.cpp).
void write_vti(const Field& field, const Domain& domain, AtomicFile& out);
void write_nrrd(const Field& field, const Domain& domain, AtomicFile& out);

}  // namespace snvr::detail
