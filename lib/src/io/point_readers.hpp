// The format parsers behind read_points. Each gets the whole file contents and
// its path (for messages) and throws InputError naming the place of a problem;
// read_points itself checks for empty sets and non-finite coordinates.
#pragma once
#include <string>
#include <string_view>

#include "snvr/geometry.hpp"

namespace snvr::detail {

// The file's points (its bytes already read and inflated), by its extension, checked
// (not empty, all finite): read_points without the reading.
PointSet parse_points(std::string_view data, const std::string& path);

PointSet parse_ply(std::string_view data, const std::string& path);
PointSet parse_xyz(std::string_view data, const std::string& path);  // also .pts and .txt
PointSet parse_obj(std::string_view data, const std::string& path);
PointSet parse_off(std::string_view data, const std::string& path);
PointSet parse_las(std::string_view data, const std::string& path);  // las_reader.cpp

}  // namespace snvr::detail
