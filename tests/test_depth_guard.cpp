// keep_points_deep: the mesh is lifted, smoothly, until every point inside is at least
// the depth from it; points already deep and points outside are left alone.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "with_threads.hpp"
#include "mesh_fields.hpp"
#include "snvr/error.hpp"
#include "snvr/quality.hpp"
#include "snvr/shell.hpp"
#include "snvr/mesh.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/shapes.hpp"
#include "reference_index.hpp"
#include "snvr/point_cloud.hpp"
#include "mesh/triangle_grid.hpp"
#include "mesh/vertex_lists.hpp"
#include "pipeline/shell_mesh.hpp"
#include "geometry/vec3_math.hpp"

// The library's OpenMP runtime (linked with it): the tests compare thread counts.
extern "C" void omp_set_num_threads(int);
extern "C" int omp_get_max_threads();

// The depth guard as it was before it searched with grids (commit a327733), serial: the
// reference that the faster one must match bit for bit, ties included. One change since:
// of equally near triangles a repair takes the lowest (it took the first in its point
// index's order, which cost the guard an index of every vertex to reproduce).
namespace snvr::reference {

using detail::fans;
using detail::rings;
using detail::VertexLists;

// Vertices are aimed this far (in voxels) beyond the depth: a triangle about a voxel
// across on a ball of radius 2 voxels sags about 0.1 voxel between its corners.
constexpr double kMarginVoxels = 0.1;
// Rounds of (largest of the ring, then mean of the ring) that spread each lift.
constexpr int kSpreadRounds = 2;
// Repair rounds for the points still too shallow after the first lift; each lifts the
// nearest triangle of each such point by what it lacks.
constexpr int kRepairRounds = 8;
constexpr int kUntangleRounds = 16;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Widens each lift to the vertex's ring, then averages it over the ring: a lift on one
// vertex becomes a smooth bump over two rings.
void spread(const VertexLists& rings, std::vector<double>& lift) {
    const std::ptrdiff_t nv = std::ptrdiff_t(lift.size());
    std::vector<double> wide(lift.size());
    for (int round = 0; round < kSpreadRounds; ++round) {
        for (std::ptrdiff_t v = 0; v < nv; ++v) {
            double m = lift[v];
            for (std::size_t r = rings.start[v]; r < rings.start[v + 1]; ++r) m = std::max(m, lift[rings.items[r]]);
            wide[v] = m;
        }
        for (std::ptrdiff_t v = 0; v < nv; ++v) {
            double sum = wide[v];
            for (std::size_t r = rings.start[v]; r < rings.start[v + 1]; ++r) sum += wide[rings.items[r]];
            lift[v] = sum / double(1 + rings.start[v + 1] - rings.start[v]);
        }
    }
}

// Moves every vertex from where it started by its displacement, and returns how many
// triangles now face against where they faced before (turned over).
std::size_t place(Mesh& mesh, const std::vector<Vec3>& start, const std::vector<Vec3>& shift,
                  const std::vector<Vec3>& faces, std::vector<std::uint8_t>& turned) {
    for (std::size_t v = 0; v < start.size(); ++v)
        for (int d = 0; d < 3; ++d) mesh.vertices[v][d] = start[v][d] + shift[v][d];
    std::size_t count = 0;
    for (std::size_t t = 0; t < faces.size(); ++t) {
        turned[t] = dot(faces[t], faces[t]) > 0 && dot(face_vector(mesh, mesh.triangles[t]), faces[t]) <= 0;
        count += turned[t];
    }
    return count;
}

// Lifts along neighbouring normals differ, and a sliver of a triangle a hundredth of a
// voxel across turns over under the difference. Giving its corners their mean shift
// moves it without turning it; repeated until no triangle is turned, or the rounds end
// (then those triangles' corners go back to where they started).
void untangle(Mesh& mesh, const std::vector<Vec3>& start, std::vector<Vec3>& shift, const std::vector<Vec3>& faces) {
    std::vector<std::uint8_t> turned(faces.size());
    for (int round = 0; round < kUntangleRounds; ++round) {
        if (place(mesh, start, shift, faces, turned) == 0) return;
        for (std::size_t t = 0; t < faces.size(); ++t) {
            if (!turned[t]) continue;
            const auto& tri = mesh.triangles[t];
            Vec3 mean{0, 0, 0};
            for (std::uint32_t v : tri)
                for (int d = 0; d < 3; ++d) mean[d] += shift[v][d] / 3;
            for (std::uint32_t v : tri) shift[v] = mean;
        }
    }
    if (place(mesh, start, shift, faces, turned) == 0) return;
    for (std::size_t t = 0; t < faces.size(); ++t)
        if (turned[t])
            for (std::uint32_t v : mesh.triangles[t]) shift[v] = {0, 0, 0};
    place(mesh, start, shift, faces, turned);
}

// Each vertex's nearest point, if nearer than `bound`.
std::vector<Index::Hit> nearest_points(const Mesh& mesh, const Index& index, double bound) {
    const std::ptrdiff_t nv = std::ptrdiff_t(mesh.vertices.size());
    std::vector<Index::Hit> hits(mesh.vertices.size());
    for (std::ptrdiff_t v = 0; v < nv; ++v) hits[v] = index.nearest(mesh.vertices[v], bound * bound);
    return hits;
}

double triangle_distance(const Mesh& m, const Vec3& p, std::uint32_t t) {
    const auto& tri = m.triangles[t];
    return std::sqrt(point_triangle_dist_sq(p, m.vertices[tri[0]], m.vertices[tri[1]], m.vertices[tri[2]]));
}

// A point that some triangle comes within depth + slack of, with those triangles.
struct Watched {
    std::size_t point;
    std::vector<std::uint32_t> triangles;
};

// Every point that a triangle comes within `within` of. Each spot of a triangle lies
// within longest edge / sqrt 3 (the largest circumradius) of one of its corners, so
// the corners within `within` + that of the point find every such triangle.
std::vector<Watched> watch_list(const Mesh& mesh, const PointSet& points, double within) {
    double longest = 0;
    for (const auto& t : mesh.triangles)
        for (int e = 0; e < 3; ++e)
            longest = std::max(longest, norm(sub(mesh.vertices[t[e]], mesh.vertices[t[(e + 1) % 3]])));
    const double reach = within + longest / std::sqrt(3.0);
    const Index corners(mesh.vertices);
    const VertexLists fan = fans(mesh);
    std::vector<Watched> watched;
    const std::ptrdiff_t np = std::ptrdiff_t(points.size());
    {
        std::vector<Watched> mine;
        for (std::ptrdiff_t p = 0; p < np; ++p) {
            const Vec3& at = points[p];
            Watched w{std::size_t(p), {}};
            corners.for_each_within(at, reach, [&](std::size_t v) {
                for (std::size_t f = fan.start[v]; f < fan.start[v + 1]; ++f) {
                    // Each triangle once: from its first corner within reach.
                    const std::uint32_t t = fan.items[f];
                    for (std::uint32_t c : mesh.triangles[t]) {
                        if (c == v) {
                            if (triangle_distance(mesh, at, t) < within) w.triangles.push_back(t);
                            break;
                        }
                        if (norm(sub(mesh.vertices[c], at)) < reach) break;
                    }
                }
            });
            if (!w.triangles.empty()) mine.push_back(std::move(w));
        }
        for (Watched& w : mine) watched.push_back(std::move(w));
    }
    std::sort(watched.begin(), watched.end(), [](const Watched& a, const Watched& b) { return a.point < b.point; });
    return watched;
}

DepthGuardReport keep_points_deep(Mesh& mesh, const PointSet& input, double depth, double voxel, double lone) {  // NOLINT
    // The points as the library's guard takes them: as its cloud holds them, in its order.
    const PointCloud cloud(input);
    PointSet points(cloud.size());
    for (std::size_t k = 0; k < points.size(); ++k) points[k] = cloud[k];
    if (!(depth > 0) || !(voxel > 0) || !std::isfinite(depth) || !std::isfinite(voxel))
        throw ParameterError("keep_points_deep: depth and voxel must be positive and finite");
    if (!(lone > 0)) throw ParameterError("keep_points_deep: lone must be positive");
    DepthGuardReport report;
    if (mesh.triangles.empty() || points.empty()) return report;
    for (const auto& t : mesh.triangles)
        for (std::uint32_t v : t)
            if (v >= mesh.vertices.size()) throw InputError("keep_points_deep: a triangle uses a missing vertex");

    std::vector<Vec3> faces(mesh.triangles.size());
    for (std::size_t t = 0; t < faces.size(); ++t) faces[t] = face_vector(mesh, mesh.triangles[t]);
    const std::vector<Vec3> normals = vertex_normals(mesh, faces);
    const std::vector<Vec3> start = mesh.vertices;
    const Index index(points);
    // The points the promise covers: those with another point within `lone`.
    std::vector<std::uint8_t> kept(points.size(), 1);
    if (std::isfinite(lone)) {
        const std::ptrdiff_t np = std::ptrdiff_t(points.size());
        for (std::ptrdiff_t p = 0; p < np; ++p) kept[p] = index.nearest_other(std::size_t(p)) <= lone;
        for (std::uint8_t k : kept) report.lone_points += !k;
    }

    // Lift every vertex nearer than the aim to a kept point on its inner side.
    const double aim = depth + kMarginVoxels * voxel;
    const std::vector<Index::Hit> near = nearest_points(mesh, index, aim);
    std::vector<double> lift(mesh.vertices.size(), 0.0);
    for (std::size_t v = 0; v < lift.size(); ++v) {
        const std::size_t p = near[v].index;
        if (p != Index::npos && kept[p] && dot(sub(mesh.vertices[v], index.point(p)), normals[v]) > 0)
            lift[v] = aim - std::sqrt(near[v].dist_sq);
    }
    for (double x : lift) report.near_vertices += x > 0;
    if (report.near_vertices == 0) return report;
    spread(rings(mesh), lift);
    std::vector<Vec3> shift(mesh.vertices.size());
    for (std::size_t v = 0; v < shift.size(); ++v)
        for (int d = 0; d < 3; ++d) shift[v][d] = normals[v][d] * lift[v];
    untangle(mesh, start, shift, faces);

    // Then move the nearest triangle of each point still shallower than the depth along
    // its own normal, all three corners alike. The watch list holds every triangle
    // within a quarter voxel of the depth from a point; repairs move a few vertices by
    // a fraction of that, outward, away from the points inside.
    const std::vector<Watched> watched = watch_list(mesh, points, depth + 0.25 * voxel);
    for (report.repair_rounds = 0;; ++report.repair_rounds) {
        std::vector<Vec3> push(mesh.vertices.size(), Vec3{0, 0, 0});
        report.shallow_points = 0;
        for (const Watched& w : watched) {
            if (!kept[w.point]) continue;
            const Vec3& p = points[w.point];
            double dist = kInf;
            std::uint32_t nearest = 0;
            for (std::uint32_t t : w.triangles) {
                const double d = triangle_distance(mesh, p, t);
                if (d < dist || (d == dist && t < nearest)) dist = d, nearest = t;
            }
            if (!(dist < depth)) continue;
            const auto& t = mesh.triangles[nearest];
            const Vec3 n = face_vector(mesh, t);
            if (dot(sub(mesh.vertices[t[0]], p), n) <= 0) continue;  // the point is not under it
            ++report.shallow_points;
            const double by = (depth - dist + 0.5 * kMarginVoxels * voxel) / norm(n);
            for (std::uint32_t v : t)
                if (by * norm(n) > norm(push[v])) push[v] = {n[0] * by, n[1] * by, n[2] * by};
        }
        if (report.shallow_points == 0 || report.repair_rounds == kRepairRounds) break;
        for (std::size_t v = 0; v < shift.size(); ++v)
            for (int d = 0; d < 3; ++d) shift[v][d] += push[v][d];
        untangle(mesh, start, shift, faces);
    }
    for (const Vec3& d : shift) report.moved_vertices += dot(d, d) > 0;
    return report;
}


}  // namespace snvr::reference

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

namespace {

void check_same(const DepthGuardReport& a, const DepthGuardReport& b) {
    CHECK(a.near_vertices == b.near_vertices);
    CHECK(a.moved_vertices == b.moved_vertices);
    CHECK(a.repair_rounds == b.repair_rounds);
    CHECK(a.shallow_points == b.shallow_points);
    CHECK(a.lone_points == b.lone_points);
}

// The guard on a copy of m, by the reference and on 1 and 2 threads: the same vertices,
// bit for bit, and the same report. Returns the report.
DepthGuardReport check_against_reference(const Mesh& m, const PointSet& points, double depth, double voxel,
                                         double lone = std::numeric_limits<double>::infinity()) {
    Mesh expected = m;
    const DepthGuardReport r = reference::keep_points_deep(expected, points, depth, voxel, lone);
    for (int threads : {1, 2}) {
        Mesh got = m;
        const DepthGuardReport g =
            with_threads(threads, [&] { return keep_points_deep(got, points, depth, voxel, lone); });
        CHECK(got.triangles == m.triangles);
        CHECK(got.vertices == expected.vertices);
        check_same(g, r);
    }
    return r;
}


// A LiDAR-like scan reconstructed with a thin wall at 64 cells: the guard lifts vertices.
struct ThinScan {
    PointSet points;
    Result result;
};
ThinScan thin_wall_scan() {
    Parameters p;
    p.resolution = 64;
    p.offset = 0.025;
    p.device = "openmp";
    ThinScan s{shapes::lidar_scan({0.5, 0.5, 0.5}, 0.7, 0.01, 0.04, 0.001), {}};
    s.result = reconstruct(s.points, p);
    return s;
}

}  // namespace

TEST_CASE("the depth guard moves the vertices exactly as it did before it searched with grids") {
    // Coarse balls with random points just inside them: lifts, repairs, and points whose
    // nearest triangles tie (a shared edge or corner).
    int repaired = 0;
    for (unsigned seed = 1; seed <= 12; ++seed) {
        std::mt19937 rng(seed);
        std::uniform_real_distribution<double> u(-1, 1);
        const double h = 0.1, r0 = 0.2 + 0.02 * (seed % 5);
        const Vec3 c{0.013 * seed, -0.021, 0.007};
        const Mesh m = coarse_sphere(c, r0, h);
        PointSet points;
        while (points.size() < 40) {
            const Vec3 p{c[0] + r0 * u(rng), c[1] + r0 * u(rng), c[2] + r0 * u(rng)};
            if (dist(p, c) < r0 - 0.05) points.push_back(p);
        }
        const DepthGuardReport r = check_against_reference(m, points, 0.1 + 0.01 * (seed % 4), h);
        repaired += r.repair_rounds > 0;
    }
    MESSAGE(repaired << " of 12 balls needed repairs");
    CHECK(repaired > 0);

    // Far from the origin, as survey scans arrive: the points' float coordinates about
    // their own origin and the cells' double ones must still agree on every pair.
    for (unsigned seed = 1; seed <= 3; ++seed) {
        std::mt19937 rng(seed);
        std::uniform_real_distribution<double> u(-1, 1);
        const double h = 0.1, r0 = 0.25;
        const Vec3 c{512345.678 + 0.013 * seed, 4012345.25, 101.5};
        const Mesh m = coarse_sphere(c, r0, h);
        PointSet points;
        while (points.size() < 200) {
            const Vec3 p{c[0] + r0 * u(rng), c[1] + r0 * u(rng), c[2] + r0 * u(rng)};
            if (dist(p, c) < r0 - 0.04) points.push_back(p);
        }
        const DepthGuardReport r = check_against_reference(m, points, 0.12, h);
        CHECK(r.near_vertices > 0);
    }

    // A real shell (thin_wall_scan), and its points with a `lone` distance below their spacing.
    const ThinScan thin = thin_wall_scan();
    const PointSet& scan = thin.points;
    const Result& result = thin.result;
    Mesh shell = extract_dual_isosurface(result.phi, result.domain);
    fair_mesh(shell);
    const double depth = result.offset - result.tube_inner;
    const DepthGuardReport r = check_against_reference(shell, scan, depth, result.domain.h);
    MESSAGE("scan: near " << r.near_vertices << ", moved " << r.moved_vertices << ", repairs " << r.repair_rounds);
    CHECK(r.near_vertices > 0);
    check_against_reference(shell, scan, depth, result.domain.h, 0.008);
}

TEST_CASE("the mesh passes say each part as it begins, change nothing for it, and stop where the teller throws") {
    const ThinScan thin = thin_wall_scan();
    const PointSet& points = thin.points;
    const Result& result = thin.result;
    DepthGuardReport quiet;
    const Mesh expected = shell_mesh(result, points, &quiet);
    REQUIRE(quiet.near_vertices > 0);
    std::vector<std::string> parts;
    DepthGuardReport g;
    const Mesh got = detail::shell_mesh_of(detail::level_set_of(result), result, PointCloud(points), &g, {}, nullptr,
                                           [&](const std::string& part) { parts.push_back(part); });
    CHECK(got.vertices == expected.vertices);
    CHECK(got.triangles == expected.triangles);
    check_same(g, quiet);
    REQUIRE(parts.size() == 3 + std::size_t(g.repair_rounds));
    CHECK(parts[0] == "fairing the surface");
    CHECK(parts[1] == "the depth guard: searching the points near the surface");
    CHECK(parts[2] == "the depth guard: lifting " + std::to_string(g.near_vertices) + " vertices near points");
    for (int r = 0; r < g.repair_rounds; ++r)
        CHECK(parts[3 + std::size_t(r)].rfind("the depth guard: repair round " + std::to_string(r + 1) + ", ", 0) == 0);
    // A cancel at the search stops before it.
    std::size_t told = 0;
    CHECK_THROWS_AS(detail::shell_mesh_of(detail::level_set_of(result), result, PointCloud(points), &g, {}, nullptr,
                                          [&](const std::string& part) {
                                              ++told;
                                              if (part.find("searching") != std::string::npos) throw Cancelled("stop");
                                          }),
                    Cancelled);
    CHECK(told == 2);
}

TEST_CASE("shell_mesh is extraction, fairing and the depth guard, on 1 and 2 threads alike") {
    Parameters p;
    p.resolution = 48;
    p.device = "openmp";
    const PointSet points = shapes::torus({0.5, 0.5, 0.5}, 0.3, 0.12, 0.02);
    const Result result = reconstruct(points, p);
    Mesh expected = extract_dual_isosurface(result.phi, result.domain);
    fair_mesh(expected);
    const DepthGuardReport r = keep_points_deep(expected, points, result.offset - result.tube_inner, result.domain.h);
    for (int threads : {1, 2}) {
        DepthGuardReport g;
        const Mesh got = with_threads(threads, [&] { return shell_mesh(result, points, &g); });
        CHECK(got.triangles == expected.triangles);
        CHECK(got.vertices == expected.vertices);
        check_same(g, r);
    }
}
