// What is done to the points before a run: outliers dropped, clusters counted, and a
// mesh's triangles sampled into points (to thicken a mesh).
#pragma once
#include <cstddef>
#include <vector>

#include "snvr/geometry.hpp"
#include "snvr/mesh.hpp"
#include "snvr/parameters.hpp"
#include "snvr/point_cloud.hpp"

namespace snvr {

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

OutlierSplit split_outliers(const PointSet& points, const Parameters& params, const OutlierSettings& settings = {});
// The same rules on a cloud, in place: the outliers leave `points` and are returned.
DroppedOutliers drop_outliers(PointCloud& points, const Parameters& params, const OutlierSettings& settings = {});

}  // namespace snvr
