// The file formats, one row each: what every reader, writer, signature check and help
// text asks of a format comes from here. A new format is a row (formats.cpp) and its
// parser or writer (declared in point_readers.hpp, mesh_readers.hpp or writers.hpp).
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "io/atomic_file.hpp"
#include "io/point_readers.hpp"
#include "snvr/domain.hpp"
#include "snvr/field.hpp"
#include "snvr/geometry.hpp"
#include "snvr/formats.hpp"
#include "snvr/mesh_io.hpp"

namespace snvr::detail {

using PointParser = FloatPoints (*)(InputSource& source, const std::string& path, const ParseOptions& options);
using MeshParser = Mesh (*)(std::string_view data, const std::string& path);
using FacesRule = bool (*)(InputSource& source, const std::string& path);
using MeshWriter = void (*)(const Mesh& mesh, AtomicFile& out);
using MeshPartsWriter = std::unique_ptr<MeshSink> (*)(AtomicFile& out);
using PointsWriter = void (*)(const PointSet& points, const std::string& comment, AtomicFile& out);
using FieldWriter = void (*)(const Field& field, const Domain& domain, AtomicFile& out);

// How a written file holds a coordinate.
enum class Stores { Exactly, Float32, Float32SixDecimals };

// How far writing vertices to path's format moves a coordinate at most, and the farthest
// coordinate (written_mesh.cpp); require_written_moves throws require_written_precision's
// error (snvr/mesh_io.hpp) where they break its rule, so that slabs held apart are
// checked as the whole mesh.
struct WrittenMoves {
    double largest = 0, farthest = 0;
};
WrittenMoves written_moves(const Vec3* vertices, std::size_t count, const std::string& path);
void require_written_moves(const WrittenMoves& moves, const std::string& path, double voxel);

// Checked on the first inflated bytes of a gzipped file, before the rest is inflated.
struct Signature {
    std::string_view magic;  // the bytes a file starts with ("": none)
    bool any_start = false;  // with no magic: any bytes may start it (binary STL); else text, no NUL byte
};

struct Reading {
    PointParser points = nullptr;  // null: not read as points
    MeshParser mesh = nullptr;     // null: not read as a mesh
    // Whether the data holds faces, so that an input is read as a mesh, not as points;
    // null: never.
    FacesRule faces = nullptr;
    // For a point format known but not read: the message (after "path: ") saying what to do.
    std::string (*points_not_read)(const std::string& path) = nullptr;
};

struct Writing {
    MeshWriter mesh = nullptr;  // the mesh whole (a format that takes it only so)
    PointsWriter points = nullptr;
    FieldWriter field = nullptr;
    Stores stores = Stores::Exactly;  // by the mesh writer
    bool print = false;               // a slicer's format: coordinates centred where float32 would move them
    // Writing a mesh, about, on one thread (this machine, the bunny's 3.3 M triangles): what
    // a run may do meanwhile is planned on it, never its result.
    double ns_a_triangle = 0;
    MeshPartsWriter parts = nullptr;  // the mesh as its parts come (snvr/mesh_io.hpp's MeshSink)
};

struct Format {
    const char* name = "";                     // in messages: "PLY"
    std::vector<std::string_view> extensions;  // lower case, with the dot
    Signature signature;
    Reading read;
    Writing write;
};

// Every format, in the order the messages and help texts list them.
const std::vector<Format>& formats();

// The format of path's extension (any case); null when none has it.
const Format* format_of(const std::string& path);
// The same for a file to read: "a.xyz.gz" is an .xyz file (format_name).
const Format* read_format(const std::string& path);

// The format serving `use` for path (read_format for reading, format_of for writing);
// throws InputError naming the extension and the ones that serve.
const Format& format_for(const std::string& path, FormatUse use);

// Whether the format serves `use` (io.hpp).
bool serves(const Format& format, FormatUse use);
// The extensions of the formats serving `use`, in order, joined by ", " and before
// the last by `last` (format_extensions: " or ").
std::string extension_list(FormatUse use, const char* last);

// The first inflated bytes of a gzipped file against its name's format: throws
// InputError unless they can start such a file (binary STL takes any bytes).
void require_signature(std::string_view first, const std::string& path);

// Whether `path` names a print format (STL, 3MF).
bool is_print_format(const std::string& path);

// About how long writing `triangles` to path's mesh format takes on one thread (0 for
// no mesh format).
double mesh_writing_seconds(const std::string& path, std::size_t triangles);

}  // namespace snvr::detail
