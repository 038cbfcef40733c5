// The walls of a shell: from each vertex along its inward normal, the distance to the
// first triangle met (measure_quality's walls, thinnest_wall, and a process's share of
// them: CheckShare in tiles.hpp); and what other processes measure of a check.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "check/mesh_topology.hpp"
#include "check/point_depths.hpp"
#include "mesh/triangle_grid.hpp"
#include "snvr/geometry.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/quality.hpp"
#include "told_pace.hpp"

namespace snvr::detail {

// Vertices per piece of the walls, handed out one piece at a time.
constexpr std::size_t kWallChunk = 4096;

// Each vertex's unit normal: the sum of its triangles' area vectors, in triangle order
// (the same to the last bit on any number of threads), normalised (0 where it vanishes).
std::vector<Vec3> unit_normals(const Mesh& m);

// A ray's t_min for the walls: far below any wall, far above the rounding of a hit at the
// ray's own start.
double wall_epsilon(const Mesh& m);

// wall[v], v in [first, last): the distance from vertex v along its inward normal to the
// first triangle met, ignoring the vertex's own triangles; infinity when nothing is met
// (and where the normal vanishes).
// skip: vertices to leave as they are (measured elsewhere), or null.
void wall_thickness(const Mesh& m, const TriangleGrid& grid, const std::vector<Vec3>& normals, double eps,
                    std::size_t first, std::size_t last, std::vector<double>& wall, const std::uint8_t* skip = nullptr);

// What other processes measure of the check (make_shell over MPI): the walls of the
// flagged vertices, and the depths of the points in the flagged groups (PointDepths'
// groups, `spans` as group_spans made them; empty: none). `fill` writes their walls back (NaN: to be measured here after
// all) and adds up their points' figures (with the points, by the cloud's order, they
// could not decide: measured here).
struct CheckElsewhere {
    std::vector<std::uint8_t> vertex;
    std::vector<std::uint8_t> groups;
    std::vector<PointDepths::Span> spans;
    std::function<void(std::vector<double>& wall, PointDepths::Figures& points)> fill;
    // Where set, the shell's topology (measure_shell's: the surface's figures need the
    // whole mesh's adjacency), counted elsewhere in part (slab_topology.hpp).
    std::function<Topology()> topology;
};

// How far a check's walls and depths have come (Told): between its rounds, kCheckRounds
// of the walls with the depths' first pass, as many of the second.
constexpr int kCheckRounds = 16;

// measure_quality (surface) or measure_shell with the walls and depths `elsewhere` names
// taken from `elsewhere.fill`: the same figures.
MeshQuality measure_sharing(const Mesh& mesh, const PointCloud& points, double offset, double voxel, bool surface,
                            const CheckElsewhere& elsewhere, const Told& told = nullptr);
// measure_quality (surface) or measure_shell, told how far it has come.
MeshQuality measure_told(const Mesh& mesh, const PointCloud& points, double offset, double voxel, bool surface,
                         const Told& told);

struct KeptRange;  // solver/shared_filing.hpp
// measure_check_share at another process, where it may have kept its range of the points
// filed by all (null: none), for a share that names groups of it.
CheckShareFigures measure_check_share(CheckShare share, KeptRange* kept);

}  // namespace snvr::detail
