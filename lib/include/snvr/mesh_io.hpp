// Meshes and their writing: reading a triangle mesh, writing meshes and fields, the
// float32 rule of each format, and outputs staged to appear together (lib/src/io/).
// Every writer writes to a temporary file next to the target and renames it on
// success, so a failure never leaves a half-written output.
#pragma once
#include <array>
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

// A mesh handed over in parts, in order: a run over several processes hands each
// process's slab in turn, so that no process need hold the whole mesh. A part is a run of
// the whole mesh's vertices and one of its triangles, numbered as the whole numbers its
// vertices (any part's).
struct MeshPart {
    std::uint64_t first_vertex = 0;  // the whole mesh's number of vertices[0]
    const Vec3* vertices = nullptr;
    std::size_t vertex_count = 0;
    const std::array<std::uint32_t, 3>* triangles = nullptr;
    std::size_t triangle_count = 0;
    // The other parts' vertices its triangles use (ascending) and their positions: given
    // to triangles() where the sink wants corners.
    const std::uint32_t* foreign = nullptr;
    const Vec3* foreign_at = nullptr;
    std::size_t foreign_count = 0;
    // Vertex v, this part's or a foreign one; throws InputError where it is neither.
    const Vec3& position(std::uint32_t v) const;
};
// What takes a mesh in parts: begin() with the whole's counts; then, where it does not
// want corners, vertices() with every part in order; then triangles() with every part
// in order (with the foreign positions where it wants corners); then finish().
class MeshSink {
public:
    virtual ~MeshSink() = default;
    // Whether each triangle's corners are wanted with it (STL repeats them) rather than
    // every vertex first (PLY, OBJ).
    virtual bool wants_corners() const = 0;
    virtual void begin(std::uint64_t vertices, std::uint64_t triangles) = 0;
    virtual void vertices(const MeshPart& part) = 0;
    virtual void triangles(const MeshPart& part) = 0;
    virtual void finish() = 0;
};
// Hands `mesh` to `sink` whole, as its one part.
void hand_mesh(const Mesh& mesh, MeshSink& sink);

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
    // A sink that stages the mesh at `path` as its parts come (staged at its finish());
    // null where the format takes a mesh only whole (.3mf: lib3mf builds the model).
    std::shared_ptr<MeshSink> mesh_sink(const std::string& path);
    // The size of the file staged for `path` (0: none yet).
    std::uint64_t staged_bytes(const std::string& path) const;
    void commit();

private:
    std::vector<std::unique_ptr<AtomicFile>> files_;
};

// Removes the named temporary files this process's writers have open (most have none:
// on Linux a temporary has no name until its final rename). Async-signal-safe, for a
// SIGINT or SIGTERM handler that then ends the process.
void remove_temporary_files() noexcept;

}  // namespace snvr
