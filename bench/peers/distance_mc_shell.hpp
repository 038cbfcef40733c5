// The simplest shell a user can make with no smoothing at all (the paper's "simplest
// method"): the unsigned distance d to the nearest point (a nanoflann kd-tree),
// evaluated only at the grid nodes of the band around the points, and the isosurface
// d = l by dual marching cubes. It is the floor a reconstruction's cost is measured
// against: what reading, indexing and a distance in the band cost at a grid and a
// point count.
#pragma once
#include <cstddef>

#include "snvr/domain.hpp"
#include "snvr/geometry.hpp"

namespace snvr::peers {

struct DistanceShell {
    Mesh mesh;            // closed, outward, from dual marching cubes
    Domain grid;          // cell-centred, voxel h, padded so the surface closes
    std::size_t band_cells = 0, band_bricks = 0;  // where the distance was evaluated
    double seconds_index = 0, seconds_band = 0, seconds_distance = 0, seconds_mesh = 0;
};

// Cells of padding beyond the offset: the outermost cell centres are 1.5 voxels
// farther than l from every point, so the field is below the level on the boundary.
constexpr int kDistancePadCells = 2;

// The grid around the points: the points' box grown by offset + kDistancePadCells
// voxels on each side, centred on it.
Domain distance_grid(const PointSet& points, double voxel, double offset);

// `voxel` and `offset` in world units. Throws snvr::ParameterError when either is not
// positive or the grid would be too large to index, snvr::InputError for no points.
DistanceShell distance_mc_shell(const PointSet& points, double voxel, double offset);

}  // namespace snvr::peers
