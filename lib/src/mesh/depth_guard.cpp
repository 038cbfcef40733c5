// keep_points_deep: moves a shell's vertices outward, smoothly, until no point lies
// nearer than the promised depth to the surface.
//
// Why the mesh needs it although the field keeps the depth: the tube holds phi above
// the profile of the surface d = depth at every grid node, but between nodes the
// interpolant of a ball two or three cells in radius sags inward, and flat triangles
// across it cut deeper still (a point on a scan's open rim ended 0.72 l deep on the
// bunny at l = 2.5 voxels with the tube at 0.8 l). Where that happens the patch of
// surface is lifted along its normals by a displacement that is spread over two rings
// of neighbours, so the lifted patch has no kink at its edge.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "geometry/point_index.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh.hpp"
#include "mesh/triangle_grid.hpp"  // point_triangle_dist_sq
#include "geometry/vec3_math.hpp"
#include "mesh/vertex_lists.hpp"

namespace snvr {
namespace {

using detail::fans;
using detail::kParallelVertices;
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
#pragma omp parallel for schedule(static) if (nv > kParallelVertices)
        for (std::ptrdiff_t v = 0; v < nv; ++v) {
            double m = lift[v];
            for (std::size_t r = rings.start[v]; r < rings.start[v + 1]; ++r) m = std::max(m, lift[rings.items[r]]);
            wide[v] = m;
        }
#pragma omp parallel for schedule(static) if (nv > kParallelVertices)
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
std::vector<PointIndex::Hit> nearest_points(const Mesh& mesh, const PointIndex& index, double bound) {
    const std::ptrdiff_t nv = std::ptrdiff_t(mesh.vertices.size());
    std::vector<PointIndex::Hit> hits(mesh.vertices.size());
#pragma omp parallel for schedule(dynamic, 1024) if (nv > kParallelVertices)
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
    const PointIndex corners(mesh.vertices);
    const VertexLists fan = fans(mesh);
    std::vector<Watched> watched;
    const std::ptrdiff_t np = std::ptrdiff_t(points.size());
#pragma omp parallel
    {
        std::vector<Watched> mine;
#pragma omp for schedule(dynamic, 256)
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
#pragma omp critical
        for (Watched& w : mine) watched.push_back(std::move(w));
    }
    std::sort(watched.begin(), watched.end(), [](const Watched& a, const Watched& b) { return a.point < b.point; });
    return watched;
}

}  // namespace

DepthGuardReport keep_points_deep(Mesh& mesh, const PointSet& points, double depth, double voxel, double lone) {
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
    const PointIndex index(points);
    // The points the promise covers: those with another point within `lone`.
    std::vector<std::uint8_t> kept(points.size(), 1);
    if (std::isfinite(lone)) {
        const std::ptrdiff_t np = std::ptrdiff_t(points.size());
#pragma omp parallel for schedule(dynamic, 1024) if (np > kParallelVertices)
        for (std::ptrdiff_t p = 0; p < np; ++p) kept[p] = index.nearest_other(std::size_t(p)) <= lone;
        for (std::uint8_t k : kept) report.lone_points += !k;
    }

    // Lift every vertex nearer than the aim to a kept point on its inner side.
    const double aim = depth + kMarginVoxels * voxel;
    const std::vector<PointIndex::Hit> near = nearest_points(mesh, index, aim);
    std::vector<double> lift(mesh.vertices.size(), 0.0);
    for (std::size_t v = 0; v < lift.size(); ++v) {
        const std::size_t p = near[v].index;
        if (p != PointIndex::npos && kept[p] && dot(sub(mesh.vertices[v], index.point(p)), normals[v]) > 0)
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
                if (d < dist) dist = d, nearest = t;
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

}  // namespace snvr
