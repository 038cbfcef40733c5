// The point readers: read_float_points and the format parsers behind it (and behind
// read_points and read_input), which the format table (formats.hpp) holds per format.
// Each parser gets the file as an InputSource (its header, its whole, or its records
// part by part, as the parser asks) and its path (for messages), and throws InputError
// naming the place of a problem, or the first point floats cannot hold (non-finite, or
// beyond float range from the origin).
#pragma once
#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "snvr/geometry.hpp"
#include "spilled_memory.hpp"

namespace snvr::detail {

class InputSource;

// Points as read: world coordinates = origin + xyz (float), input order.
//
// The origin is 0 for files whose coordinates are floats already (float32 PLY, or PLY
// integers of up to 16 bits): they are held exactly. For double values (text, double or
// 32-bit integer PLY, LAS) it is chosen from the box of the first points read (4096): 0
// where that box is near the origin (its centre no farther from 0 than its longest
// side), else its round centre (snvr::round_centre; a lone point itself). A LAS file's
// header gives the whole box before the points: its origin is taken unless the points
// then break the bound below (a header box that is wrong), when the first points choose.
// With D the diagonal of the box of all the points,
//     |x - origin| <= 2.5 D   for every point x,
// and the only error is float rounding of x - origin: at most 2^-24 |x - origin|, so
// under 1.5e-7 D. (A scan 100 m across keeps its points to 26 um wherever it lies; floats
// of x itself are 3 cm apart at x = 500000.) Why 2.5 D: from a far sample box the origin
// lies within half the box's longest side of its centre, so |x - origin| <= D + 0.87 D;
// a near one holds its points within 1.5 D of 0, and every x lies within D of them.
struct FloatPoints {
    PointArray<std::array<float, 3>> xyz;  // beyond a budget, in a file (spilled_memory.hpp)
    Vec3 origin{0, 0, 0};
    std::size_t first = 0;  // read in parts (ParseOptions::parts): the input index of xyz[0]
};

// How the parsers share out their work. The defaults suit real files; the tests use
// small blocks and various thread counts to reach every boundary.
struct ParseOptions {
    std::size_t text_block = std::size_t(1) << 20;  // bytes of text a thread parses at a time
    int threads = 0;                                 // 0: as many as OpenMP gives
    std::size_t origin_sample = 4096;                // first points the origin is chosen from
    std::size_t read_part = std::size_t(1) << 20;    // bytes of binary records a thread reads at a time
    // Part `part` of `parts` equal runs of the points (one process's of several), where
    // points_in_parts says the file can be read so; the origin is the whole file's.
    std::size_t part = 0, parts = 1;
};

// The points of a file that can be read in parts, each part on its own (a plain binary
// PLY whose vertex records have a fixed size, no lists before them, every record there);
// 0 for any other file.
std::size_t points_in_parts(const std::string& path);

// Everything read_points promises (regular file, extension, .gz, messages naming file and place,
// non-finite coordinates and empty sets refused, a file changed while read refused), as
// floats. Binary records are read part by part, never the whole file at once; text is
// read whole and released before this returns: the points alone remain.
FloatPoints read_float_points(const std::string& path, const ParseOptions& options = {},
                              const std::string& temp_folder = {});

// The source's points by its format (its path's), checked (not empty, all held, the
// file unchanged): read_float_points once the file is open.
FloatPoints parse_points(InputSource& source, const ParseOptions& options = {});
// The same for bytes in memory, read as a file named path.
FloatPoints parse_points(std::string_view data, const std::string& path, const ParseOptions& options = {});

// What an input file holds, by its format (formats.hpp): a mesh where the format reads
// meshes and the file holds faces (STL always), else its points as read_float_points
// reads them. Throws as read_float_points or read_mesh; the file is released before
// this returns.
struct PointsOrMesh {
    bool is_mesh = false;
    FloatPoints points;  // when not a mesh
    Mesh mesh;           // when one
};
// A .gz file is inflated into an unnamed file in `temp_folder` (input_source.hpp).
PointsOrMesh read_points_or_mesh(const std::string& path, const std::string& temp_folder = {});

// World coordinates in doubles: origin + xyz.
PointSet world_points(const FloatPoints& points);

FloatPoints parse_ply(InputSource& source, const std::string& path, const ParseOptions& options);
FloatPoints parse_xyz(InputSource& source, const std::string& path, const ParseOptions& options);  // .pts .txt .csv
FloatPoints parse_obj(InputSource& source, const std::string& path, const ParseOptions& options);
FloatPoints parse_off(InputSource& source, const std::string& path, const ParseOptions& options);
FloatPoints parse_las(InputSource& source, const std::string& path, const ParseOptions& options);

}  // namespace snvr::detail
