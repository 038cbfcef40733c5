// The whole method: points in, phase field out (mesh it with extract_isosurface).
#pragma once
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "snvr/domain.hpp"
#include "snvr/field.hpp"
#include "snvr/geometry.hpp"
#include "snvr/mesh.hpp"
#include "snvr/parameters.hpp"
#include "snvr/point_cloud.hpp"

namespace snvr {

struct StepStats {
    int step = 0;                        // 1-based
    int cycles = 0;                      // V-cycles used
    bool converged = false;              // residual below tol within max_cycles
    double initial_residual = 0;         // before the first cycle
    double residual = 0;                 // after the last cycle
    std::vector<double> cycle_residuals; // after each cycle
    double seconds_linear = 0, seconds_nonlinear = 0;
    double bytes_moved = 0;              // least memory traffic of the step's operations
};

struct StageSeconds {
    double domain = 0;     // fitting the grid, gap estimate, kd-tree
    double distance = 0;   // unsigned distance in the band
    double init = 0;       // phase field, g, coarse coefficients
    double steps = 0;      // all time steps
    double total = 0;
};

struct Result {
    Domain domain;
    Field phi;                    // phi^{Nt} in the band's bricks (+-1 beyond); the shell is where phi > 0
    double offset = 0;            // l used, world units
    std::string offset_reason;    // why this offset (given, 2.5 voxels, sampling gap)
    double gap = 0;               // estimated sampling gap of the points (world)
    double eps = 0, xi = 0;       // world units
    double dt = 0;                // normalised
    double tube_inner = 0, tube_outer = 0;  // the tube's sides, world units from the offset (0: free flow)
    std::string backend;          // which backend ran
    std::size_t active_cells = 0; // cells with g > 0
    std::size_t active_bricks = 0, total_bricks = 0;
    std::size_t solver_bytes = 0; // memory held by the solver's fields
    std::vector<StepStats> steps;
    StageSeconds seconds;
    std::vector<std::string> warnings;
};

struct Progress {
    std::string stage;      // "domain", "distance", "init", "step"
    int step = 0, steps = 0;
    const StepStats* stats = nullptr;  // set for "step"
    std::string message;
};
using ProgressCallback = std::function<void(const Progress&)>;

// Fits the grid (see fit_domain), computes the distance, runs the split scheme.
// Throws InputError / ParameterError / ResourceError with a message naming the problem.
Result reconstruct(const PointCloud& points, const Parameters& params, const ProgressCallback& progress = {});
Result reconstruct(const PointSet& points, const Parameters& params,
                   const ProgressCallback& progress = {});  // makes a PointCloud

// The shell's surface: the zero level set of result.phi, meshed the way snvr-cl does
// (closed, manifold, outward), faired (fair_mesh), and, when the run kept a tube, lifted where the mesh dips
// nearer to a point than the tube's inner wall (keep_points_deep; every point when the
// offset is at least the sampling gap, else the points with a neighbour within the
// offset). `points` are the reconstruction's input. One place for the default mesher.
Mesh shell_mesh(const Result& result, const PointCloud& points, DepthGuardReport* guard = nullptr,
                const MeshFairing& fairing = {});
Mesh shell_mesh(const Result& result, const PointSet& points, DepthGuardReport* guard = nullptr,
                const MeshFairing& fairing = {});  // makes a PointCloud

// Clusters of points linked by distances below link_distance. A shell of offset l joins
// points closer than 2l, so a result with more solid pieces (MeshReport::solids) than
// count_point_clusters(points, 2 l) has broken apart (the offset is below half the gaps
// in the sampling).
std::size_t count_point_clusters(const PointCloud& points, double link_distance);
std::size_t count_point_clusters(const PointSet& points, double link_distance);  // makes a PointCloud

// Points that are not surface, as scanners and the paper's Fig. 10 (5-15% uniform
// random points) add them. First each point whose `neighbours`-th nearest point is
// farther than reach_factor times the median of that distance: the surface is dense
// where a point in space is not, and outliers up to half the points do not move a
// median (left in, they would set the sampling gap and so the offset; the median is
// taken over up to median_sample points evenly strided in input order). Then, among the
// rest, the clusters a shell of the offset planned for them (2 l: see
// count_point_clusters) would leave apart as loose beads, if they have fewer than
// min_cluster points and under 1% of all. In between, with `strays`, the points that
// the density let through because they lie within a few spacings of the surface, where
// each would raise a bump on the shell: a point whose nearest neighbour is unusually far
// and that stands clearly off the plane of its 16 nearest neighbours (by over six times
// their scatter about it and over half the distance to the farthest of them). Points on
// edges, corners and thin detail have no flat neighbourhood to stand off.
struct OutlierSettings {
    std::size_t neighbours = 8;
    double reach_factor = 3;
    std::size_t min_cluster = 10;
    std::size_t median_sample = 100000;
    bool strays = true;
    void validate() const;  // throws ParameterError naming the bad value
};
struct OutlierSplit {
    PointSet kept, outliers;  // each in input order
    double link = 0;          // 2 l, the clusters' link (0 when none was looked for)
};
struct DroppedOutliers {
    PointSet points;  // the outliers, world units, in input order
    std::vector<std::size_t> input_indices;  // each one's place in the input (0-based), ascending
    double link = 0;  // as OutlierSplit's
};
// Points on a mesh's triangles at most `spacing` apart: every vertex, each edge once
// (in equal parts), and each triangle's inside on the barycentric grid of its longest
// edge's parts. Throws ResourceError, before allocating, beyond max_points (50 million:
// 1.2 GB of points, and about as much again for their index and distances; the bunny's
// shell as an STL, thickened again at 1024 cells, takes about 22 million).
PointSet sample_triangles(const Mesh& mesh, double spacing, std::size_t max_points = 50000000);

OutlierSplit split_outliers(const PointSet& points, const Parameters& params, const OutlierSettings& settings = {});
// The same rules on a cloud, in place: the outliers leave `points` and are returned.
DroppedOutliers drop_outliers(PointCloud& points, const Parameters& params, const OutlierSettings& settings = {});

// The grid reconstruct() would use, and the offset and gap it would choose.
struct DomainPlan {
    Domain domain;
    double offset = 0;
    std::string offset_reason;
    double gap = 0;
    double eps = 0, xi = 0;       // world units
    double dt = 0;                // normalised
    int steps = 0;
    double tube_inner = 0, tube_outer = 0;  // world units from the offset; 0: free flow
    std::size_t estimated_bytes = 0;  // what follows the box: brick tables, the mesher's sign bits (the band's fields come later)
};
DomainPlan plan_domain(const PointCloud& points, const Parameters& params);
DomainPlan plan_domain(const PointSet& points, const Parameters& params);  // makes a PointCloud

}  // namespace snvr
