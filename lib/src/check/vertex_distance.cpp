// vertex_distance (quality.hpp): each mesh's vertices filed in a point tree, the other's
// looked up in it.
#include <algorithm>
#include <cmath>

#include "geometry/point_tree.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/quality.hpp"

namespace snvr {

namespace {

// From each of `from`'s vertices to the nearest of `to`'s: the largest and the sum of squares.
void nearest_of(const Mesh& from, const Mesh& to, double& most, double& squares) {
    if (from.vertices.empty() || to.vertices.empty()) return;
    const PointCloud targets(to.vertices);
    const detail::PointTree& tree = detail::tree_of(targets);
    const std::ptrdiff_t n = std::ptrdiff_t(from.vertices.size());
    double local_most = 0, local_squares = 0;
#pragma omp parallel for reduction(max : local_most) reduction(+ : local_squares)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
        const double d = tree.nearest(from.vertices[std::size_t(i)]).dist_sq;
        local_most = std::max(local_most, d);
        local_squares += d;
    }
    most = std::max(most, std::sqrt(local_most));
    squares += local_squares;
}

}  // namespace

VertexDistance vertex_distance(const Mesh& a, const Mesh& b) {
    VertexDistance d;
    double squares = 0;
    nearest_of(a, b, d.max, squares);
    nearest_of(b, a, d.max, squares);
    const std::size_t n = a.vertices.size() + b.vertices.size();
    d.rms = n ? std::sqrt(squares / double(n)) : 0;
    return d;
}

}  // namespace snvr
