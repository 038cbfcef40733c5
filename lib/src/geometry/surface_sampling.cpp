// sample_triangles (point_cloud.hpp): a mesh given as input becomes points on its
// triangles, so that its faces, not only its corners, are thickened.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_set>

#include "geometry/vec3_math.hpp"
#include "snvr/error.hpp"
#include "snvr/point_cloud.hpp"

namespace snvr {
namespace {

// Parts of at most `spacing` along a segment of this length (at least 1).
std::uint64_t parts(double length, double spacing) {
    const double n = std::ceil(length / spacing);
    return n < 1 ? 1 : n > 1e9 ? std::uint64_t(1e9) : std::uint64_t(n);
}

}  // namespace

PointSet sample_triangles(const Mesh& mesh, double spacing, std::size_t max_points) {
    if (!(spacing > 0) || !std::isfinite(spacing))
        throw ParameterError("the sampling spacing must be a positive number");
    const auto edge_key = [](std::uint32_t a, std::uint32_t b) {
        return std::uint64_t(std::min(a, b)) << 32 | std::max(a, b);
    };
    // Count first: a fine spacing on a large mesh must fail before it allocates.
    std::uint64_t total = mesh.vertices.size();
    std::unordered_set<std::uint64_t> edges;
    for (const auto& t : mesh.triangles) {
        std::uint64_t n = 1;
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t a = t[c], b = t[(c + 1) % 3];
            const std::uint64_t k = parts(norm(sub(mesh.vertices[a], mesh.vertices[b])), spacing);
            n = std::max(n, k);
            if (a != b && edges.insert(edge_key(a, b)).second) total += k - 1;
        }
        total += n >= 3 ? (n - 1) * (n - 2) / 2 : 0;
        if (total > max_points)
            throw ResourceError("sampling the mesh's " + std::to_string(mesh.triangles.size()) + " triangles at " +
                                std::to_string(spacing) + " would take more than " + std::to_string(max_points) +
                                " points: give a coarser --resolution or a larger --voxel");
    }
    PointSet points(mesh.vertices);
    points.reserve(total);
    edges.clear();
    for (const auto& t : mesh.triangles) {
        const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
        std::uint64_t n = 1;
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t i = t[e], j = t[(e + 1) % 3];
            const Vec3 &p = mesh.vertices[i], &q = mesh.vertices[j];
            const std::uint64_t k = parts(norm(sub(p, q)), spacing);
            n = std::max(n, k);
            if (i == j || !edges.insert(edge_key(i, j)).second) continue;
            for (std::uint64_t m = 1; m < k; ++m) {
                const double s = double(m) / double(k);
                points.push_back({p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1]), p[2] + s * (q[2] - p[2])});
            }
        }
        // The inside on the barycentric grid of the longest edge's parts.
        for (std::uint64_t i = 1; i + 1 < n; ++i)
            for (std::uint64_t j = 1; i + j < n; ++j) {
                const double u = double(i) / double(n), v = double(j) / double(n), w = 1 - u - v;
                points.push_back({w * a[0] + u * b[0] + v * c[0], w * a[1] + u * b[1] + v * c[1],
                                  w * a[2] + u * b[2] + v * c[2]});
            }
    }
    return points;
}

}  // namespace snvr
