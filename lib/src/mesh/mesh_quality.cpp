// measure_quality: the shell's figures against its points, l and h (see quality.hpp
// for what each one means), and their text and JSON forms.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "geometry/disjoint_sets.hpp"
#include "io/io_common.hpp"
#include "geometry/point_index.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh.hpp"
#include "snvr/quality.hpp"
#include "mesh/triangle_grid.hpp"
#include "geometry/vec3_math.hpp"

namespace snvr {
namespace {

using Tri = std::array<std::uint32_t, 3>;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kDegrees = 180 / 3.14159265358979323846;
// Below this many items a loop is not worth waking threads for.
constexpr std::ptrdiff_t kParallel = 4096;

// Robust for nearly parallel vectors, unlike acos of the dot product.
double angle(const Vec3& a, const Vec3& b) { return std::atan2(norm(cross(a, b)), dot(a, b)); }

bool degenerate(const Tri& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; }

void check_indices(const Mesh& mesh, const char* who) {
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (std::uint32_t v : mesh.triangles[t])
            if (v >= mesh.vertices.size())
                throw InputError(std::string(who) + ": triangle " + std::to_string(t) + " uses vertex " +
                                 std::to_string(v) + " of " + std::to_string(mesh.vertices.size()));
}

// The distance from each vertex along its inward normal to the first triangle
// met, ignoring the vertex's own triangles; infinity when nothing is met.
std::vector<double> wall_thickness(const Mesh& m, const TriangleGrid& grid, const std::vector<Vec3>& normals) {
    Vec3 lo{kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf};
    for (const Vec3& p : m.vertices)
        for (int d = 0; d < 3; ++d) {
            lo[d] = std::min(lo[d], p[d]);
            hi[d] = std::max(hi[d], p[d]);
        }
    // Far below any wall, far above the rounding of a hit at the ray's own start.
    const double eps = m.vertices.empty() ? 0 : 1e-9 * norm({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    std::vector<double> wall(m.vertices.size(), kInf);
    const std::ptrdiff_t nv = std::ptrdiff_t(m.vertices.size());
#pragma omp parallel for schedule(dynamic, 1024) if (nv > kParallel)
    for (std::ptrdiff_t v = 0; v < nv; ++v) {
        const Vec3& n = normals[v];
        if (dot(n, n) == 0) continue;
        wall[v] = grid.first_hit(m.vertices[v], {-n[0], -n[1], -n[2]}, eps, std::uint32_t(v)).t;
    }
    return wall;
}

// The nearest-rank 1st percentile of the values (NaN for none); reorders them.
double percentile_01(std::vector<double>& values) {
    if (values.empty()) return kNaN;
    const auto k = std::ptrdiff_t(0.01 * double(values.size() - 1));
    std::nth_element(values.begin(), values.begin() + k, values.end());
    return values[k];
}

// The half-edges of the proper triangles grouped by their lower vertex v, each as
// (upper vertex << 32 | triangle), sorted: runs of one upper vertex are one edge.
struct EdgeBuckets {
    std::vector<std::size_t> start;
    std::vector<std::uint64_t> items;
};

EdgeBuckets edge_buckets(const Mesh& m) {
    const auto& T = m.triangles;
    const std::size_t nv = m.vertices.size();
    EdgeBuckets b;
    b.start.assign(nv + 1, 0);
    for (const Tri& t : T)
        if (!degenerate(t))
            for (int c = 0; c < 3; ++c) ++b.start[std::min(t[c], t[(c + 1) % 3]) + 1];
    for (std::size_t v = 0; v < nv; ++v) b.start[v + 1] += b.start[v];
    b.items.resize(b.start[nv]);
    std::vector<std::size_t> next(b.start.begin(), b.start.end() - 1);
    for (std::size_t t = 0; t < T.size(); ++t)
        if (!degenerate(T[t]))
            for (int c = 0; c < 3; ++c) {
                const std::uint32_t a = T[t][c], e = T[t][(c + 1) % 3];
                b.items[next[std::min(a, e)]++] = std::uint64_t(std::max(a, e)) << 32 | t;
            }
#pragma omp parallel for schedule(dynamic, 4096) if (std::ptrdiff_t(nv) > kParallel)
    for (std::ptrdiff_t v = 0; v < std::ptrdiff_t(nv); ++v)
        std::sort(b.items.begin() + std::ptrdiff_t(b.start[v]), b.items.begin() + std::ptrdiff_t(b.start[v + 1]));
    return b;
}

std::uint32_t upper(std::uint64_t item) { return std::uint32_t(item >> 32); }
std::uint32_t triangle(std::uint64_t item) { return std::uint32_t(item); }

// Genus summed over the closed components; the open ones are counted apart.
void measure_topology(const Mesh& m, const EdgeBuckets& edges, MeshQuality& q) {
    const auto& T = m.triangles;
    const std::size_t nv = m.vertices.size(), nt = T.size();
    DisjointSets pieces(nt);
    for (std::size_t v = 0; v < nv; ++v)
        for (std::size_t k = edges.start[v] + 1; k < edges.start[v + 1]; ++k)
            if (upper(edges.items[k]) == upper(edges.items[k - 1]))
                pieces.unite(triangle(edges.items[k]), triangle(edges.items[k - 1]));
    constexpr std::uint32_t none = std::uint32_t(-1);
    std::vector<std::uint32_t> id(nt, none);  // compact component of each proper triangle
    std::uint32_t n_comp = 0;
    for (std::size_t t = 0; t < nt; ++t)
        if (!degenerate(T[t])) {
            const std::uint32_t root = pieces.find(std::uint32_t(t));
            if (id[root] == none) id[root] = n_comp++;
            id[t] = id[root];
        }
    // chi = V - E + F per component; a vertex shared by two components counts in each.
    std::vector<long> chi(n_comp, 0);
    std::vector<char> open(n_comp, 0);
    for (std::size_t t = 0; t < nt; ++t)
        if (id[t] != none) ++chi[id[t]];
    for (std::size_t v = 0; v < nv; ++v)
        for (std::size_t k = edges.start[v]; k < edges.start[v + 1]; ++k) {
            const bool first = k == edges.start[v] || upper(edges.items[k]) != upper(edges.items[k - 1]);
            if (!first) continue;
            const std::uint32_t c = id[triangle(edges.items[k])];
            --chi[c];
            const bool last = k + 1 == edges.start[v + 1] || upper(edges.items[k + 1]) != upper(edges.items[k]);
            if (last) open[c] = 1;  // an edge with one triangle
        }
    std::vector<std::uint32_t> vertex_comp(nv, none);
    std::vector<std::uint64_t> extra;  // (vertex << 32 | component) beyond a vertex's first
    for (std::size_t t = 0; t < nt; ++t) {
        if (id[t] == none) continue;
        for (std::uint32_t v : T[t]) {
            if (vertex_comp[v] == none) {
                vertex_comp[v] = id[t];
                ++chi[id[t]];
            } else if (vertex_comp[v] != id[t]) {
                extra.push_back(std::uint64_t(v) << 32 | id[t]);
            }
        }
    }
    std::sort(extra.begin(), extra.end());
    extra.erase(std::unique(extra.begin(), extra.end()), extra.end());
    for (std::uint64_t e : extra) ++chi[std::uint32_t(e)];
    q.genus = 0;
    q.open_components = 0;
    for (std::uint32_t c = 0; c < n_comp; ++c) {
        if (open[c])
            ++q.open_components;
        else
            q.genus += (2 - chi[c]) / 2;
    }
}

// Dihedral RMS and the count of interior edges. Each edge is weighted by the sum
// of its two triangles' areas, so that the figure does not depend on how finely
// a flat or smoothly curved region happens to be cut.
void measure_dihedral(const std::vector<Vec3>& faces, const EdgeBuckets& edges, MeshQuality& q) {
    const std::ptrdiff_t nv = std::ptrdiff_t(edges.start.size()) - 1;
    double sum = 0, weight = 0;
    std::size_t interior = 0;
#pragma omp parallel for schedule(dynamic, 4096) reduction(+ : sum, weight, interior) if (nv > kParallel)
    for (std::ptrdiff_t v = 0; v < nv; ++v) {
        const std::uint64_t* it = edges.items.data() + edges.start[v];
        const std::uint64_t* last = edges.items.data() + edges.start[v + 1];
        while (it != last) {
            const std::uint64_t* run = it;
            while (it != last && upper(*it) == upper(*run)) ++it;
            if (it - run != 2) continue;
            const Vec3 &a = faces[triangle(run[0])], &b = faces[triangle(run[1])];
            const double w = 0.5 * (norm(a) + norm(b));
            if (w == 0) continue;
            const double theta = angle(a, b) * kDegrees;
            sum += w * theta * theta;
            weight += w;
            ++interior;
        }
    }
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
    double sum = 0;
    std::size_t count = 0;
#pragma omp parallel for schedule(static) reduction(+ : sum, count) if (std::ptrdiff_t(nv) > kParallel)
    for (std::ptrdiff_t v = 0; v < std::ptrdiff_t(nv); ++v) {
        if (dot(normals[v], normals[v]) == 0 || dot(ring[v], ring[v]) == 0) continue;
        const double theta = angle(normals[v], ring[v]) * kDegrees;
        sum += theta * theta;
        ++count;
    }
    q.normal_noise = count ? std::sqrt(sum / double(count)) : kNaN;
}

// Depth of the points below the surface and how many lie inside.
void measure_points(const Mesh& m, const TriangleGrid& grid, const PointSet& points, MeshQuality& q) {
    const std::ptrdiff_t np = std::ptrdiff_t(points.size());
    // Inside or not by the parity of crossings along a ray in a direction that no
    // grid-aligned edge of a marching-cubes mesh is parallel to.
    // Each ray heads for the nearer face of the mesh's box on every axis, to cut the walk short.
    const Vec3 dir = [] {
        const Vec3 d{0.5377, 0.3019, 0.7877};
        const double n = norm(d);
        return Vec3{d[0] / n, d[1] / n, d[2] / n};
    }();
    Vec3 lo{kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf};
    for (const Vec3& v : m.vertices)
        for (int d = 0; d < 3; ++d) {
            lo[d] = std::min(lo[d], v[d]);
            hi[d] = std::max(hi[d], v[d]);
        }
    std::vector<double> depth(points.size());
    double depth_min = kInf;
    std::size_t parity_inside = 0;
#pragma omp parallel for schedule(dynamic, 64) reduction(min : depth_min) reduction(+ : parity_inside) if (np > 256)
    for (std::ptrdiff_t n = 0; n < np; ++n) {
        const double d = std::sqrt(grid.closest(points[n]).dist_sq);
        const Vec3& p = points[n];
        Vec3 toward = dir;
        for (int d = 0; d < 3; ++d)
            if (p[d] - lo[d] < hi[d] - p[d]) toward[d] = -toward[d];
        const bool inside = grid.count_crossings(p, toward) % 2 == 1;
        depth[n] = inside ? d : -d;
        if (inside) {
            depth_min = std::min(depth_min, d);
            ++parity_inside;
        }
    }
    q.points_inside = points.empty() ? 0 : count_points_inside(m, points);
    q.points_outside = points.size() - q.points_inside;
    q.inside_fraction = points.empty() ? kNaN : double(q.points_inside) / double(points.size());
    q.inside_disagreements = parity_inside > q.points_inside ? parity_inside - q.points_inside
                                                             : q.points_inside - parity_inside;
    q.depth_min = depth_min < kInf ? depth_min / q.offset : kNaN;
    q.depth_p01 = percentile_01(depth) / q.offset;
}

// e = (distance from a vertex to the nearest point) - l, in h.
void measure_offset(const Mesh& m, const PointSet& points, MeshQuality& q) {
    if (points.empty() || m.vertices.empty()) {
        q.offset_rms = q.offset_mean = q.offset_max = kNaN;
        return;
    }
    const PointIndex index(points);
    const std::ptrdiff_t nv = std::ptrdiff_t(m.vertices.size());
    double sum = 0, sum_sq = 0, max_abs = 0;
#pragma omp parallel for schedule(dynamic, 1024) reduction(+ : sum, sum_sq) reduction(max : max_abs) if (nv > kParallel)
    for (std::ptrdiff_t v = 0; v < nv; ++v) {
        const double e = (std::sqrt(index.nearest(m.vertices[v], kInf).dist_sq) - q.offset) / q.voxel;
        sum += e;
        sum_sq += e * e;
        max_abs = std::max(max_abs, std::fabs(e));
    }
    q.offset_mean = sum / double(nv);
    q.offset_rms = std::sqrt(sum_sq / double(nv));
    q.offset_max = max_abs;
}

void measure_walls(const Mesh& m, const TriangleGrid& grid, const std::vector<Vec3>& normals, MeshQuality& q) {
    std::vector<double> wall = wall_thickness(m, grid, normals);
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
    double sum_sq = 0, max_abs = 0;
#pragma omp parallel for schedule(dynamic, 1024) reduction(+ : sum_sq) reduction(max : max_abs) if (nv > kParallel)
    for (std::ptrdiff_t v = 0; v < nv; ++v) {
        const double e = std::fabs(exact(m.vertices[v])) / q.voxel;
        sum_sq += e * e;
        max_abs = std::max(max_abs, e);
    }
    q.has_exact = true;
    q.exact_rms = nv ? std::sqrt(sum_sq / double(nv)) : kNaN;
    q.exact_max = nv ? max_abs : kNaN;
}

}  // namespace

MeshQuality measure_quality(const Mesh& mesh, const PointSet& points, double offset, double voxel,
                            const std::function<double(const Vec3&)>& exact) {
    const auto started = std::chrono::steady_clock::now();
    if (!(offset > 0) || !(voxel > 0) || !std::isfinite(offset) || !std::isfinite(voxel))
        throw ParameterError("measure_quality: offset and voxel must be positive (got " +
                             detail::format_number(offset) + " and " + detail::format_number(voxel) + ")");
    check_indices(mesh, "measure_quality");
    MeshQuality q;
    q.vertices = mesh.vertices.size();
    q.triangles = mesh.triangles.size();
    q.points = points.size();
    q.offset = offset;
    q.voxel = voxel;

    q.report = check_mesh(mesh);
    const MeshReport& report = q.report;
    q.components = report.components;
    q.solids = report.solids;
    q.cavities = report.components - std::min(report.components, report.solids);
    q.closed = report.closed();
    q.manifold = report.manifold();
    q.oriented = report.oriented();

    std::vector<Vec3> faces(mesh.triangles.size());
#pragma omp parallel for schedule(static) if (std::ptrdiff_t(faces.size()) > kParallel)
    for (std::ptrdiff_t t = 0; t < std::ptrdiff_t(faces.size()); ++t) faces[t] = face_vector(mesh, mesh.triangles[t]);
    const std::vector<Vec3> normals = vertex_normals(mesh, faces);
    {
        const EdgeBuckets edges = edge_buckets(mesh);
        measure_topology(mesh, edges, q);
        measure_dihedral(faces, edges, q);
        measure_normal_noise(normals, edges, q);
    }
    const TriangleGrid grid(mesh);
    measure_points(mesh, grid, points, q);
    measure_offset(mesh, points, q);
    measure_walls(mesh, grid, normals, q);
    if (exact) measure_exact(mesh, exact, q);
    q.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return q;
}

double thinnest_wall(const Mesh& mesh) {
    check_indices(mesh, "thinnest_wall");
    std::vector<Vec3> faces(mesh.triangles.size());
    for (std::size_t t = 0; t < faces.size(); ++t) faces[t] = face_vector(mesh, mesh.triangles[t]);
    const TriangleGrid grid(mesh);
    const std::vector<double> wall = wall_thickness(mesh, grid, vertex_normals(mesh, faces));
    return wall.empty() ? kInf : *std::min_element(wall.begin(), wall.end());
}

namespace {

std::string fixed(double v, int digits = 3) {
    if (std::isnan(v)) return "n/a";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    return buf;
}

const char* yes_no(bool b) { return b ? "yes" : "no"; }

}  // namespace

std::string format_quality(const MeshQuality& q) {
    std::string s;
    s += "mesh:        " + std::to_string(q.vertices) + " vertices, " + std::to_string(q.triangles) +
         " triangles; closed " + yes_no(q.closed) + ", manifold " + yes_no(q.manifold) + ", oriented " +
         yes_no(q.oriented) + "\n";
    s += "pieces:      " + std::to_string(q.solids) + " solid, " + std::to_string(q.cavities) + " cavities (" +
         std::to_string(q.components) + " components); genus " + std::to_string(q.genus);
    if (q.open_components) s += " (" + std::to_string(q.open_components) + " open components left out)";
    s += "\n";
    s += "points:      " + std::to_string(q.points_inside) + " of " + std::to_string(q.points) + " inside (" +
         fixed(100 * q.inside_fraction, 2) + "%), " + std::to_string(q.points_outside) + " outside\n";
    s += "depth:       min " + fixed(q.depth_min) + " l (inside points), 1st percentile " + fixed(q.depth_p01) +
         " l (all, signed)";
    if (q.inside_disagreements) s += "; inside tests disagree on " + std::to_string(q.inside_disagreements);
    s += "\n";
    s += "offset err:  RMS " + fixed(q.offset_rms) + " h, mean " + fixed(q.offset_mean) + " h, max |e| " +
         fixed(q.offset_max) + " h   (l = " + detail::format_number(q.offset) +
         ", h = " + detail::format_number(q.voxel) + ")\n";
    s += "smoothness:  dihedral RMS " + fixed(q.dihedral_rms, 2) + " deg (" + std::to_string(q.interior_edges) +
         " interior edges), normal noise " + fixed(q.normal_noise, 2) + " deg\n";
    s += "walls:       min " + fixed(q.wall_min) + " h = " + fixed(q.wall_min_2l) + " x 2l, 1st percentile " +
         fixed(q.wall_p01) + " h = " + fixed(q.wall_p01_2l) + " x 2l";
    if (q.wall_misses) s += "; " + std::to_string(q.wall_misses) + " rays met nothing";
    s += "\n";
    if (q.has_exact) s += "exact error: RMS " + fixed(q.exact_rms, 4) + " h, max " + fixed(q.exact_max, 4) + " h\n";
    s += "measured in " + fixed(q.seconds, 2) + " s\n";
    return s;
}

std::string quality_json(const MeshQuality& q) {
    std::string s = "{";
    const auto key = [&](const char* name) {
        if (s.size() > 1) s += ',';
        s += '"';
        s += name;
        s += "\":";
    };
    const auto count = [&](const char* name, std::size_t v) {
        key(name);
        s += std::to_string(v);
    };
    const auto number = [&](const char* name, double v) {
        key(name);
        if (std::isfinite(v))
            detail::append_number(s, v);
        else
            s += "null";
    };
    const auto flag = [&](const char* name, bool v) {
        key(name);
        s += v ? "true" : "false";
    };
    count("vertices", q.vertices);
    count("triangles", q.triangles);
    count("points", q.points);
    number("offset", q.offset);
    number("voxel", q.voxel);
    count("components", q.components);
    count("solids", q.solids);
    count("cavities", q.cavities);
    flag("closed", q.closed);
    flag("manifold", q.manifold);
    flag("oriented", q.oriented);
    key("genus");
    s += std::to_string(q.genus);
    count("open_components", q.open_components);
    count("points_inside", q.points_inside);
    count("points_outside", q.points_outside);
    number("inside_fraction", q.inside_fraction);
    number("depth_min_l", q.depth_min);
    number("depth_p01_l", q.depth_p01);
    count("inside_disagreements", q.inside_disagreements);
    number("offset_rms_h", q.offset_rms);
    number("offset_mean_h", q.offset_mean);
    number("offset_max_h", q.offset_max);
    number("dihedral_rms_deg", q.dihedral_rms);
    count("interior_edges", q.interior_edges);
    number("normal_noise_deg", q.normal_noise);
    number("wall_min_h", q.wall_min);
    number("wall_p01_h", q.wall_p01);
    number("wall_min_2l", q.wall_min_2l);
    number("wall_p01_2l", q.wall_p01_2l);
    count("wall_misses", q.wall_misses);
    if (q.has_exact) {
        number("exact_rms_h", q.exact_rms);
        number("exact_max_h", q.exact_max);
    }
    number("seconds", q.seconds);
    s += '}';
    return s;
}

}  // namespace snvr
