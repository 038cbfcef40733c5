// Reading point sets and writing meshes and fields. Every writer writes to a
// temporary file next to the target and renames it on success, so a failure
// never leaves a half-written output.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "snvr/domain.hpp"
#include "snvr/field.hpp"
#include "snvr/geometry.hpp"
#include "snvr/mesh.hpp"
#include "snvr/parameters.hpp"
#include "snvr/point_cloud.hpp"

namespace snvr {

class AtomicFile;

// Chooses the reader from the extension: .ply (ASCII, binary little/big endian,
// float or double x/y/z among any other properties), .xyz/.pts/.txt/.csv (x y z per
// line, separated by spaces, tabs, commas or semicolons, extra columns ignored), .obj
// ("v" lines), .off, .las; each also gzipped (.gz). The points are read as 32-bit floats
// about an origin and returned as doubles: float files exactly, double values rounded
// to within 1.5e-7 of their box's diagonal (see FloatPoints in io/point_readers.hpp).
// Throws IoError (cannot open) or InputError (malformed, names file and place);
// non-finite coordinates, points too far apart for floats and empty sets are InputErrors.
PointSet read_points(const std::string& path);
// The same points as a cloud (point_cloud.hpp), as read: 12 bytes a point, no doubles made.
PointCloud read_point_cloud(const std::string& path);

// The points a reconstruction starts from: a point file as read_point_cloud reads it, or
// a mesh (.stl; .ply, .obj or .off with faces; any of them gzipped) with its triangles
// sampled at half the voxel the run will have (sample_triangles), so that its faces,
// not only its corners, are thickened.
struct InputPoints {
    PointCloud points;
    std::size_t triangles = 0;  // the mesh's, when the input was one
    double spacing = 0;         // the sampling's
};
InputPoints read_input(const std::string& path, const Parameters& params);

// Reads a triangle mesh, choosing the parser from the extension: .stl (binary or
// ASCII; corners with identical coordinates become one vertex), .ply (ASCII or
// binary, a vertex element with x/y/z and a face element with a vertex_indices
// list), .obj ("v" and "f" lines), .off, each also gzipped (.gz). Polygons become fans of triangles. Throws
// IoError (cannot open or read) or InputError (malformed, names file and place).
Mesh read_mesh(const std::string& path);

// Chooses the format from the extension: .stl (binary), .ply (binary little endian), .obj,
// .3mf (its unit set to millimetres: coordinates are taken to be in mm).
void write_mesh(const Mesh& mesh, const std::string& path);

// Writes points as binary little-endian PLY (.ply, float32 x y z, `comment` in the
// header) or text (.xyz/.pts/.txt, one "x y z" line each, digits that read back
// exactly), atomically like write_mesh. Throws InputError for another extension.
void write_points(const PointSet& points, const std::string& path, const std::string& comment = "");

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

// What is done with a file format, for format_extensions.
enum class FormatUse { ReadPoints, ReadMesh, WriteMesh, WritePoints, WriteField };

// The extensions the readers or writers take for `use`, for help texts: ".stl, .ply,
// .obj or .3mf" for WriteMesh. The readers also take each of theirs gzipped (".gz" added).
std::string format_extensions(FormatUse use);

// Removes the named temporary files this process's writers have open (most have none:
// on Linux a temporary has no name until its final rename). Async-signal-safe, for a
// SIGINT or SIGTERM handler that then ends the process.
void remove_temporary_files() noexcept;

}  // namespace snvr
