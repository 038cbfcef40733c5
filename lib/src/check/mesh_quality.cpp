// measure_quality: the shell's figures against its points, l and h (see quality.hpp
// for what each one means; their text and JSON forms are in quality_text.cpp).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <omp.h>

#include "number_text.hpp"
#include "snvr/error.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/mesh.hpp"
#include "snvr/quality.hpp"
#include "mesh/cell_rings.hpp"
#include "check/mesh_adjacency.hpp"
#include "check/mesh_topology.hpp"
#include "threads_here.hpp"
#include "check/point_depths.hpp"
#include "check/walls.hpp"
#include "mesh/triangle_grid.hpp"
#include "geometry/point_tree.hpp"
#include "geometry/vec3_math.hpp"
#include "parallel_sizes.hpp"

namespace snvr {

namespace {

using detail::PointTree;
using detail::threads_here;
using detail::unit_normals;
using detail::wall_epsilon;
using detail::wall_thickness;
using detail::kCheckRounds;
using detail::kWallChunk;

using Tri = std::array<std::uint32_t, 3>;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kDegrees = 180 / 3.14159265358979323846;
// Below this many items a loop is not worth waking threads for.

// Robust for nearly parallel vectors, unlike acos of the dot product.
double angle(const Vec3& a, const Vec3& b) { return std::atan2(norm(cross(a, b)), dot(a, b)); }

void check_indices(const Mesh& mesh, const char* who) {
    // The largest index first (a loop without branches): there is rarely anything to report.
    std::uint32_t top = 0;
    for (const Tri& t : mesh.triangles) top = std::max(top, std::max(t[0], std::max(t[1], t[2])));
    if (mesh.triangles.empty() || top < mesh.vertices.size()) return;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (std::uint32_t v : mesh.triangles[t])
            if (v >= mesh.vertices.size())
                throw InputError(std::string(who) + ": triangle " + std::to_string(t) + " uses vertex " +
                                 std::to_string(v) + " of " + std::to_string(mesh.vertices.size()));
}

// The nearest-rank 1st percentile of the values (NaN for none); reorders them.
double percentile_01(std::vector<double>& values) {
    if (values.empty()) return kNaN;
    const auto k = std::ptrdiff_t(0.01 * double(values.size() - 1));
    std::nth_element(values.begin(), values.begin() + k, values.end());
    return values[k];
}

// Calls compute(first, last, out) on chunks of [0, n), in parallel, each filling
// its own buffer, then consume(buffer) chunk by chunk in order: sums taken in
// consume come out as from one thread (the same figure for any number of
// threads), while the costly part runs in parallel and no buffer outgrows a chunk.
template <class T, class Compute, class Consume>
void ordered_chunks(std::size_t n, [[maybe_unused]] bool parallel, const Compute& compute, const Consume& consume) {
    constexpr std::size_t kChunk = 8192;
    const std::ptrdiff_t chunks = std::ptrdiff_t((n + kChunk - 1) / kChunk);
#pragma omp parallel if (parallel)
    {
        std::vector<T> buffer;
#pragma omp for ordered schedule(static, 1)
        for (std::ptrdiff_t c = 0; c < chunks; ++c) {
            buffer.clear();
            compute(std::size_t(c) * kChunk, std::min(n, std::size_t(c + 1) * kChunk), buffer);
#pragma omp ordered
            { consume(buffer); }
        }
    }
}

// The half-edges of the proper triangles grouped by their lower vertex v, each as
// (upper vertex << 32 | triangle), sorted: runs of one upper vertex are one edge.
struct EdgeBuckets {
    std::vector<std::size_t> start;
    std::vector<std::uint64_t> items;
    void swap(EdgeBuckets& o) {
        start.swap(o.start);
        items.swap(o.items);
    }
};

std::uint32_t upper(std::uint64_t item) { return std::uint32_t(item >> 32); }
std::uint32_t triangle(std::uint64_t item) { return std::uint32_t(item); }

// Dihedral RMS and the count of interior edges. Each edge is weighted by the sum
// of its two triangles' areas, so that the figure does not depend on how finely
// a flat or smoothly curved region happens to be cut.
void measure_dihedral(const Mesh& m, const EdgeBuckets& edges, MeshQuality& q) {
    const std::size_t nv = edges.start.size() - 1;
    double sum = 0, weight = 0;
    std::size_t interior = 0;
    ordered_chunks<std::array<double, 2>>(
        nv, std::ptrdiff_t(nv) > detail::kParallelItems,
        [&](std::size_t first_v, std::size_t last_v, std::vector<std::array<double, 2>>& terms) {
            for (std::size_t v = first_v; v < last_v; ++v) {
                const std::uint64_t* it = edges.items.data() + edges.start[v];
                const std::uint64_t* last = edges.items.data() + edges.start[v + 1];
                while (it != last) {
                    const std::uint64_t* run = it;
                    while (it != last && upper(*it) == upper(*run)) ++it;
                    if (it - run != 2) continue;
                    const Vec3 a = face_vector(m, m.triangles[triangle(run[0])]);
                    const Vec3 b = face_vector(m, m.triangles[triangle(run[1])]);
                    const double w = 0.5 * (norm(a) + norm(b));
                    if (w == 0) continue;
                    const double theta = angle(a, b) * kDegrees;
                    terms.push_back({w * theta * theta, w});
                }
            }
        },
        [&](const std::vector<std::array<double, 2>>& terms) {
            for (const auto& t : terms) {
                sum += t[0];
                weight += t[1];
            }
            interior += terms.size();
        });
    q.interior_edges = interior;
    q.dihedral_rms = weight > 0 ? std::sqrt(sum / weight) : kNaN;
}

// RMS over vertices of the angle between a vertex's normal and the mean of its
// neighbours' normals: high where the normals jitter from vertex to vertex.
void measure_normal_noise(const std::vector<Vec3>& normals, const EdgeBuckets& edges, MeshQuality& q) {
    const std::size_t nv = normals.size();
    std::vector<Vec3> ring(nv, Vec3{0, 0, 0});
    for (std::size_t v = 0; v < nv; ++v)
        for (std::size_t k = edges.start[v]; k < edges.start[v + 1]; ++k) {
            const std::uint32_t u = upper(edges.items[k]);
            if (k > edges.start[v] && u == upper(edges.items[k - 1])) continue;  // each edge once
            for (int d = 0; d < 3; ++d) {
                ring[v][d] += normals[u][d];
                ring[u][d] += normals[v][d];
            }
        }
    // Angles in parallel, summed in vertex order: the same figure for any number
    // of threads (and no waiting on each other, as ordered chunks would).
    std::vector<double> theta_sq(nv, -1.0);  // -1: no angle at this vertex
#pragma omp parallel for schedule(static) if (std::ptrdiff_t(nv) > detail::kParallelItems)
    for (std::ptrdiff_t v = 0; v < std::ptrdiff_t(nv); ++v) {
        if (dot(normals[v], normals[v]) == 0 || dot(ring[v], ring[v]) == 0) continue;
        const double theta = angle(normals[v], ring[v]) * kDegrees;
        theta_sq[v] = theta * theta;
    }
    double sum = 0;
    std::size_t count = 0;
    for (double t : theta_sq)
        if (t >= 0) {
            sum += t;
            ++count;
        }
    q.normal_noise = count ? std::sqrt(sum / double(count)) : kNaN;
}

// e = (distance from a vertex to the nearest point) - l, in h.
// fan_start, fan_tri: the triangles around each vertex (detail::vertex_fans).
void measure_offset(const Mesh& m, const PointTree& points, const std::vector<std::size_t>& fan_start,
                    const std::vector<std::uint32_t>& fan_tri, MeshQuality& q) {
    if (points.size() == 0 || m.vertices.empty()) {
        q.offset_rms = q.offset_mean = q.offset_max = kNaN;
        return;
    }
    const std::size_t nv = m.vertices.size();
    std::vector<std::uint32_t> nearest(nv, PointTree::npos);  // each vertex's nearest point
    // Neighbouring vertices have nearby nearest points: the nearest points found
    // for the vertex's neighbours earlier in its run bound its search (any point
    // no farther than the bound is found, so the result is the same).
    constexpr std::size_t kRun = 2048;
    const std::ptrdiff_t runs = std::ptrdiff_t((nv + kRun - 1) / kRun);
    const auto& T = m.triangles;
#pragma omp parallel for schedule(dynamic, 1) if (std::ptrdiff_t(nv) > detail::kParallelItems)
    for (std::ptrdiff_t r = 0; r < runs; ++r) {
        const std::size_t first = std::size_t(r) * kRun, last = std::min(nv, std::size_t(r + 1) * kRun);
        for (std::size_t v = first; v < last; ++v) {
            const Vec3& x = m.vertices[v];
            // The first neighbour met that has its nearest point will do: they all
            // lie within an edge of each other.
            double bound = kInf;
            for (std::size_t k = fan_start[v]; k < fan_start[v + 1] && bound == kInf; ++k)
                for (std::uint32_t u : T[fan_tri[k]])
                    if (u >= first && u < v && nearest[u] != PointTree::npos) {
                        bound = PointTree::dist_sq(x, points.point(nearest[u]));
                        break;
                    }
            // A little above the bound, so that the point that gave it is found again.
            bound += std::max(bound * 0x1p-50, std::numeric_limits<double>::denorm_min());
            PointTree::Hit hit = points.nearest(x, bound);
            if (hit.index == PointTree::npos && bound < kInf) hit = points.nearest(x, kInf);
            nearest[v] = hit.index;
        }
    }
    // Summed in vertex order: the same figures for any number of threads.
    double sum = 0, sum_sq = 0, max_abs = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        double dist_sq = kInf;  // none only when no point or vertex is finite
        if (nearest[v] != PointTree::npos) {
            // The same sum as the search made.
            dist_sq = PointTree::dist_sq(m.vertices[v], points.point(nearest[v]));
        }
        const double e = (std::sqrt(dist_sq) - q.offset) / q.voxel;
        sum += e;
        sum_sq += e * e;
        max_abs = std::max(max_abs, std::fabs(e));
    }
    q.offset_mean = sum / double(nv);
    q.offset_rms = std::sqrt(sum_sq / double(nv));
    q.offset_max = max_abs;
}

// The point figures from PointDepths' and, when given, count_points_inside (the depths'
// own count is then the second opinion).
void measure_points(detail::PointDepths::Figures& f, std::optional<std::size_t> counted_inside, MeshQuality& q) {
    const std::size_t points_inside = counted_inside.value_or(f.inside);
    q.points_inside = points_inside;
    q.points_outside = q.points - q.points_inside;
    q.inside_fraction = q.points == 0 ? kNaN : double(q.points_inside) / double(q.points);
    q.inside_disagreements = f.inside > q.points_inside ? f.inside - q.points_inside : q.points_inside - f.inside;
    q.depth_min = f.depth_min < kInf ? f.depth_min / q.offset : kNaN;
    q.depth_p01 = percentile_01(f.depths) / q.offset;
}

// The wall figures from every vertex's wall (reordered).
void measure_walls(std::vector<double>& wall, MeshQuality& q) {
    const auto hits_end = std::partition(wall.begin(), wall.end(), [](double w) { return w < kInf; });
    q.wall_misses = std::size_t(wall.end() - hits_end);
    wall.erase(hits_end, wall.end());
    q.wall_min = wall.empty() ? kNaN : *std::min_element(wall.begin(), wall.end()) / q.voxel;
    q.wall_p01 = percentile_01(wall) / q.voxel;
    q.wall_min_2l = q.wall_min * q.voxel / (2 * q.offset);
    q.wall_p01_2l = q.wall_p01 * q.voxel / (2 * q.offset);
}

void measure_exact(const Mesh& m, const std::function<double(const Vec3&)>& exact, MeshQuality& q) {
    const std::ptrdiff_t nv = std::ptrdiff_t(m.vertices.size());
    std::vector<double> error(m.vertices.size());
#pragma omp parallel for schedule(dynamic, 1024) if (nv > detail::kParallelItems)
    for (std::ptrdiff_t v = 0; v < nv; ++v) error[v] = std::fabs(exact(m.vertices[v])) / q.voxel;
    // Summed in vertex order: the same figures for any number of threads.
    double sum_sq = 0, max_abs = 0;
    for (double e : error) {
        sum_sq += e * e;
        max_abs = std::max(max_abs, e);
    }
    q.has_exact = true;
    q.exact_rms = nv ? std::sqrt(sum_sq / double(nv)) : kNaN;
    q.exact_max = nv ? max_abs : kNaN;
}

// The figures of measure_quality; the surface's (offset error, smoothness, the
// second inside test) only when `surface` is set.
// The inputs checked, and the figures they give at once.
MeshQuality counted_figures(const char* who, std::size_t vertices, std::size_t triangles, std::size_t points,
                            double offset, double voxel, bool surface) {
    if (!(offset > 0) || !(voxel > 0) || !std::isfinite(offset) || !std::isfinite(voxel))
        throw ParameterError(std::string(who) + ": offset and voxel must be positive (got " +
                             detail::format_number(offset) + " and " + detail::format_number(voxel) + ")");
    MeshQuality q;
    q.vertices = vertices;
    q.triangles = triangles;
    q.points = points;
    q.offset = offset;
    q.voxel = voxel;
    q.has_surface = surface;
    if (!surface) q.offset_rms = q.offset_mean = q.offset_max = q.dihedral_rms = q.normal_noise = kNaN;
    if (triangles > std::numeric_limits<std::uint32_t>::max())
        throw ResourceError(std::string(who) + ": more than 2^32 triangles");
    return q;
}
MeshQuality start_figures(const char* who, const Mesh& mesh, const PointTree& points, double offset, double voxel,
                          bool surface) {
    check_indices(mesh, who);
    return counted_figures(who, mesh.vertices.size(), mesh.triangles.size(), points.size(), offset, voxel, surface);
}

// The figures of the topology.
void topology_figures(const detail::Topology& topology, MeshQuality& q) {
    const MeshReport& report = q.report = topology.report;
    q.genus = topology.genus;
    q.open_components = topology.open_components;
    q.components = report.components;
    q.solids = report.solids;
    q.cavities = report.components - std::min(report.components, report.solids);
    q.closed = report.closed();
    q.manifold = report.manifold();
    q.oriented = report.oriented();
}

// The figures from what the tasks found.
void finish_figures(const Mesh& mesh, bool surface, const std::vector<Vec3>& normals, EdgeBuckets& edges,
                    detail::PointDepths::Figures& figures, std::size_t points_inside,
                    std::vector<double>& wall, const std::function<double(const Vec3&)>& exact,
                    MeshQuality& q) {
    if (surface) measure_normal_noise(normals, edges, q);
    EdgeBuckets().swap(edges);
    measure_points(figures, surface ? std::optional<std::size_t>(points_inside) : std::nullopt, q);
    measure_walls(wall, q);
    if (exact) measure_exact(mesh, exact, q);
}

// elsewhere: walls and points another process measures (or null).
MeshQuality measure(const char* who, const Mesh& mesh, const PointTree& points, double offset, double voxel,
                    bool surface, const std::function<double(const Vec3&)>& exact,
                    const detail::CheckElsewhere* elsewhere = nullptr, const detail::Told& told = nullptr,
                    const detail::WallRays& rays = nullptr) {
    const auto started = std::chrono::steady_clock::now();
    MeshQuality q = start_figures(who, mesh, points, offset, voxel, surface);
    // Tasks on the team's threads, each part on one thread (their loops run
    // serially inside a task): the mesh's own figures (A) on one, the grid and
    // what needs no more (B) on the other, then the walls, which need only B,
    // and the depths of the points, which need A too, in pieces taken by
    // whichever thread is free. Every part is parallel in places only, or bound by
    // memory, so side by side they go faster than each with both threads. The
    // figures are the same either way: pieces write their own slots, and what
    // they add up is added up in a fixed order afterwards.
    // Without the surface figures (offset error, smoothness: about 0.3 of the
    // thread time on the bunny) the points' depth searches start from a guess
    // (twice the offset; a miss searches again without bound), and a point is
    // inside by its nearest triangle's side (a ray only where that is unclear):
    // one inside test, not two.
    const std::size_t nv = mesh.vertices.size();
    std::vector<double> wall(nv, kInf);
    EdgeBuckets edges;
    std::optional<TriangleGrid> grid;
    std::optional<detail::PointDepths> depths;
    std::vector<Vec3> normals;
    std::vector<std::uint32_t> order;  // the walls' (detail::wall_order)
    std::size_t points_inside = 0;
    std::exception_ptr failed[3];  // A, B and the pieces: an exception may not leave a task
    const auto guarded = [&](std::exception_ptr& slot, auto&& part) {
        try {
            part();
        } catch (...) {
#pragma omp critical(snvr_measure_quality_failed)
            slot = std::current_exception();
        }
    };
    // The caller's thread makes the tasks (and says how far they have come).
#pragma omp parallel if (mesh.triangles.size() > 20000)
#pragma omp master
    {
#pragma omp task
        guarded(failed[0], [&] {
            detail::Topology topology;
            if (elsewhere && elsewhere->topology && !surface) {  // the mesh's slabs count it
                topology = elsewhere->topology();
            } else {
                detail::MeshAdjacency adjacency = detail::adjacency_of(mesh);
                topology = detail::mesh_topology(mesh, adjacency);
                if (surface) measure_offset(mesh, points, adjacency.fan_start, adjacency.fan_tri, q);
                edges.start.swap(adjacency.edge_start);
                edges.items.swap(adjacency.edge_items);
            }
            topology_figures(topology, q);
            if (surface) measure_dihedral(mesh, edges, q);
        });
        guarded(failed[1], [&] {
            grid.emplace(mesh);
            normals = unit_normals(mesh);
            order = detail::wall_order(mesh);
            if (surface && points.size()) {
                // The second opinion (rays along z from every point) takes the points as a set.
                PointSet all(points.size());
                for (std::size_t k = 0; k < all.size(); ++k) all[k] = points.point(k);
                points_inside = count_points_inside(mesh, all);
            }
            if (elsewhere && !elsewhere->groups.empty())  // its groups made once, as dealt
                depths.emplace(mesh, *grid, points, voxel, elsewhere->spans, surface, surface, &elsewhere->groups);
            else
                depths.emplace(mesh, *grid, points, voxel, surface, surface);
        });
        if (!failed[1]) {
            const double eps = wall_epsilon(mesh);
            // Chunks of neighbouring groups (they share bounds and working space), a few per
            // thread; the second pass once the first has found the shallowest measured depth.
            const std::size_t groups = depths->groups(), chunk = std::max<std::size_t>(16, groups / 64);
            const std::size_t wall_chunks = (nv + kWallChunk - 1) / kWallChunk, group_chunks = (groups + chunk - 1) / chunk;
            // In rounds, each's tasks done before the next's are made, so that between them
            // the caller can be told how far the walls and depths have come (the walls and
            // the first pass in turn, then the second; a vertex's wall, a group's pass a
            // unit each). The same chunks as at once: the same figures.
            const std::size_t all = nv + 2 * groups;
            const auto tell = [&](std::size_t done) {
                if (told) guarded(failed[2], [&] { told(done, all); });
                return !failed[2];
            };
            const auto round_of = [](std::size_t n, int r) { return n * std::size_t(r) / std::size_t(kCheckRounds); };
            // Where the rays go elsewhere, they go at once, as the first round's task (the
            // depths' first pass beside them); the host casts them where that fails.
            const std::uint8_t* skip = elsewhere ? elsewhere->vertex.data() : nullptr;
            bool cast_elsewhere = bool(rays);
            const auto cast_chunk = [&](std::size_t c) {
                guarded(failed[2], [&] {
                    wall_thickness(mesh, *grid, normals, eps, order, c * kWallChunk, std::min(nv, (c + 1) * kWallChunk),
                                   wall, skip);
                });
            };
            bool going = tell(0);
            for (int r = 0; going && r < kCheckRounds; ++r) {
#pragma omp taskgroup
                {
                    for (std::size_t c = round_of(wall_chunks, r); !cast_elsewhere && c < round_of(wall_chunks, r + 1); ++c)
#pragma omp task firstprivate(c)
                        cast_chunk(c);
                    if (cast_elsewhere && r == 0)
#pragma omp task
                        guarded(failed[2], [&] {
                            std::vector<std::uint32_t> cast;
                            cast.reserve(nv);
                            for (std::uint32_t v : order)
                                if (!skip || !skip[v]) cast.push_back(v);
                            const std::string on = rays(mesh, *grid, normals, eps, cast, wall);
                            if (!on.empty()) q.walls_on = on;
                        });
                    for (std::size_t c = round_of(group_chunks, r); c < round_of(group_chunks, r + 1); ++c)
#pragma omp task firstprivate(c)
                        guarded(failed[2], [&] { depths->bound(c * chunk, std::min(groups, (c + 1) * chunk)); });
                }
                if (cast_elsewhere && r == 0 && q.walls_on == "host") {  // it could not: the host casts them all
                    cast_elsewhere = false;
#pragma omp taskgroup
                    for (std::size_t c = 0; c < round_of(wall_chunks, 1); ++c)
#pragma omp task firstprivate(c)
                        cast_chunk(c);
                }
                going = tell(std::min(nv, (cast_elsewhere ? nv : round_of(wall_chunks, r + 1) * kWallChunk)) +
                             std::min(groups, round_of(group_chunks, r + 1) * chunk));
            }
            const double shallowest = going ? depths->shallowest() : 0;
            for (int r = 0; going && r < kCheckRounds; ++r) {
#pragma omp taskgroup
                {
                    for (std::size_t c = round_of(group_chunks, r); c < round_of(group_chunks, r + 1); ++c)
#pragma omp task firstprivate(c)
                        guarded(failed[2], [&] { depths->settle(c * chunk, std::min(groups, (c + 1) * chunk), shallowest); });
                }
                going = tell(nv + groups + std::min(groups, round_of(group_chunks, r + 1) * chunk));
            }
        }
#pragma omp taskwait
    }
    for (const std::exception_ptr& e : failed)
        if (e) std::rethrow_exception(e);
    detail::PointDepths::Figures figures = depths ? depths->figures() : detail::PointDepths::Figures{};
    if (elsewhere) {  // their walls and points' figures back, every one decided
        detail::PointDepths::Figures theirs;
        elsewhere->fill(wall, theirs);
        figures.inside += theirs.inside;
        figures.depth_min = std::min(figures.depth_min, theirs.depth_min);
    }
    finish_figures(mesh, surface, normals, edges, figures, points_inside, wall, exact, q);
    q.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return q;
}

}  // namespace

MeshQuality measure_quality(const Mesh& mesh, const PointCloud& points, double offset, double voxel,
                            const std::function<double(const Vec3&)>& exact) {
    return measure("measure_quality", mesh, detail::tree_of(points), offset, voxel, true, exact);
}
MeshQuality measure_quality(const Mesh& mesh, const PointSet& points, double offset, double voxel,
                            const std::function<double(const Vec3&)>& exact) {
    return measure_quality(mesh, PointCloud(points), offset, voxel, exact);
}

MeshQuality measure_shell(const Mesh& mesh, const PointCloud& points, double offset, double voxel) {
    return measure("measure_shell", mesh, detail::tree_of(points), offset, voxel, false, {});
}
MeshQuality measure_shell(const Mesh& mesh, const PointSet& points, double offset, double voxel) {
    return measure_shell(mesh, PointCloud(points), offset, voxel);
}

MeshQuality detail::measure_sharing(const Mesh& mesh, const PointCloud& points, double offset, double voxel,
                                    bool surface, const CheckElsewhere& elsewhere, const Told& told) {
    if (elsewhere.vertex.size() != mesh.vertices.size()) throw ParameterError("measure_sharing: one flag a vertex");
    return measure(surface ? "measure_quality" : "measure_shell", mesh, detail::tree_of(points), offset, voxel, surface,
                   {}, &elsewhere, told);
}

MeshQuality detail::shell_figures(const Topology& topology, std::size_t points, double offset, double voxel,
                                  std::vector<double>& walls, PointDepths::Figures& depths) {
    MeshQuality q = counted_figures("measure_shell", topology.report.vertices, topology.report.triangles, points, offset,
                                    voxel, false);
    topology_figures(topology, q);
    measure_points(depths, std::nullopt, q);
    measure_walls(walls, q);
    return q;
}

MeshQuality detail::measure_told(const Mesh& mesh, const PointCloud& points, double offset, double voxel, bool surface,
                                 const Told& told, const WallRays& rays) {
    return measure(surface ? "measure_quality" : "measure_shell", mesh, detail::tree_of(points), offset, voxel, surface,
                   {}, nullptr, told, rays);
}

double thinnest_wall(const Mesh& mesh) {
    check_indices(mesh, "thinnest_wall");
    const TriangleGrid grid(mesh);
    const std::vector<Vec3> normals = unit_normals(mesh);
    const double eps = wall_epsilon(mesh);
    const std::size_t nv = mesh.vertices.size();
    std::vector<double> wall(nv, kInf);
    const std::vector<std::uint32_t> order = detail::wall_order(mesh);
#pragma omp parallel for schedule(dynamic, 1) if (std::ptrdiff_t(nv) > detail::kParallelItems)
    for (std::ptrdiff_t c = 0; c < std::ptrdiff_t((nv + kWallChunk - 1) / kWallChunk); ++c)
        wall_thickness(mesh, grid, normals, eps, order, std::size_t(c) * kWallChunk,
                       std::min(nv, std::size_t(c + 1) * kWallChunk), wall);
    return wall.empty() ? kInf : *std::min_element(wall.begin(), wall.end());
}

}  // namespace snvr
