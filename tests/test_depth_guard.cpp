// keep_points_deep: the mesh is lifted, smoothly, until every point inside is at least
// the depth from it; points already deep and points outside are left alone.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "mesh_fields.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh.hpp"
#include "mesh/triangle_grid.hpp"
#include "geometry/vec3_math.hpp"

using namespace snvr;
using namespace snvr::testing;

namespace {

// Dual-marching-cubes sphere of radius r0 (world) around c, 3 cells per unit length
// coarse enough that flat triangles cut well inside the sphere.
Mesh coarse_sphere(const Vec3& c, double r0, double h) {
    const int n = int(std::ceil(2 * (r0 + 3 * h) / h)) + 2;
    const Vec3 origin{c[0] - n * h / 2, c[1] - n * h / 2, c[2] - n * h / 2};
    const Grid g = make_grid(n, n, n, h, origin, [&](const Vec3& p, int, int, int) {
        return std::tanh((r0 - dist(p, c)) / (1.5 * h));
    });
    return extract_dual_isosurface(g.field, g.domain);
}

// Brute force: the smallest distance from p to any triangle.
double depth_of(const Mesh& m, const Vec3& p) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& t : m.triangles)
        best = std::min(best, point_triangle_dist_sq(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]));
    return std::sqrt(best);
}

}  // namespace

TEST_CASE("a ball meshed two cells in radius: every point inside ends at least the depth deep") {
    const double h = 0.1, r0 = 0.2;
    const Vec3 c{0.013, -0.021, 0.007};
    Mesh m = coarse_sphere(c, r0, h);
    const PointSet points{c, {c[0] + 0.02, c[1], c[2]}, {c[0], c[1] - 0.015, c[2] + 0.01}};
    double before = 1e30;
    for (const Vec3& p : points) before = std::min(before, depth_of(m, p));
    const double depth = 0.19;
    REQUIRE(before < depth);  // the flat triangles cut into the ball of radius 0.19
    const Mesh original = m;

    const DepthGuardReport r = keep_points_deep(m, points, depth, h);
    MESSAGE("depth before " << before << ", near " << r.near_vertices << ", moved " << r.moved_vertices
                            << ", repairs " << r.repair_rounds << ", shallow " << r.shallow_points);
    CHECK(r.near_vertices > 0);
    CHECK(r.moved_vertices >= r.near_vertices);
    CHECK(r.shallow_points == 0);
    for (const Vec3& p : points) CHECK(depth_of(m, p) >= depth);
    check_printable(check_mesh(m));
    CHECK(m.triangles == original.triangles);
    for (const auto& t : m.triangles) {  // none turned over
        const Vec3 a = cross(sub(m.vertices[t[1]], m.vertices[t[0]]), sub(m.vertices[t[2]], m.vertices[t[0]]));
        const Vec3 b = cross(sub(original.vertices[t[1]], original.vertices[t[0]]),
                             sub(original.vertices[t[2]], original.vertices[t[0]]));
        CHECK(dot(a, b) > 0);
    }
    // Lifted outward only, and by about what was missing, not more.
    double most = 0;
    for (std::size_t v = 0; v < m.vertices.size(); ++v) {
        CHECK(dist(m.vertices[v], c) >= dist(original.vertices[v], c) - 1e-12);
        most = std::max(most, dist(m.vertices[v], original.vertices[v]));
    }
    CHECK(most <= depth - before + 0.2 * h);
}

TEST_CASE("points with no other point within `lone` are left out") {
    const double h = 0.1, r0 = 0.2;
    const Vec3 c{0.013, -0.021, 0.007};
    const Mesh original = coarse_sphere(c, r0, h);
    const PointSet points{c, {c[0] + 0.02, c[1], c[2]}, {c[0], c[1] - 0.015, c[2] + 0.01}};  // 0.018-0.025 apart
    Mesh alone = original;
    const DepthGuardReport a = keep_points_deep(alone, points, 0.19, h, 0.01);
    CHECK(a.lone_points == 3);
    CHECK(a.near_vertices == 0);
    CHECK(alone.vertices == original.vertices);
    Mesh linked = original;
    const DepthGuardReport b = keep_points_deep(linked, points, 0.19, h, 0.05);
    CHECK(b.lone_points == 0);
    CHECK(b.shallow_points == 0);
    for (const Vec3& p : points) CHECK(depth_of(linked, p) >= 0.19);
}

TEST_CASE("points already deep, and points outside, leave the mesh as it is") {
    const double h = 0.05, r0 = 0.5;
    const Vec3 c{0, 0, 0};
    Mesh m = coarse_sphere(c, r0, h);
    const Mesh original = m;
    const PointSet points{c, {0.1, 0, 0}, {0, 0.9, 0}};  // the last lies outside, 0.4 from the sphere
    const DepthGuardReport r = keep_points_deep(m, points, 0.3, h);
    CHECK(r.near_vertices == 0);
    CHECK(r.moved_vertices == 0);
    CHECK(r.shallow_points == 0);
    CHECK(m.vertices == original.vertices);

    // A point just outside the surface is not under it: nothing is lifted for it.
    const PointSet outside{{0, 0, r0 + 0.02}};
    const DepthGuardReport o = keep_points_deep(m, outside, 0.1, h);
    CHECK(o.near_vertices == 0);
    CHECK(m.vertices == original.vertices);
}

TEST_CASE("keep_points_deep rejects a depth or voxel that is not positive and finite") {
    Mesh m = coarse_sphere({0, 0, 0}, 0.5, 0.1);
    const PointSet points{{0, 0, 0}};
    CHECK_THROWS_AS(keep_points_deep(m, points, 0, 0.1), ParameterError);
    CHECK_THROWS_AS(keep_points_deep(m, points, 0.1, -1), ParameterError);
    CHECK_THROWS_AS(keep_points_deep(m, points, std::nan(""), 0.1), ParameterError);
    CHECK_THROWS_AS(keep_points_deep(m, points, 0.1, 0.1, 0), ParameterError);
    Mesh broken = m;
    broken.triangles[0][0] = std::uint32_t(broken.vertices.size());
    CHECK_THROWS_AS(keep_points_deep(broken, points, 0.1, 0.1), InputError);
}
