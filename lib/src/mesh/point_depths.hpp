// How deep each point lies below a closed mesh's surface (point_depths.cpp).
#pragma once
#include <cstddef>
#include <vector>

#include "geometry/point_tree.hpp"
#include "mesh/triangle_grid.hpp"
#include "snvr/geometry.hpp"

namespace snvr::detail {

struct TriangleFrame;  // point_depths.cpp

// The points in groups of nearby points (nodes of the tree), each group with the
// triangles that can be nearest to one of its points: within d + 2 r of the group's
// centre, d its distance to the surface and r its radius. Every point is then tested
// against its group's few dozen triangles, in float and in parallel lanes, and the
// nearest found again in double: the exact squared distance of the nearest triangle.
class PointDepths {
public:
    // `voxel` bounds a group's radius (its triangles are those within a few voxels).
    PointDepths(const Mesh& mesh, const TriangleGrid& grid, const PointTree& points, double voxel);
    ~PointDepths();

    std::size_t groups() const { return groups_.size(); }
    // For the points of groups [first, last): depth[k] = their distance to the surface,
    // negated (-0 for 0) when outside; inside by the side of the nearest triangle where
    // the point's foot lies clear inside its face, else (or always when `by_rays`) by
    // the parity of a ray's crossings. Neighbouring groups in one call share a bound.
    void measure(std::size_t first, std::size_t last, bool by_rays, std::vector<double>& depth) const;

private:
    // One group, its centre's squared distance to the surface given; scratch: the
    // call's working space (point_depths.cpp).
    void measure_group(const PointTree::Node& node, const Vec3& centre, double centre_sq, bool by_rays, void* scratch,
                       std::vector<double>& depth) const;

    const Mesh& mesh_;
    const TriangleGrid& grid_;
    const PointTree& points_;
    std::vector<const PointTree::Node*> groups_;
    std::vector<TriangleFrame> frames_;  // each triangle's, as the lanes take it
    Vec3 lo_{0, 0, 0}, hi_{0, 0, 0};  // the mesh's box, for the rays' directions
};

}  // namespace snvr::detail
