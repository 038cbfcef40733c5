// Meshes and their writing: reading a triangle mesh, writing meshes and fields, the
// float32 rule of each format, and outputs staged to appear together (lib/src/io/).
// Every writer writes to a temporary file next to the target and renames it on
// success, so a failure never leaves a half-written output.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "snvr/domain.hpp"
#include "snvr/field.hpp"
#include "snvr/geometry.hpp"
#include "snvr/mesh.hpp"

namespace snvr {

class AtomicFile;

// Reads a triangle mesh, choosing the parser from the extension: .stl (binary or
// ASCII; corners with identical coordinates become one vertex), .ply (ASCII or
// binary, a vertex element with x/y/z and a face element with a vertex_indices
// list), .obj ("v" and "f" lines), .off, each also gzipped (.gz). Polygons become fans of triangles. Throws
// IoError (cannot open or read) or InputError (malformed, names file and place).
Mesh read_mesh(const std::string& path);

// Chooses the format from the extension: .stl (binary), .ply (binary little endian), .obj,
// .3mf (its unit set to millimetres: coordinates are taken to be in mm).
void write_mesh(const Mesh& mesh, const std::string& path);

// Writes the field as VTK image data (.vti, raw appended binary) or NRRD (.nrrd),
// with the origin at the centre of cell (0,0,0) (domain.origin + h/2) and spacing h.
void write_field(const Field& field, const Domain& domain, const std::string& path);

// The mesh as a reader of `path` gets it: for the formats that store float32
// coordinates (.stl, .ply) every vertex rounded to float32, for .3mf also to the six
// decimals lib3mf prints; for .obj (exact digits)
// a copy. Checks of what is written run on this.
// Takes the mesh by value: move it in where the original is not needed (it is written
// rounded the same way), and no copy is made.
Mesh as_written(Mesh mesh, const std::string& path);

// Throws IoError when the format of `path` cannot hold the mesh's coordinates to
// 1% of a voxel (float32 far from the origin: at x = 500000 its step is 0.03), giving
// the distance and the remedies (an exact format, or coordinates shifted to the origin).
void require_written_precision(const Mesh& mesh, const std::string& path, double voxel);
// The same rule before a run: whether any coordinate up to `farthest` from the origin,
// written to path's format, stays within what require_written_precision allows at
// `voxel`.
bool holds_faithfully(double farthest, const std::string& path, double voxel);

// Outputs that appear together or not at all: each add_ writes its file in full to a
// temporary (and throws, naming it, if it cannot), and only commit() renames them onto
// their targets. A failure before commit(), or an OutputFiles dropped without it, leaves
// every target as it was and no temporary behind.
class OutputFiles {
public:
    OutputFiles();
    ~OutputFiles();
    OutputFiles(const OutputFiles&) = delete;
    OutputFiles& operator=(const OutputFiles&) = delete;

    // Each returns the size of the file it staged, in bytes.
    std::uint64_t add_mesh(const Mesh& mesh, const std::string& path);
    std::uint64_t add_field(const Field& field, const Domain& domain, const std::string& path);
    std::uint64_t add_bytes(const std::string& bytes, const std::string& path);  // as given
    std::uint64_t add_points(const PointSet& points, const std::string& path, const std::string& comment = "");
    void commit();

private:
    std::vector<std::unique_ptr<AtomicFile>> files_;
};

// Removes the named temporary files this process's writers have open (most have none:
// on Linux a temporary has no name until its final rename). Async-signal-safe, for a
// SIGINT or SIGTERM handler that then ends the process.
void remove_temporary_files() noexcept;

}  // namespace snvr
