// The walls of a shell: from each vertex along its inward normal, the distance to the
// first triangle met (measure_quality's walls, thinnest_wall, and a process's share of
// them: CheckShare in tiles.hpp); and what other processes measure of a check.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "check/mesh_topology.hpp"
#include "check/point_depths.hpp"
#include "check/slab_mesh.hpp"
#include "check/slab_queries.hpp"
#include "check/slab_shares.hpp"
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
// The same for a mesh whose box is [lo, hi] (not empty).
double wall_epsilon(const Vec3& lo, const Vec3& hi);

// wall[v] for the vertices order[k], k in [first, last): the distance from vertex v along
// its inward normal to the first triangle met, ignoring the vertex's own triangles;
// infinity when nothing is met (and where the normal vanishes).
// skip: vertices to leave as they are (measured elsewhere), or null.
void wall_thickness(const Mesh& m, const TriangleGrid& grid, const std::vector<Vec3>& normals, double eps,
                    const std::vector<std::uint32_t>& order, std::size_t first, std::size_t last,
                    std::vector<double>& wall, const std::uint8_t* skip = nullptr);

// Casts the walls' rays elsewhere (an OpenCL device: devices/check_device.hpp): wall[order[k]]
// as wall_thickness would give it for every k; returns where it cast them, or "" where it
// could not (the host casts them then).
using WallRays = std::function<std::string(const Mesh& m, const TriangleGrid& grid, const std::vector<Vec3>& normals,
                                           double eps, const std::vector<std::uint32_t>& order, std::vector<double>& wall)>;

// The vertices in the order their walls are measured in: by blocks of space (a coarse
// Morton order of 64 blocks an axis over the mesh's box), so that rays cast one after
// another meet the same cells, triangles and vertices in the caches; each wall is the same
// in any order. (The bunny at 1024 cells: its rays 16-20% faster than in the mesher's order,
// one thread or two.)
std::vector<std::uint32_t> wall_order(const Mesh& m);

// What other processes measure of the check (make_shell over MPI, with the surface's
// figures): the walls of the flagged vertices, and the depths of the points in the flagged
// groups (PointDepths' groups, `spans` as group_spans made them; empty: none). `fill`
// writes their walls back and adds up their points' figures, every one decided (what no
// share could, asked of the slabs: slab_queries.hpp).
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
// measure_shell's figures from its parts: the topology, every vertex's wall (reordered) and
// the points' figures (the depths reordered).
MeshQuality shell_figures(const Topology& topology, std::size_t points, double offset, double voxel,
                          std::vector<double>& walls, PointDepths::Figures& depths);
// measure_quality (surface) or measure_shell, told how far it has come; the walls' rays cast
// by `rays` where given (and able).
MeshQuality measure_told(const Mesh& mesh, const PointCloud& points, double offset, double voxel, bool surface,
                         const Told& told, const WallRays& rays = nullptr);

// Every group of `depths` measured, in chunks over the threads.
void measure_groups(PointDepths& depths);

struct KeptRange;  // solver/shared_filing.hpp
// measure_check_share at another process, where it may have kept its range of the points
// filed by all (null: none), for a share that names groups of it; what the share cannot
// decide asked of the slabs (every process at once: slab_queries.hpp; `ready`: this slab's
// answers, made before, or null: made then), so that every wall and point comes back
// decided. measured_whole: each measured vertex's number in the whole mesh.
CheckShareFigures measure_check_share(CheckShare share, KeptRange* kept, const std::vector<std::uint32_t>& measured_whole,
                                      const SlabMesh& slabs, TileScheduler& on, const SlabAnswers* ready);

// The first process's own share of the check: the walls of share.measured, and the depths
// of the groups of `points` made as `spans` that `elsewhere` does not flag (the sampled
// ones' too); `before_asking` run once they are measured, then what the share cannot
// decide asked of the slabs (as the others do; `ready`: this slab's answers, or null).
// eps and reach: the shell's, as the others'.
struct FirstShare {
    std::vector<double> walls;  // share.measured's
    PointDepths::Figures points;
    std::uint64_t points_asked = 0;  // of the slabs, by every process
};
FirstShare measure_first_share(ShareMesh share, const PointTree& points, double voxel,
                               const std::vector<PointDepths::Span>& spans, const std::vector<std::uint8_t>& elsewhere,
                               double eps, double reach, const SlabMesh& slabs, TileScheduler& on,
                               const SlabAnswers* ready, const std::function<void()>& before_asking,
                               const Told& told);

}  // namespace snvr::detail
