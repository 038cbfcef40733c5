// The points a run works on, compact and searchable (lib/src/geometry/point_cloud.cpp),
// and what geometry does to points before a run: the outlier rules' settings, clusters,
// a mesh's triangles sampled into points.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "snvr/geometry.hpp"

namespace snvr {

using Vec3f = std::array<float, 3>;

namespace detail {
class PointTree;
struct CloudAccess;  // the library's stages reach the tree through it (geometry/point_tree.hpp)
}

// Float coordinates about an origin (world = origin + coordinate, summed in double):
// 12 bytes a point and 4 for its place in the input, against 24 for a PointSet. The
// points are kept in a spatial (Morton) order and filed once into a tree of boxes that
// every stage of a run searches (outliers, sampling gap, distance, depth guard, check),
// so a stage looks at single points only where a box's bound is close to its threshold.
// Float holds a point to 6e-8 of its distance from the origin: with the origin near the
// points, a 1e6-cell grid's voxel is still 16 times coarser. A float file's points near
// the world origin are held exactly (origin 0).
class PointCloud {
public:
    PointCloud();
    // Rounds each point to float about an origin: 0 when every coordinate is a float or
    // the points' box is near the world origin (its centre no farther from it than its
    // longest side), else round_centre(points). Throws InputError for a non-finite
    // coordinate (naming the point, counted from 0), ResourceError beyond 2^32 - 1 points.
    explicit PointCloud(const PointSet& points);
    // The same from n points as 3n coordinates x0 y0 z0 x1 ... (a numpy (n, 3) array), read
    // straight into the cloud.
    PointCloud(const double* xyz, std::size_t n);
    PointCloud(const float* xyz, std::size_t n);
    // Takes coordinates about `origin`, as the readers make them; the same errors.
    PointCloud(std::vector<Vec3f> coordinates, const Vec3& origin);
    PointCloud(const PointCloud&);
    PointCloud& operator=(const PointCloud&);
    PointCloud(PointCloud&&) noexcept;
    PointCloud& operator=(PointCloud&&) noexcept;
    ~PointCloud();

    std::size_t size() const;
    bool empty() const { return size() == 0; }
    // Point k in the cloud's own (spatial) order, in world units.
    Vec3 operator[](std::size_t k) const;
    // Point k's place in the input it was made from (0-based).
    std::size_t input_index(std::size_t k) const;
    const Vec3& origin() const;
    // The points' box in world units, {lo, hi} (both the origin for no points).
    std::array<Vec3, 2> box() const;
    // The points in world units, in input order.
    PointSet to_point_set() const;
    // The memory the cloud holds: its coordinates, their input places and the tree over them.
    std::size_t bytes() const;

    // Keeps the points whose flag (by the cloud's order) is set: the order of the rest, and
    // each one's input index, stay as they were.
    void keep(const std::vector<std::uint8_t>& flags);
    // Multiplies every point by factor (> 0): a change of units, in float.
    void scale(double factor);
    // Adds `by` to every point (the origin moves; the coordinates stay).
    void translate(const Vec3& by);

private:
    friend struct detail::CloudAccess;
    std::unique_ptr<detail::PointTree> tree_;
};

// round_centre (geometry.hpp) of a cloud's points.
Vec3 round_centre(const PointCloud& points);

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
// min_cluster points and under 1% of all, or if they lie far from the largest cluster
// with under far_cluster_share of all. In between, with `strays`, the points that
// the density let through because they lie within a few spacings of the surface, where
// each would raise a bump on the shell: a point whose nearest neighbour is unusually far
// and that stands clearly off the plane of its 16 nearest neighbours (by over six times
// their scatter about it and over half the distance to the farthest of them). Points on
// edges, corners and thin detail have no flat neighbourhood to stand off.
struct OutlierSettings {
    std::size_t neighbours = 8;
    double reach_factor = 3;
    std::size_t min_cluster = 10;
    // Clusters far from the largest (farther from its box than far_cluster_distance times
    // its longest side), each under far_cluster_share of the points: stray returns that
    // would set the grid. At most 5% of the points go this way.
    double far_cluster_distance = 1;
    double far_cluster_share = 0.01;
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
    // The kept points' clusters at `link` (count_point_clusters), found on the way; 0 when
    // the rules did not end on a count of the points as kept.
    std::size_t clusters = 0;
};
// Points on a mesh's triangles at most `spacing` apart: every vertex, each edge once
// (in equal parts), and each triangle's inside on the barycentric grid of its longest
// edge's parts. Throws ResourceError, before allocating, beyond max_points (50 million:
// 1.2 GB of points, and about as much again for their index and distances; the bunny's
// shell as an STL, thickened again at 1024 cells, takes about 22 million).
PointSet sample_triangles(const Mesh& mesh, double spacing, std::size_t max_points = 50000000);

}  // namespace snvr
