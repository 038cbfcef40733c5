// The check's walls on an OpenCL device (kernels/wall_rays.cl): the host's rays
// (check/walls.hpp's wall_thickness, TriangleGrid::first_hit) cast by a work-item each,
// through the host's own grid, to the same walls to the bit. The mesh, its normals and the
// grid go to the device once, the walls come back.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "mesh/triangle_grid.hpp"
#include "snvr/geometry.hpp"

namespace snvr::opencl {

// The bytes device_walls puts on the device for a mesh and its grid.
std::size_t device_walls_bytes(const Mesh& m, const TriangleGrid& grid);

// wall[order[k]] for every k: the distance from the vertex along the reverse of its normal
// to the first triangle met past `eps`, ignoring its own triangles, infinity where none is
// met or the normal vanishes. `spec` names the device as --device does; it needs double
// precision. Throws ResourceError naming the walls and what failed (the device's memory,
// its build), ParameterError where the device has no double precision.
void device_walls(const std::string& spec, const Mesh& m, const TriangleGrid& grid, const std::vector<Vec3>& normals,
                  double eps, const std::vector<std::uint32_t>& order, std::vector<double>& wall);

}  // namespace snvr::opencl
