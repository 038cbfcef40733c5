// Points and their reading (and writing): every point format snvr-cl reads, as a
// PointSet or straight into a PointCloud (lib/src/io/).
#pragma once
#include <functional>
#include <string>

#include "snvr/geometry.hpp"
#include "snvr/point_cloud.hpp"

namespace snvr {

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

// Writes points as binary little-endian PLY (.ply, float32 x y z, `comment` in the
// header) or text (.xyz/.pts/.txt, one "x y z" line each, digits that read back
// exactly), atomically like write_mesh. Throws InputError for another extension.
void write_points(const PointSet& points, const std::string& path, const std::string& comment = "");
// The same for `count` points made as they are written, never held whole: `produce`
// hands them to its argument in chunks. Binary PLY only (its header has the count);
// IoError when `produce` makes more or fewer, and nothing is written.
void write_point_stream(const std::string& path, std::size_t count, const std::string& comment,
                        const std::function<void(const std::function<void(const PointSet&)>&)>& produce);

}  // namespace snvr
