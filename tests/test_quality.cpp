// Mesh quality measures on shapes whose answers are known, the triangle grid
// against brute force, and read_mesh.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "with_threads.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh_io.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/mesh.hpp"
#include "snvr/quality.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/shapes.hpp"
#include "mesh_fields.hpp"
#include "temp_dir.hpp"
#include "thread_processes.hpp"
#include "check/mesh_topology.hpp"
#include "check/slab_queries.hpp"
#include "check/slab_shares.hpp"
#include "check/walls.hpp"
#include "check/slab_topology.hpp"
#include "geometry/vec3_math.hpp"
#include "mesh/triangle_grid.hpp"

// The library's OpenMP runtime (linked with it): the tests compare thread counts.
extern "C" void omp_set_num_threads(int);
extern "C" int omp_get_max_threads();

using namespace snvr;
using snvr::testing::TempDir;
namespace fs = std::filesystem;

using snvr::testing::with_threads;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double dist(const Vec3& a, const Vec3& b) {
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

// The zero level of f (positive inside) on an n^3 grid of spacing h from origin.
template <class F>
Mesh isosurface(F f, Vec3 origin, double h, int n) {
    Domain domain;
    domain.origin = origin;
    domain.h = h;
    domain.nx = domain.ny = domain.nz = n;
    std::vector<double> values(domain.cells());
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) values[domain.index(i, j, k)] = f(domain.cell_center(i, j, k));
    return extract_isosurface(Field::from_dense(n, n, n, values), domain);
}

// Icosahedron split `levels` times, its vertices pushed onto the sphere (c, r);
// each vertex moved radially by up to `noise` r at random when noise > 0.
Mesh icosphere(const Vec3& c, double r, int levels, double noise = 0) {
    const double t = (1 + std::sqrt(5.0)) / 2;
    std::vector<Vec3> v{{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                        {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    std::vector<std::array<std::uint32_t, 3>> f{{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                                {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                                {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                                {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    for (int level = 0; level < levels; ++level) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> middle;
        const auto mid = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            const auto found = middle.find(key);
            if (found != middle.end()) return found->second;
            v.push_back({(v[a][0] + v[b][0]) / 2, (v[a][1] + v[b][1]) / 2, (v[a][2] + v[b][2]) / 2});
            return middle[key] = std::uint32_t(v.size() - 1);
        };
        std::vector<std::array<std::uint32_t, 3>> next;
        for (const auto& tri : f) {
            const std::uint32_t ab = mid(tri[0], tri[1]), bc = mid(tri[1], tri[2]), ca = mid(tri[2], tri[0]);
            next.push_back({tri[0], ab, ca});
            next.push_back({tri[1], bc, ab});
            next.push_back({tri[2], ca, bc});
            next.push_back({ab, bc, ca});
        }
        f = next;
    }
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-noise, noise);
    Mesh m;
    m.triangles = f;
    for (const Vec3& p : v) {
        const double s = r * (1 + (noise > 0 ? jitter(rng) : 0)) / dist(p, {0, 0, 0});
        m.vertices.push_back({c[0] + s * p[0], c[1] + s * p[1], c[2] + s * p[2]});
    }
    return m;
}

const Vec3 kCentre{0.5, 0.5, 0.5};

// A spherical shell between radii R - l and R + l around kCentre, and its points.
constexpr double kR = 0.3, kL = 0.05, kH = 0.01;
const Mesh& shell() {
    static const Mesh mesh = isosurface(
        [](const Vec3& p) { return kL - std::fabs(dist(p, kCentre) - kR); }, {0.1, 0.1, 0.1}, kH, 80);
    return mesh;
}

void write_text(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

double ray_triangle(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& b, const Vec3& c) {
    // Solve o + t d = a + u (b - a) + v (c - a) by Cramer's rule.
    const Vec3 e1{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const Vec3 s{o[0] - a[0], o[1] - a[1], o[2] - a[2]};
    const auto det3 = [](const Vec3& x, const Vec3& y, const Vec3& z) {
        return x[0] * (y[1] * z[2] - y[2] * z[1]) - y[0] * (x[1] * z[2] - x[2] * z[1]) + z[0] * (x[1] * y[2] - x[2] * y[1]);
    };
    const Vec3 nd{-d[0], -d[1], -d[2]};
    const double det = det3(e1, e2, nd);
    if (det == 0) return kInf;
    const double u = det3(s, e2, nd) / det, v = det3(e1, s, nd) / det, t = det3(e1, e2, s) / det;
    return u >= 0 && v >= 0 && u + v <= 1 ? t : kInf;
}

// A torus about the z axis through (0.5, 0.5): ring radius 0.3, tube radius 0.1.
Mesh torus_mesh() {
    return isosurface(
        [](const Vec3& p) {
            const double ring = std::hypot(p[0] - 0.5, p[1] - 0.5) - 0.3;
            return 0.1 - std::hypot(ring, p[2] - 0.5);
        },
        {0.05, 0.05, 0.3}, 0.02, 45);
}

}  // namespace

TEST_CASE("quality: a sphere has genus 0, a torus genus 1") {
    const Mesh sphere = isosurface([](const Vec3& p) { return 0.3 - dist(p, kCentre); }, {0.1, 0.1, 0.1}, 0.02, 40);
    const MeshQuality s = measure_quality(sphere, {kCentre}, 0.3, 0.02);
    CHECK(s.closed);
    CHECK(s.manifold);
    CHECK(s.oriented);
    CHECK(s.components == 1);
    CHECK(s.solids == 1);
    CHECK(s.cavities == 0);
    CHECK(s.genus == 0);
    CHECK(s.open_components == 0);
    CHECK(s.points_inside == 1);

    const Mesh torus = torus_mesh();
    // Points on the core circle are inside; those on the axis, in the hole, are not.
    PointSet points;
    for (int k = 0; k < 16; ++k) {
        const double a = 2 * 3.14159265358979 * k / 16;
        points.push_back({0.5 + 0.3 * std::cos(a), 0.5 + 0.3 * std::sin(a), 0.5});
    }
    points.push_back({0.5, 0.5, 0.5});
    const MeshQuality t = measure_quality(torus, points, 0.1, 0.02);
    CHECK(t.components == 1);
    CHECK(t.genus == 1);
    CHECK(t.points_inside == 16);
    CHECK(t.points_outside == 1);
    CHECK(t.inside_disagreements == 0);
    CHECK(t.depth_min == doctest::Approx(1).epsilon(0.05));   // the core circle is 0.1 = l deep
    CHECK(t.depth_p01 == doctest::Approx(-2).epsilon(0.05));  // the axis is 0.2 outside
}

TEST_CASE("quality: the walls measured in blocks of space are the walls in vertex order") {
    const Mesh& mesh = shell();
    const std::size_t nv = mesh.vertices.size();
    const std::vector<std::uint32_t> order = detail::wall_order(mesh);
    REQUIRE(order.size() == nv);
    std::vector<std::uint32_t> sorted = order, identity(nv);
    std::sort(sorted.begin(), sorted.end());
    std::iota(identity.begin(), identity.end(), 0u);
    REQUIRE(sorted == identity);  // each vertex once
    CHECK(order != sorted);  // the mesher's order is not the blocks'
    // Neighbours in the order are near in space: far nearer than in the mesh's own order.
    const auto mean_step = [&](const std::vector<std::uint32_t>& o) {
        double sum = 0;
        for (std::size_t k = 1; k < nv; ++k) sum += dist(mesh.vertices[o[k]], mesh.vertices[o[k - 1]]);
        return sum / double(nv - 1);
    };
    CHECK(mean_step(order) < 0.5 * mean_step(sorted));
    const TriangleGrid grid(mesh);
    const std::vector<Vec3> normals = detail::unit_normals(mesh);
    const double eps = detail::wall_epsilon(mesh);
    std::vector<double> by_blocks(nv, kInf), in_order(nv, kInf);
    detail::wall_thickness(mesh, grid, normals, eps, order, 0, nv, by_blocks);
    detail::wall_thickness(mesh, grid, normals, eps, sorted, 0, nv, in_order);
    CHECK(by_blocks == in_order);
    CHECK(*std::min_element(in_order.begin(), in_order.end()) == thinnest_wall(mesh));
}

TEST_CASE("quality: a spherical shell of radii R - l and R + l") {
    const Mesh& mesh = shell();
    const PointSet points = shapes::sphere(kCentre, kR, 0.02);
    const auto exact = [](const Vec3& p) { return std::fabs(dist(p, kCentre) - kR) - kL; };
    const MeshQuality q = measure_quality(mesh, points, kL, kH, exact);
    MESSAGE(format_quality(q));
    CHECK(q.closed);
    CHECK(q.components == 2);
    CHECK(q.solids == 1);
    CHECK(q.cavities == 1);
    CHECK(q.genus == 0);
    CHECK(q.points_inside == points.size());
    CHECK(q.points_outside == 0);
    CHECK(q.inside_disagreements == 0);
    CHECK(q.inside_fraction == 1.0);
    CHECK(q.depth_min == doctest::Approx(1).epsilon(0.03));
    CHECK(q.depth_p01 == doctest::Approx(1).epsilon(0.03));
    CHECK(q.wall_misses == 0);
    CHECK(q.wall_min_2l == doctest::Approx(1).epsilon(0.03));
    CHECK(q.wall_p01_2l == doctest::Approx(1).epsilon(0.03));
    CHECK(q.wall_min * kH == doctest::Approx(2 * kL * q.wall_min_2l));
    CHECK(thinnest_wall(mesh) == doctest::Approx(q.wall_min * kH));
    CHECK(q.has_exact);
    CHECK(q.exact_rms < 0.05);
    CHECK(q.exact_max < 0.15);
    // The points are a sampling of the sphere, so the nearest one is a bit beyond l.
    CHECK(std::fabs(q.offset_mean) < 0.1);
    CHECK(q.offset_rms < 0.1);
    CHECK(q.offset_rms >= std::fabs(q.offset_mean));
    CHECK(q.dihedral_rms > 0);
    CHECK(q.normal_noise > 0);
    // Whatever the mesher, the JSON line names every figure once.
    const std::string json = quality_json(q);
    CHECK(json.front() == '{');
    CHECK(json.back() == '}');
    CHECK(json.find("\"genus\":0") != std::string::npos);
    CHECK(json.find("\"exact_rms_h\":") != std::string::npos);
}

namespace {

// `whole` in `processes` slabs cut at random places of its vertices and, apart, of its
// triangles (some slabs empty).
std::vector<Mesh> slabs_of(const Mesh& whole, int processes, std::mt19937& rng) {
    const auto cuts = [&](std::size_t n) {
        std::uniform_int_distribution<std::size_t> at(0, n);
        std::vector<std::size_t> c{0, n};
        for (int k = 1; k < processes; ++k) c.push_back(at(rng));
        std::sort(c.begin(), c.end());
        return c;
    };
    const std::vector<std::size_t> v = cuts(whole.vertices.size()), t = cuts(whole.triangles.size());
    std::vector<Mesh> parts(static_cast<std::size_t>(processes));
    for (std::size_t p = 0; p < parts.size(); ++p) {
        parts[p].vertices.assign(whole.vertices.begin() + std::ptrdiff_t(v[p]), whole.vertices.begin() + std::ptrdiff_t(v[p + 1]));
        parts[p].triangles.assign(whole.triangles.begin() + std::ptrdiff_t(t[p]),
                                  whole.triangles.begin() + std::ptrdiff_t(t[p + 1]));
    }
    return parts;
}

// `whole` in slabs (slabs_of), its topology measured by processes as threads.
detail::Topology topology_in_slabs(const Mesh& whole, int processes, std::mt19937& rng) {
    const std::vector<Mesh> parts = slabs_of(whole, processes, rng);
    // All steps at once, or the first taking the others' counts before counting its own
    // (as a run does, between other work).
    std::vector<detail::Topology> got(parts.size());
    const bool first_takes_first = std::uniform_int_distribution<int>(0, 1)(rng) == 1;
    testing::on_threads(processes, [&](TileScheduler& on) {
        const Mesh& part = parts[std::size_t(on.rank())];
        if (on.rank() != 0 || !first_takes_first) {
            got[std::size_t(on.rank())] = detail::slab_topology(detail::SlabPart::of(part), on);
            return;
        }
        detail::SlabMesh held(detail::SlabPart::of(part), on);
        detail::SlabTopology slabs(held, on);
        slabs.take_others();
        slabs.count();
        got[0] = slabs.joined();
    });
    return got[0];
}

// Every figure the same, the volume to the bit.
void check_same_topology(const detail::Topology& a, const detail::Topology& b) {
    const MeshReport &x = a.report, &y = b.report;
    CHECK(x.vertices == y.vertices);
    CHECK(x.triangles == y.triangles);
    CHECK(x.boundary_edges == y.boundary_edges);
    CHECK(x.nonmanifold_edges == y.nonmanifold_edges);
    CHECK(x.misoriented_edges == y.misoriented_edges);
    CHECK(x.nonmanifold_vertices == y.nonmanifold_vertices);
    CHECK(x.degenerate_triangles == y.degenerate_triangles);
    CHECK(x.zero_area_triangles == y.zero_area_triangles);
    CHECK(x.components == y.components);
    CHECK(x.solids == y.solids);
    CHECK(std::memcmp(&x.volume, &y.volume, sizeof x.volume) == 0);
    CHECK(a.genus == b.genus);
    CHECK(a.open_components == b.open_components);
}

}  // namespace

TEST_CASE("quality: the topology of a mesh in slabs over processes is the whole mesh's, every figure") {
    // Shapes of known figures, then defects of every kind the report counts.
    const Mesh sphere = isosurface([](const Vec3& p) { return 0.3 - dist(p, kCentre); }, {0.1, 0.1, 0.1}, 0.02, 40);
    const Mesh torus = torus_mesh();
    Mesh two_tori = testing::merge(torus, torus);
    for (std::size_t k = torus.vertices.size(); k < two_tori.vertices.size(); ++k) two_tori.vertices[k][0] += 0.55;
    Mesh defects = testing::merge(shell(), icosphere({0.5, 0.5, 0.5}, 0.05, 2));
    defects.triangles[3] = {defects.triangles[3][0], defects.triangles[3][2], defects.triangles[3][1]};  // misoriented
    defects.triangles.erase(defects.triangles.begin() + 100);                                            // a hole
    defects.triangles.push_back(defects.triangles[500]);                                                 // non-manifold
    defects.triangles.push_back({7, 7, 9});                                                              // degenerate
    defects.vertices.push_back(defects.vertices[11]);  // two at one place: zero area
    defects.triangles.push_back({11, std::uint32_t(defects.vertices.size() - 1), 12});
    defects.vertices.push_back({2, 2, 2});  // in no triangle
    // Two tetrahedra sharing a corner (a non-manifold vertex), and one lone triangle.
    Mesh bowtie;
    bowtie.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0}, {0, 0, -1}, {3, 3, 3}, {4, 3, 3}, {3, 4, 3}};
    bowtie.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {0, 5, 4}, {0, 4, 6}, {0, 6, 5}, {4, 5, 6}, {7, 8, 9}};
    const detail::Topology t = detail::mesh_topology(torus, detail::adjacency_of(torus));
    CHECK(t.genus == 1);
    CHECK(t.report.closed());
    const detail::Topology tt = detail::mesh_topology(two_tori, detail::adjacency_of(two_tori));
    CHECK(tt.genus == 2);
    CHECK(tt.report.solids == 2);
    const detail::Topology d = detail::mesh_topology(defects, detail::adjacency_of(defects));
    CHECK(d.report.boundary_edges > 0);
    CHECK(d.report.nonmanifold_edges > 0);
    CHECK(d.report.misoriented_edges > 0);
    CHECK(d.report.degenerate_triangles == 1);
    CHECK(d.report.zero_area_triangles == 1);
    CHECK(d.open_components > 0);
    const detail::Topology b = detail::mesh_topology(bowtie, detail::adjacency_of(bowtie));
    CHECK(b.report.nonmanifold_vertices == 1);
    CHECK(b.report.components == 3);
    CHECK(b.open_components == 1);
    std::mt19937 rng(5);
    for (const Mesh* m : std::vector<const Mesh*>{&sphere, &torus, &two_tori, &shell(), &defects, &bowtie}) {
        const detail::Topology whole = detail::mesh_topology(*m, detail::adjacency_of(*m));
        // check_mesh and measure_quality say the same.
        const MeshReport r = check_mesh(*m);
        CHECK(r.components == whole.report.components);
        CHECK(r.volume == whole.report.volume);
        const MeshQuality q = measure_quality(*m, {kCentre}, 0.05, 0.01);
        CHECK(q.genus == whole.genus);
        CHECK(q.open_components == whole.open_components);
        for (int processes = 1; processes <= 5; ++processes)
            for (int cut = 0; cut < 3; ++cut) {
                CAPTURE(processes);
                check_same_topology(topology_in_slabs(*m, processes, rng), whole);
            }
    }
}

namespace {

// Process p's share of the check as the whole mesh gives it (what the first cut out of it
// before the slabs gave the shares): the triangles with a corner near p, in order, their
// vertices numbered as they first come, the walls p measures.
detail::ShareMesh share_of_whole(const Mesh& whole, const detail::CheckDeal& deal, int p) {
    constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
    detail::ShareMesh share;
    std::vector<std::uint32_t> number(whole.vertices.size(), kNone);
    for (const auto& t : whole.triangles) {
        std::uint64_t near = 0;
        for (std::uint32_t v : t) near |= deal.near(whole.vertices[v]);
        if (!(near >> p & 1)) continue;
        std::array<std::uint32_t, 3> mine;
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t v = t[std::size_t(c)];
            if (number[v] == kNone) {
                number[v] = std::uint32_t(share.vertices.size());
                share.vertices.push_back(whole.vertices[v]);
                if (deal.walls_by[deal.tile_at(whole.vertices[v])] == p) {
                    share.measured.push_back(number[v]);
                    share.measured_whole.push_back(v);
                }
            }
            mine[std::size_t(c)] = number[v];
        }
        share.triangles.push_back(mine);
    }
    return share;
}

}  // namespace

TEST_CASE("quality: the check's shares gathered from slabs are the whole mesh's, to the bit") {
    const Mesh sphere = isosurface([](const Vec3& p) { return 0.3 - dist(p, kCentre); }, {0.1, 0.1, 0.1}, 0.02, 40);
    Mesh two_tori = testing::merge(torus_mesh(), torus_mesh());
    for (std::size_t k = two_tori.vertices.size() / 2; k < two_tori.vertices.size(); ++k) two_tori.vertices[k][0] += 0.55;
    std::mt19937 rng(11);
    std::size_t shares = 0, empty = 0;
    for (const Mesh* m : std::vector<const Mesh*>{&sphere, &two_tori, &shell()})
        for (int processes = 2; processes <= 5; ++processes)
            for (int round = 0; round < 3; ++round) {
                CAPTURE(processes);
                CAPTURE(round);
                // A grid of 4^3 tiles over the mesh's box, each tile's measurers at random.
                const Bounds box = bounds(m->vertices);
                detail::CheckDeal deal;
                deal.core = 4;
                deal.grid.nx = deal.grid.ny = deal.grid.nz = 16;
                deal.grid.h = box.longest() / 15;
                for (std::size_t a = 0; a < 3; ++a) deal.grid.origin[a] = box.lo[a] - 0.5 * deal.grid.h;
                deal.widened = std::uniform_real_distribution<double>(0, 2 * deal.grid.h)(rng);
                std::uniform_int_distribution<int> process(0, processes - 1);
                for (int t = 0; t < 64; ++t) {
                    deal.walls_by.push_back(std::uint8_t(process(rng)));
                    deal.measures_in.push_back(std::uint64_t(1) << deal.walls_by.back() | std::uint64_t(1) << process(rng));
                }
                const std::vector<Mesh> parts = slabs_of(*m, processes, rng);
                std::vector<detail::ShareMesh> got(parts.size());
                std::vector<std::uint64_t> bytes(parts.size());
                testing::on_threads(processes, [&](TileScheduler& on) {
                    const std::size_t p = std::size_t(on.rank());
                    detail::SlabMesh held(detail::SlabPart::of(parts[p]), on);
                    got[p] = detail::share_from_slabs(held, deal, on, bytes[p]);
                });
                for (int p = 0; p < processes; ++p) {
                    const detail::ShareMesh want = share_of_whole(*m, deal, p);
                    const detail::ShareMesh& share = got[std::size_t(p)];
                    CHECK(share.vertices == want.vertices);
                    CHECK(share.triangles == want.triangles);
                    CHECK(share.measured == want.measured);
                    CHECK(share.measured_whole == want.measured_whole);
                    CHECK(bytes[std::size_t(p)] == bytes[0]);
                    (want.triangles.empty() || want.triangles.size() == m->triangles.size() ? empty : shares) += 1;
                }
            }
    // Most shares hold part of the mesh, neither none nor all of it.
    MESSAGE(shares << " shares of part of a mesh, " << empty << " of none or all");
    CHECK(shares > 2 * empty);
}

TEST_CASE("quality: what no share decides, asked of the slabs, is the whole mesh's answer, to the bit") {
    const Mesh sphere = isosurface([](const Vec3& p) { return 0.3 - dist(p, kCentre); }, {0.1, 0.1, 0.1}, 0.02, 40);
    Mesh two_tori = testing::merge(torus_mesh(), torus_mesh());
    for (std::size_t k = two_tori.vertices.size() / 2; k < two_tori.vertices.size(); ++k) two_tori.vertices[k][0] += 0.55;
    std::mt19937 rng(13);
    std::size_t inside = 0, on_plane = 0, hit = 0;
    for (const Mesh* m : std::vector<const Mesh*>{&sphere, &two_tori, &shell()}) {
        // The whole mesh's answers: a wall's first hit, a point's nearest triangle and side
        // (as PointDepths measures it: by the plane, else a ray's crossings).
        const TriangleGrid whole(*m);
        const std::vector<Vec3> normals = detail::unit_normals(*m);
        const Bounds box = bounds(m->vertices);
        const double eps = detail::wall_epsilon(*m);
        std::vector<detail::FarWall> walls;
        std::vector<Vec3> points;
        std::uniform_int_distribution<std::uint32_t> vertex(0, std::uint32_t(m->vertices.size() - 1));
        std::uniform_int_distribution<std::size_t> triangle(0, m->triangles.size() - 1);
        std::uniform_real_distribution<double> unit(-1, 1);
        for (int k = 0; k < 200; ++k) {
            const std::uint32_t v = vertex(rng);
            walls.push_back({m->vertices[v], {-normals[v][0], -normals[v][1], -normals[v][2]}, v});
            Vec3 p;  // about the box and far beyond it, on vertices, on triangles' planes
            for (std::size_t a = 0; a < 3; ++a)
                p[a] = 0.5 * (box.lo[a] + box.hi[a]) + (k % 4 == 0 ? 3 : 0.7) * unit(rng) * box.extent(int(a));
            if (k % 5 == 1) p = m->vertices[v];
            if (k % 5 == 2) {
                const auto& t = m->triangles[triangle(rng)];
                for (std::size_t a = 0; a < 3; ++a)
                    p[a] = (m->vertices[t[0]][a] + m->vertices[t[1]][a] + m->vertices[t[2]][a]) / 3;
            }
            points.push_back(p);
        }
        std::vector<double> want_hits;
        std::vector<detail::PointDepths::Depth> want_depths;
        std::vector<std::uint8_t> want_rays;  // each point's side by a ray's crossings alone
        for (const detail::FarWall& w : walls) want_hits.push_back(whole.first_hit(w.origin, w.dir, eps, w.vertex).t);
        for (const Vec3& p : points) {
            const TriangleGrid::Closest c = whole.closest(p);
            const auto& t = m->triangles[c.triangle];
            int side = face_side(p, m->vertices[t[0]], m->vertices[t[1]], m->vertices[t[2]]);
            on_plane += side == 0;
            want_rays.push_back(whole.count_crossings(p, detail::PointDepths::ray_toward(p, box.lo, box.hi)) % 2);
            if (side == 0) side = want_rays.back() ? -1 : 1;
            want_depths.push_back({std::sqrt(c.dist_sq), side < 0});
            inside += side < 0;
        }
        for (double t : want_hits) hit += t < kInf;
        for (int processes = 1; processes <= 4; ++processes) {
            CAPTURE(processes);
            const std::vector<Mesh> parts = slabs_of(*m, processes, rng);
            std::vector<std::vector<double>> hits(parts.size());
            std::vector<std::vector<detail::PointDepths::Depth>> depths(parts.size());
            std::vector<std::vector<std::uint8_t>> rays(parts.size());
            // Each process asks its own part of the questions (some none).
            const std::size_t cut = std::uniform_int_distribution<std::size_t>(0, walls.size())(rng);
            testing::on_threads(processes, [&](TileScheduler& on) {
                const std::size_t p = std::size_t(on.rank());
                detail::SlabMesh held(detail::SlabPart::of(parts[p]), on);
                const auto part = [&](const auto& all) {
                    using V = std::decay_t<decltype(all)>;
                    return p == 0 ? V(all.begin(), all.begin() + std::ptrdiff_t(cut))
                                  : p == 1 ? V(all.begin() + std::ptrdiff_t(cut), all.end()) : V();
                };
                detail::FarQuestions asked;
                asked.walls = part(walls);
                asked.points = part(points);
                asked.sides = part(points);
                const detail::FarAnswers answers = detail::ask_slabs(held, eps, asked, on);
                hits[p] = answers.hits;
                depths[p] = answers.depths;
                rays[p] = answers.inside;
            });
            std::vector<double> got_hits = hits[0];
            std::vector<detail::PointDepths::Depth> got_depths = depths[0];
            std::vector<std::uint8_t> got_rays = rays[0];
            if (processes > 1) {
                got_hits.insert(got_hits.end(), hits[1].begin(), hits[1].end());
                got_depths.insert(got_depths.end(), depths[1].begin(), depths[1].end());
                got_rays.insert(got_rays.end(), rays[1].begin(), rays[1].end());
            } else {  // one process asks all
                testing::on_threads(1, [&](TileScheduler& on) {
                    detail::SlabMesh held(detail::SlabPart::of(parts[0]), on);
                    const detail::FarAnswers answers = detail::ask_slabs(held, eps, {walls, points, points}, on);
                    got_hits = answers.hits;
                    got_depths = answers.depths;
                    got_rays = answers.inside;
                });
            }
            REQUIRE(got_hits.size() == want_hits.size());
            REQUIRE(got_depths.size() == want_depths.size());
            REQUIRE(got_rays.size() == want_rays.size());
            for (std::size_t k = 0; k < want_hits.size(); ++k) {
                CAPTURE(k);
                CHECK(got_hits[k] == want_hits[k]);
                CHECK(got_depths[k].distance == want_depths[k].distance);
                CHECK(got_depths[k].inside == want_depths[k].inside);
                CHECK(got_rays[k] == want_rays[k]);
            }
        }
    }
    // Some of every kind: inside and out, on a plane (decided by the rays), walls met.
    MESSAGE(inside << " points inside, " << on_plane << " on their nearest triangle's plane, " << hit << " walls met");
    CHECK(inside > 50);
    CHECK(on_plane > 50);
    CHECK(hit > 300);
}

TEST_CASE("quality: a ball around one point: offset error, depth and wall") {
    const double l = 0.2, h = 0.01;
    const Mesh ball = icosphere(kCentre, l, 4);
    const MeshQuality q = measure_quality(ball, {kCentre}, l, h);
    CHECK(q.oriented);
    CHECK(q.genus == 0);
    CHECK(std::fabs(q.offset_rms) < 1e-12);  // every vertex is exactly l from the point
    CHECK(std::fabs(q.offset_mean) < 1e-12);
    CHECK(q.depth_min == doctest::Approx(1).epsilon(0.01));  // faces are chords, slightly inside
    CHECK(q.wall_min_2l == doctest::Approx(1).epsilon(0.01));  // the diameter
    CHECK(q.wall_min == doctest::Approx(2 * l / h).epsilon(0.01));
}

TEST_CASE("quality: dihedral angle and normal noise grow with noise") {
    const MeshQuality fine = measure_quality(icosphere(kCentre, 0.3, 5), {kCentre}, 0.3, 0.01);
    const MeshQuality noisy = measure_quality(icosphere(kCentre, 0.3, 5, 0.01), {kCentre}, 0.3, 0.01);
    MESSAGE("fine: dihedral " << fine.dihedral_rms << " deg, noise " << fine.normal_noise << " deg; noisy: "
                              << noisy.dihedral_rms << ", " << noisy.normal_noise);
    CHECK(fine.dihedral_rms < 2);     // edges span about 1.1 degrees of arc
    CHECK(fine.normal_noise < 0.5);   // smooth normals: neighbours agree
    CHECK(noisy.dihedral_rms > 3 * fine.dihedral_rms);
    CHECK(noisy.normal_noise > 5 * fine.normal_noise);
    CHECK(fine.interior_edges == 3 * fine.triangles / 2);
}

TEST_CASE("quality: measure_shell has measure_quality's figures for a print, and no surface figures") {
    // The shell with its cavity, and the torus with points in its hole: the depth's sign
    // comes from the windings alone here, so points outside must come out negative too.
    const Mesh torus = torus_mesh();
    PointSet around_torus = shapes::sphere({0.5, 0.5, 0.5}, 0.3, 0.03);  // in the tube and out of it
    const struct {
        const Mesh& mesh;
        PointSet points;
        double l, h;
    } cases[] = {{shell(), shapes::sphere(kCentre, kR, 0.02), kL, kH}, {torus, around_torus, 0.1, 0.02}};
    for (const auto& c : cases) {
        const MeshQuality all = measure_quality(c.mesh, c.points, c.l, c.h);
        const MeshQuality q = measure_shell(c.mesh, c.points, c.l, c.h);
        CHECK(all.has_surface);
        CHECK_FALSE(q.has_surface);
        CHECK(q.closed == all.closed);
        CHECK(q.manifold == all.manifold);
        CHECK(q.oriented == all.oriented);
        CHECK(q.components == all.components);
        CHECK(q.solids == all.solids);
        CHECK(q.genus == all.genus);
        CHECK(q.points_inside == all.points_inside);
        CHECK(q.points_outside == all.points_outside);
        CHECK(q.depth_min == all.depth_min);
        CHECK(q.depth_p01 == all.depth_p01);
        CHECK(q.wall_min == all.wall_min);
        CHECK(q.wall_p01 == all.wall_p01);
        CHECK(q.wall_misses == all.wall_misses);
        CHECK(std::isnan(q.offset_rms));
        CHECK(std::isnan(q.dihedral_rms));
        CHECK(std::isnan(q.normal_noise));
        const std::string json = quality_json(q);
        CHECK(json.find("\"wall_min_h\":") != std::string::npos);
        CHECK(json.find("offset_rms") == std::string::npos);
        CHECK(format_quality(q).find("smoothness") == std::string::npos);
    }
    CHECK(measure_shell(torus, around_torus, 0.1, 0.02).points_outside > 0);
    CHECK_THROWS_AS(measure_shell(torus, around_torus, 0, 0.02), ParameterError);
}

TEST_CASE("quality: bad arguments") {
    const Mesh ball = icosphere(kCentre, 0.2, 1);
    CHECK_THROWS_AS(measure_quality(ball, {kCentre}, 0, 0.01), ParameterError);
    CHECK_THROWS_AS(measure_quality(ball, {kCentre}, 0.1, -1), ParameterError);
    Mesh broken = ball;
    broken.triangles[3][1] = std::uint32_t(ball.vertices.size());
    CHECK_THROWS_AS(measure_quality(broken, {kCentre}, 0.1, 0.01), InputError);
}

namespace {

// The brute-force first hit: the least t > t_min over the triangles without vertex skip.
double first_hit_brute(const Mesh& mesh, const Vec3& p, const Vec3& d, double t_min, std::uint32_t skip) {
    double first = kInf;
    for (const auto& t : mesh.triangles) {
        if (t[0] == skip || t[1] == skip || t[2] == skip) continue;
        const double s = ray_triangle(p, d, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
        if (s > t_min && s < kInf) first = std::min(first, s);
    }
    return first;
}

// Random points and rays against every triangle: closest distance, first hit and
// the number of crossings as the grid finds them.
void check_grid_against_brute_force(const Mesh& mesh, unsigned seed, int queries, double lo, double hi) {
    const TriangleGrid grid(mesh);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> coord(lo, hi), unit(-1, 1);
    for (int n = 0; n < queries; ++n) {
        const Vec3 p{coord(rng), coord(rng), coord(rng)};
        double best = kInf;
        for (const auto& t : mesh.triangles)
            best = std::min(best, point_triangle_dist_sq(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]));
        CHECK(grid.closest(p).dist_sq == best);

        Vec3 d{unit(rng), unit(rng), unit(rng)};
        const double len = dist(d, {0, 0, 0});
        for (double& x : d) x /= len;
        std::size_t crossings = 0;
        for (const auto& t : mesh.triangles) {
            const double s = ray_triangle(p, d, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
            crossings += s > 0 && s < kInf;
        }
        const double first = first_hit_brute(mesh, p, d, 0, TriangleGrid::none);
        const TriangleGrid::Hit hit = grid.first_hit(p, d, 0);
        if (first == kInf) {
            CHECK(hit.t == kInf);
            CHECK(hit.triangle == TriangleGrid::none);
        } else {
            CHECK(hit.t == doctest::Approx(first).epsilon(1e-9));
        }
        CHECK(grid.count_crossings(p, d) == crossings);
    }
}

}  // namespace

TEST_CASE("triangle grid: closest triangle and first hit agree with brute force") {
    check_grid_against_brute_force(shell(), 11, 200, -0.2, 1.2);
    // Distance to a triangle's own plane, edges and corners.
    const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
    CHECK(point_triangle_dist_sq({0.2, 0.2, 0.5}, a, b, c) == doctest::Approx(0.25));
    CHECK(point_triangle_dist_sq({2, 0, 0}, a, b, c) == doctest::Approx(1));
    CHECK(point_triangle_dist_sq({1, 1, 0}, a, b, c) == doctest::Approx(0.5));
    CHECK(point_triangle_dist_sq({0.5, -1, 0}, a, b, c) == doctest::Approx(1));
    CHECK(point_triangle_dist_sq({3, 0, 0}, a, b, {2, 0, 0}) == doctest::Approx(1));  // degenerate
}


TEST_CASE("triangle grid: bounds, rays along the axes and from the vertices agree with brute force") {
    const Mesh& mesh = shell();
    const TriangleGrid grid(mesh);
    const auto brute_closest = [&](const Vec3& p) {
        double best = kInf;
        for (const auto& t : mesh.triangles)
            best = std::min(best, point_triangle_dist_sq(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]));
        return best;
    };
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> coord(-1.0, 2.0), unit(-1, 1);
    for (int n = 0; n < 100; ++n) {
        // Far outside the grid as well as in it.
        const Vec3 p{coord(rng), coord(rng), coord(rng)};
        const double best = brute_closest(p);
        CHECK(grid.closest(p).dist_sq == best);
        // A bound just above the distance finds the same triangle; one below finds nothing.
        const TriangleGrid::Closest above = grid.closest(p, best * (1 + 1e-6));
        CHECK(above.dist_sq == best);
        CHECK(above.triangle != TriangleGrid::none);
        const TriangleGrid::Closest below = grid.closest(p, best * (1 - 1e-6));
        CHECK(below.dist_sq == kInf);
        CHECK(below.triangle == TriangleGrid::none);
        // Rays along an axis (two direction components zero).
        for (int axis = 0; axis < 3; ++axis)
            for (double sign : {-1.0, 1.0}) {
                Vec3 d{0, 0, 0};
                d[axis] = sign;
                const double first = first_hit_brute(mesh, p, d, 0, TriangleGrid::none);
                const TriangleGrid::Hit hit = grid.first_hit(p, d, 0);
                if (first == kInf)
                    CHECK(hit.t == kInf);
                else
                    CHECK(hit.t == doctest::Approx(first).epsilon(1e-9));
            }
    }
    // Rays from vertices inwards and outwards, their own triangles left out, as the walls are measured.
    std::uniform_int_distribution<std::size_t> pick(0, mesh.vertices.size() - 1);
    for (int n = 0; n < 100; ++n) {
        const auto v = std::uint32_t(pick(rng));
        Vec3 d{unit(rng), unit(rng), unit(rng)};
        const double len = dist(d, {0, 0, 0});
        for (double& x : d) x /= len;
        const double first = first_hit_brute(mesh, mesh.vertices[v], d, 1e-9, v);
        const TriangleGrid::Hit hit = grid.first_hit(mesh.vertices[v], d, 1e-9, v);
        if (first == kInf)
            CHECK(hit.t == kInf);
        else
            CHECK(hit.t == doctest::Approx(first).epsilon(1e-9));
    }
}

TEST_CASE("triangle grid: triangles many cells wide among small ones agree with brute force") {
    // The cells follow the mean triangle, so the two large triangles cross hundreds of
    // cells, where each cell keeps only the part of their box near it.
    Mesh mesh = shell();
    const auto first = std::uint32_t(mesh.vertices.size());
    mesh.vertices.push_back({-0.3, -0.2, 0.45});
    mesh.vertices.push_back({1.4, 0.1, 0.55});
    mesh.vertices.push_back({0.2, 1.3, 0.5});
    mesh.vertices.push_back({0.5, 0.5, -0.4});
    mesh.triangles.push_back({first, first + 1, first + 2});
    mesh.triangles.push_back({first, first + 3, first + 1});
    check_grid_against_brute_force(mesh, 17, 300, -0.5, 1.5);
}

TEST_CASE("quality: the same figures with one thread and with two") {
    const Mesh& mesh = shell();  // big enough for every parallel path
    const PointSet points = shapes::sphere(kCentre, kR, 0.01);
    const auto json = [&](int threads) {
        return with_threads(threads, [&] {
            std::string s = quality_json(measure_quality(mesh, points, kL, kH));
            return s.substr(0, s.find("\"seconds\""));
        });
    };
    const std::string one = json(1);
    CHECK(one == json(2));
    CHECK(one == json(3));
    const auto shell_json = [&](int threads) {
        return with_threads(threads, [&] {
            std::string s = quality_json(measure_shell(mesh, points, kL, kH));
            return s.substr(0, s.find("\"seconds\""));
        });
    };
    CHECK(shell_json(1) == shell_json(2));
    CHECK(with_threads(1, [&] { return thinnest_wall(mesh); }) == with_threads(2, [&] { return thinnest_wall(mesh); }));
    const MeshReport r1 = with_threads(1, [&] { return check_mesh(mesh); });
    const MeshReport r2 = with_threads(2, [&] { return check_mesh(mesh); });
    CHECK(r1.volume == r2.volume);
    CHECK(r1.components == r2.components);
    CHECK(r1.solids == r2.solids);
    CHECK(with_threads(1, [&] { return count_points_inside(mesh, points); }) ==
          with_threads(2, [&] { return count_points_inside(mesh, points); }));
}

TEST_CASE("count_point_clusters: the pieces of linking every pair closer than the distance") {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> coord(0, 1);
    PointSet points;
    for (int n = 0; n < 1500; ++n) points.push_back({coord(rng), coord(rng), 0.1 * coord(rng)});
    points.push_back(points[17]);  // a duplicate
    points.push_back({std::numeric_limits<double>::quiet_NaN(), 0.5, 0.5});  // never linked
    points.push_back({kInf, 0.5, 0.5});
    // The library holds points as float (about the origin here: they lie near it).
    PointSet held = points;
    for (Vec3& p : held)
        for (double& x : p) x = double(float(x));
    const auto brute = [&](double link) {
        const PointSet& points = held;
        std::vector<std::size_t> parent(points.size());
        for (std::size_t n = 0; n < parent.size(); ++n) parent[n] = n;
        const auto root = [&](std::size_t n) {
            while (parent[n] != n) n = parent[n] = parent[parent[n]];
            return n;
        };
        for (std::size_t a = 0; a < points.size(); ++a)
            for (std::size_t b = a + 1; b < points.size(); ++b) {
                const double dx = points[a][0] - points[b][0], dy = points[a][1] - points[b][1],
                             dz = points[a][2] - points[b][2];
                if (dx * dx + dy * dy + dz * dz < link * link) parent[std::max(root(a), root(b))] = std::min(root(a), root(b));
            }
        std::size_t roots = 0;
        for (std::size_t n = 0; n < points.size(); ++n) roots += root(n) == n;
        return roots;
    };
    for (double link : {0.0, 0.005, 0.02, 0.03, 0.05, 0.2, 2.0}) {
        CAPTURE(link);
        CHECK(count_point_clusters(points, link) == brute(link));
    }
}

TEST_CASE("read_mesh: round trip through write_mesh, and bad files") {
    TempDir dir("quality");
    const Mesh mesh = icosphere(kCentre, 0.25, 2);
    for (const char* name : {"m.stl", "m.ply", "m.obj"}) {
        CAPTURE(name);
        const std::string path = dir.file(name);
        write_mesh(mesh, path);
        const Mesh back = read_mesh(path);
        REQUIRE(back.triangles.size() == mesh.triangles.size());
        CHECK(back.vertices.size() == mesh.vertices.size());  // STL corners welded again
        const double tolerance = std::string(name) == "m.obj" ? 0 : 1e-7;
        double worst = 0;
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
            for (int k = 0; k < 3; ++k)
                worst = std::max(worst, dist(mesh.vertices[mesh.triangles[t][k]], back.vertices[back.triangles[t][k]]));
        CHECK(worst <= tolerance);
        const MeshReport report = check_mesh(back);
        CHECK(report.closed());
        CHECK(report.oriented());
    }

    // ASCII STL and OBJ polygons with slashes and negative indices.
    write_text(dir.file("tet.stl"),
               "solid tet\n"
               "facet normal 0 0 -1\n outer loop\n  vertex 0 0 0\n  vertex 0 1 0\n  vertex 1 0 0\n endloop\nendfacet\n"
               "facet normal 0 -1 0\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 0 1\n endloop\nendfacet\n"
               "facet normal -1 0 0\n outer loop\n  vertex 0 0 0\n  vertex 0 0 1\n  vertex 0 1 0\n endloop\nendfacet\n"
               "facet normal 1 1 1\n outer loop\n  vertex 1 0 0\n  vertex 0 1 0\n  vertex 0 0 1\n endloop\nendfacet\n"
               "endsolid tet\n");
    const Mesh tet = read_mesh(dir.file("tet.stl"));
    CHECK(tet.vertices.size() == 4);
    CHECK(tet.triangles.size() == 4);
    CHECK(check_mesh(tet).closed());
    CHECK(check_mesh(tet).oriented());
    write_text(dir.file("quad.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1 4//1\nf -1 -2 -3\n");
    const Mesh quad = read_mesh(dir.file("quad.obj"));
    CHECK(quad.triangles.size() == 3);
    CHECK(quad.triangles[2] == std::array<std::uint32_t, 3>{3, 2, 1});

    // A truncated binary STL, broken text and missing files.
    const std::string stl = dir.file("m.stl");
    fs::resize_file(stl, fs::file_size(stl) - 10);
    const auto message = [](const std::string& path) {
        try {
            read_mesh(path);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    CHECK_THROWS_AS(read_mesh(stl), InputError);
    CHECK(message(stl).find("truncated") != std::string::npos);
    CHECK(message(stl).find(stl) != std::string::npos);
    write_text(dir.file("bad.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 3\n");
    CHECK_THROWS_AS(read_mesh(dir.file("bad.obj")), InputError);
    CHECK(message(dir.file("bad.obj")).find("line 3") != std::string::npos);
    write_text(dir.file("bad.stl"), "solid x\nfacet normal 0 0 1\n outer loop\n vertex 0 0\n");
    CHECK(message(dir.file("bad.stl")).find("line 4") != std::string::npos);
    const std::string ply = dir.file("m.ply");
    fs::resize_file(ply, fs::file_size(ply) - 5);
    CHECK_THROWS_AS(read_mesh(ply), InputError);
    CHECK(message(ply).find("face records") != std::string::npos);
    CHECK_THROWS_AS(read_mesh(dir.file("missing.stl")), IoError);
    fs::copy_file(ply, dir.file("m.off"));  // a file that exists, with an extension it does not read
    CHECK_THROWS_AS(read_mesh(dir.file("m.off")), InputError);
}
