// Isosurface extraction, mesh checks and point-in-mesh counting.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "mesh_fields.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh.hpp"
#include "snvr/quality.hpp"

#if __has_include(<omp.h>)
#include <omp.h>
#define SNVR_TEST_OMP 1
#endif

using namespace snvr;
using namespace snvr::testing;

namespace {

void require_watertight(const MeshReport& r) {
    CHECK(r.triangles > 0);
    check_printable(r);
    // Closed 2-manifold: E = 3F/2 and V - E + F is even.
    CHECK(r.triangles % 2 == 0);
    const long euler = long(r.vertices) - long(3 * r.triangles / 2) + long(r.triangles);
    CHECK(euler % 2 == 0);
}

bool all_vertices_used(const Mesh& m) {
    std::vector<char> used(m.vertices.size(), 0);
    for (const auto& t : m.triangles)
        for (auto v : t) used[v] = 1;
    for (char u : used)
        if (!u) return false;
    return true;
}

// Sign-changing edges of the Kuhn triangulation (offsets: non-empty subsets of
// +x, +y, +z), counted independently of the extractor.
std::size_t count_crossing_edges(const Grid& g, double iso) {
    std::size_t n = 0;
    const Field& f = g.field;
    for (int k = 0; k < f.nz; ++k)
        for (int j = 0; j < f.ny; ++j)
            for (int i = 0; i < f.nx; ++i)
                for (int d = 1; d < 8; ++d) {
                    const int i2 = i + (d & 1), j2 = j + (d >> 1 & 1), k2 = k + (d >> 2);
                    if (i2 >= f.nx || j2 >= f.ny || k2 >= f.nz) continue;
                    n += (f.at(i, j, k) > iso) != (f.at(i2, j2, k2) > iso);
                }
    return n;
}

Mesh unit_cube() {
    Mesh m;
    for (int c = 0; c < 8; ++c) m.vertices.push_back({double(c & 1), double(c >> 1 & 1), double(c >> 2)});
    // Outward; the top (z = 1) face is split along (0,0,1)-(1,1,1).
    m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                   {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
    return m;
}

Mesh octahedron() {
    Mesh m;
    m.vertices = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (std::uint32_t x : {0u, 1u})
        for (std::uint32_t y : {2u, 3u})
            for (std::uint32_t z : {4u, 5u}) {
                // Outward when (x, y, z) is a right-handed triple of the octant's axes.
                const bool flip = ((x == 1) != (y == 3)) != (z == 5);
                m.triangles.push_back(flip ? std::array<std::uint32_t, 3>{x, z, y}
                                           : std::array<std::uint32_t, 3>{x, y, z});
            }
    return m;
}

Mesh tetrahedron(Vec3 o, double s) {
    Mesh m;
    m.vertices = {o, {o[0] + s, o[1], o[2]}, {o[0], o[1] + s, o[2]}, {o[0], o[1], o[2] + s}};
    m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    return m;
}

}  // namespace

TEST_CASE("sphere field: closed, oriented, one component, close to the sphere") {
    const int sizes[][3] = {{24, 24, 24}, {25, 25, 25}, {20, 27, 33}, {31, 22, 26}};
    for (const auto& n : sizes)
        for (Precision precision : {Precision::Double, Precision::Single}) {
            CAPTURE(n[0]);
            CAPTURE(n[1]);
            CAPTURE(n[2]);
            const double h = 0.1;
            const Vec3 origin{-1.0, 2.0, 0.5};
            Vec3 c{origin[0] + 0.5 * n[0] * h, origin[1] + 0.5 * n[1] * h, origin[2] + 0.5 * n[2] * h};
            c[0] += 0.013;  // off the grid's symmetry
            const double r0 = 0.38 * std::min({n[0], n[1], n[2]}) * h;
            const Grid g = make_grid(n[0], n[1], n[2], h, origin,
                                     [&](const Vec3& p, int, int, int) { return r0 - dist(p, c); }, precision);
            const Mesh m = extract_isosurface(g.field, g.domain);
            const MeshReport r = check_mesh(m);
            require_watertight(r);
            CHECK(r.components == 1);
            CHECK(long(r.vertices) - long(3 * r.triangles / 2) + long(r.triangles) == 2);  // a sphere
            CHECK(all_vertices_used(m));
            CHECK(r.vertices == count_crossing_edges(g, 0.0));
            const double exact = 4.0 / 3.0 * kPi * r0 * r0 * r0;
            CHECK(std::fabs(r.volume - exact) < 0.02 * exact);
            double sq = 0;
            for (const Vec3& v : m.vertices) sq += std::pow(dist(v, c) - r0, 2);
            CHECK(std::sqrt(sq / double(m.vertices.size())) < 0.05 * h);
        }
}

TEST_CASE("sphere field with a non-zero iso value shrinks the sphere") {
    const double h = 0.05, iso = 0.1;
    const Grid g = make_grid(40, 40, 40, h, {0, 0, 0}, [](const Vec3& p, int, int, int) {
        return 0.8 - dist(p, {1, 1, 1});
    });
    const MeshReport r = check_mesh(extract_isosurface(g.field, g.domain, iso));
    require_watertight(r);
    const double exact = 4.0 / 3.0 * kPi * std::pow(0.7, 3);
    CHECK(std::fabs(r.volume - exact) < 0.02 * exact);
}

TEST_CASE("thin spherical shell: two closed sheets enclosing the difference of volumes") {
    for (int n : {40, 41}) {
        const double h = 1.0 / n, r0 = 0.3, w = 2.2 * h;
        const Vec3 c{0.5, 0.5, 0.5};
        const Grid g = make_grid(n, n, n, h, {0, 0, 0}, [&](const Vec3& p, int, int, int) {
            return w - std::fabs(dist(p, c) - r0);
        });
        const Mesh m = extract_isosurface(g.field, g.domain);
        const MeshReport r = check_mesh(m);
        require_watertight(r);
        CHECK(r.components == 2);
        const double exact = 4.0 / 3.0 * kPi * (std::pow(r0 + w, 3) - std::pow(r0 - w, 3));
        CHECK(std::fabs(r.volume - exact) < 0.02 * exact);
        // Points in the shell are inside, the hollow and the outside are not.
        const PointSet in_shell{{0.5, 0.5, 0.5 + r0}, {0.5 + r0, 0.5, 0.5}, {0.5, 0.5 - r0, 0.5}};
        const PointSet out{{0.5, 0.5, 0.5}, {0.5, 0.5, 0.5 + 0.5 * r0}, {0.05, 0.05, 0.05}, {0.5, 0.5, 0.95}};
        CHECK(count_points_inside(m, in_shell) == in_shell.size());
        CHECK(count_points_inside(m, out) == 0);
    }
}

TEST_CASE("random fields always give closed, manifold, oriented meshes") {
    const int sizes[][3] = {{7, 9, 11}, {8, 8, 8}, {3, 3, 3}, {5, 6, 4}, {12, 10, 9}, {4, 13, 3}, {70, 3, 5}};
    enum Kind { Uniform, Ternary, TernaryShiftedIso };
    for (Kind kind : {Uniform, Ternary, TernaryShiftedIso})
        for (const auto& n : sizes)
            for (unsigned seed = 1; seed <= 25; ++seed) {
                CAPTURE(int(kind));
                CAPTURE(n[0]);
                CAPTURE(n[1]);
                CAPTURE(n[2]);
                CAPTURE(seed);
                std::mt19937 rng(seed * 7919u + unsigned(n[0] * 31 + n[1] * 17 + n[2]));
                std::uniform_real_distribution<double> uniform(-1, 1);
                std::uniform_int_distribution<int> ternary(-1, 1);
                // Ternary fields put many samples exactly on the iso value.
                const double iso = kind == TernaryShiftedIso ? 0.5 : 0.0;
                const Grid g = make_grid(n[0], n[1], n[2], 0.5, {1, -2, 3}, [&](const Vec3&, int i, int j, int k) {
                    if (i == 0 || j == 0 || k == 0 || i == n[0] - 1 || j == n[1] - 1 || k == n[2] - 1) return iso - 1;
                    return kind == Uniform ? uniform(rng) : iso + 0.5 * ternary(rng);
                });
                const Mesh m = extract_isosurface(g.field, g.domain, iso);
                CHECK(m.vertices.size() == count_crossing_edges(g, iso));
                PointSet above, below;
                for (int k = 0; k < n[2]; ++k)
                    for (int j = 0; j < n[1]; ++j)
                        for (int i = 0; i < n[0]; ++i) {
                            const double v = g.field.at(i, j, k);
                            if (v > iso) above.push_back(g.domain.cell_center(i, j, k));
                            if (v < iso) below.push_back(g.domain.cell_center(i, j, k));
                        }
                if (above.empty()) {
                    CHECK(m.triangles.empty());
                    continue;
                }
                const MeshReport r = check_mesh(m);
                require_watertight(r);
                CHECK(all_vertices_used(m));
                // The surface is the level set of the interpolant, which equals the samples.
                CHECK(count_points_inside(m, above) == above.size());
                CHECK(count_points_inside(m, below) == 0);
            }
}

TEST_CASE("a single positive sample gives the 24-triangle star of its vertex") {
    struct Case {
        double value, rest, volume;
    };
    // With the other samples exactly on the iso value every vertex sits on a
    // neighbouring sample: the star is the union of the 24 tetrahedra around
    // the sample, volume 24/6.  With -value around, it is half as wide.
    for (const Case c : {Case{1.0, 0.0, 4.0}, Case{1e-300, 0.0, 4.0}, Case{1.0, -1.0, 0.5}}) {
        const Grid g = make_grid(5, 6, 7, 1.0, {0, 0, 0}, [&](const Vec3&, int i, int j, int k) {
            return i == 2 && j == 3 && k == 3 ? c.value : c.rest;
        });
        const Mesh m = extract_isosurface(g.field, g.domain);
        const MeshReport r = check_mesh(m);
        require_watertight(r);
        CHECK(r.vertices == 14);
        CHECK(r.triangles == 24);
        CHECK(r.components == 1);
        CHECK(r.volume == doctest::Approx(c.volume));
        CHECK(count_points_inside(m, {g.domain.cell_center(2, 3, 3)}) == 1);
    }
}

TEST_CASE("no surface: all below, all equal to iso, or too few samples") {
    const Grid below = make_grid(6, 5, 4, 1.0, {0, 0, 0}, [](const Vec3&, int, int, int) { return -1.0; });
    CHECK(extract_isosurface(below.field, below.domain).triangles.empty());
    const Grid flat = make_grid(6, 5, 4, 1.0, {0, 0, 0}, [](const Vec3&, int, int, int) { return 0.0; });
    CHECK(extract_isosurface(flat.field, flat.domain).triangles.empty());
    const Grid thin = make_grid(6, 1, 4, 1.0, {0, 0, 0}, [](const Vec3&, int, int, int) { return 1.0; });
    CHECK(extract_isosurface(thin.field, thin.domain).triangles.empty());

    Grid bad = below;
    bad.domain.nx = 7;
    CHECK_THROWS_AS(extract_isosurface(bad.field, bad.domain), ParameterError);
    bad = below;
    bad.field.nz = 12;  // the shape no longer the bricks'
    bad.domain.nz = 12;
    CHECK_THROWS_AS(extract_isosurface(bad.field, bad.domain), InputError);
    CHECK_THROWS_AS(extract_dual_isosurface(bad.field, bad.domain), InputError);
}

TEST_CASE("check_mesh detects defects") {
    const Mesh cube = unit_cube();
    const MeshReport ok = check_mesh(cube);
    require_watertight(ok);
    CHECK(ok.components == 1);
    CHECK(ok.volume == doctest::Approx(1.0));

    SUBCASE("open: a triangle removed") {
        Mesh m = cube;
        m.triangles.pop_back();
        const MeshReport r = check_mesh(m);
        CHECK(r.boundary_edges == 3);
        CHECK_FALSE(r.closed());
        CHECK(r.manifold());
        CHECK(r.misoriented_edges == 0);
    }
    SUBCASE("one triangle flipped") {
        Mesh m = cube;
        std::swap(m.triangles[5][1], m.triangles[5][2]);
        const MeshReport r = check_mesh(m);
        CHECK(r.misoriented_edges == 3);
        CHECK(r.closed());
        CHECK_FALSE(r.oriented());
    }
    SUBCASE("all triangles flipped: consistent but inward") {
        Mesh m = cube;
        for (auto& t : m.triangles) std::swap(t[1], t[2]);
        const MeshReport r = check_mesh(m);
        CHECK(r.misoriented_edges == 0);
        CHECK(r.volume == doctest::Approx(-1.0));
        CHECK_FALSE(r.oriented());
    }
    SUBCASE("three triangles on one edge") {
        Mesh m = cube;
        m.vertices.push_back({0.5, -1, 0});
        m.triangles.push_back({0, 1, 8});  // a fin on the edge 0-1
        const MeshReport r = check_mesh(m);
        CHECK(r.nonmanifold_edges == 1);
        CHECK(r.boundary_edges == 2);
        CHECK_FALSE(r.manifold());
        CHECK(r.components == 1);
    }
    SUBCASE("bow-tie vertex: two tetrahedra touching at a corner") {
        // The second tetrahedron is the first mirrored through their shared vertex 0.
        Mesh m = tetrahedron({0, 0, 0}, 1);
        m.vertices.insert(m.vertices.end(), {{-1, 0, 0}, {0, -1, 0}, {0, 0, -1}});
        for (auto t : std::vector<std::array<std::uint32_t, 3>>{{0, 4, 5}, {0, 5, 6}, {0, 6, 4}, {4, 6, 5}})
            m.triangles.push_back(t);
        const MeshReport r = check_mesh(m);
        CHECK(r.nonmanifold_vertices == 1);
        CHECK(r.nonmanifold_edges == 0);
        CHECK(r.boundary_edges == 0);
        CHECK(r.misoriented_edges == 0);
        CHECK(r.components == 2);
        CHECK_FALSE(r.manifold());
        CHECK(r.volume == doctest::Approx(2.0 / 6.0));
    }
    SUBCASE("degenerate triangle") {
        Mesh m = cube;
        m.triangles.push_back({3, 3, 5});
        const MeshReport r = check_mesh(m);
        CHECK(r.degenerate_triangles == 1);
        CHECK_FALSE(r.manifold());
        CHECK(r.boundary_edges == 0);
    }
    SUBCASE("zero-area triangles: corners at one place or on one line") {
        Mesh m = cube;
        CHECK(check_mesh(m).zero_area_triangles == 0);
        m.vertices[1] = m.vertices[0];  // an edge of length zero
        const std::size_t at_one_place = check_mesh(m).zero_area_triangles;
        CHECK(at_one_place > 0);
        m = cube;
        m.vertices.push_back({0.5, 0, 0});  // on the edge from (0,0,0) to (1,0,0)
        m.triangles.push_back({0, std::uint32_t(m.vertices.size() - 1), 1});
        CHECK(check_mesh(m).zero_area_triangles == 1);
        CHECK(check_mesh(m).degenerate_triangles == 0);
    }
    SUBCASE("two separate closed pieces") {
        const MeshReport r = check_mesh(merge(cube, tetrahedron({3, 3, 3}, 1)));
        require_watertight(r);
        CHECK(r.components == 2);
        CHECK(r.volume == doctest::Approx(1.0 + 1.0 / 6.0));
    }
    SUBCASE("index out of range") {
        Mesh m = cube;
        m.triangles.push_back({0, 1, 99});
        CHECK_THROWS_AS(check_mesh(m), InputError);
        CHECK_THROWS_AS(count_points_inside(m, {{0.5, 0.5, 0.5}}), InputError);
    }
    SUBCASE("empty mesh") {
        const MeshReport r = check_mesh(Mesh{});
        CHECK_FALSE(r.closed());
        CHECK(r.components == 0);
        CHECK(count_points_inside(Mesh{}, {{0, 0, 0}}) == 0);
    }
}

TEST_CASE("count_points_inside: rays through vertices and edges") {
    SUBCASE("cube") {
        const Mesh m = unit_cube();
        // (0.5, 0.5) and (0.25, 0.25) lie on the diagonals of the top and bottom faces.
        const PointSet inside{{0.5, 0.5, 0.5}, {0.25, 0.25, 0.1}, {0.3, 0.6, 0.9}, {0.999, 0.001, 0.5}};
        const PointSet outside{{0.5, 0.5, 1.5}, {0.5, 0.5, -0.5}, {0, 0, -1}, {1, 1, -1}, {0, 1, -1},
                               {0.5, 0, -1},   {1, 0.5, -1},    {0.5, 1, 2}, {2, 0.5, 0.5}, {0.5, 0.5, 1.0001}};
        CHECK(count_points_inside(m, inside) == inside.size());
        CHECK(count_points_inside(m, outside) == 0);
    }
    SUBCASE("octahedron") {
        const Mesh m = octahedron();
        REQUIRE(check_mesh(m).oriented());
        // Through the apex, through edges, through the silhouette vertices and edges.
        const PointSet inside{{0, 0, 0}, {0.5, 0, 0}, {0, 0.5, -0.2}, {0.2, 0.2, 0.2}, {-0.5, 0, 0.4}, {0, -0.25, -0.7}};
        const PointSet outside{{0, 0, -2},   {0, 0, 2},       {0.5, 0, -2}, {1, 0, -3},
                               {0.5, 0.5, -2}, {-0.5, -0.5, 0}, {2, 2, 0},    {0, 1, -1}};
        CHECK(count_points_inside(m, inside) == inside.size());
        CHECK(count_points_inside(m, outside) == 0);
    }
    SUBCASE("extracted sphere: rays through every vertex") {
        const double h = 0.25, r0 = 1.25;  // samples at offsets like (3,0,4) h are exactly on the sphere
        const Grid g = make_grid(21, 21, 21, h, {0, 0, 0}, [&](const Vec3& p, int, int, int) {
            return r0 - dist(p, {2.625, 2.625, 2.625});
        });
        const Vec3 c{2.625, 2.625, 2.625};
        const Mesh m = extract_isosurface(g.field, g.domain);
        require_watertight(check_mesh(m));
        PointSet inside, outside;
        for (const Vec3& v : m.vertices) {
            outside.push_back({v[0], v[1], c[2] + 2 * r0});
            outside.push_back({v[0], v[1], c[2] - 2 * r0});
            if (std::hypot(v[0] - c[0], v[1] - c[1]) < r0 - 0.3 * h) inside.push_back({v[0], v[1], c[2]});
        }
        for (std::size_t t = 0; t < m.triangles.size(); t += 3) {  // rays through (or next to) edge midpoints
            const Vec3 &a = m.vertices[m.triangles[t][0]], &b = m.vertices[m.triangles[t][1]];
            const double x = 0.5 * (a[0] + b[0]), y = 0.5 * (a[1] + b[1]);
            if (std::hypot(x - c[0], y - c[1]) < r0 - 0.3 * h) inside.push_back({x, y, c[2] + 0.1 * h});
        }
        for (double z = -3.9; z < 4; z += 0.5) inside.push_back({c[0] + 3 * h, c[1], c[2] + z * h});
        CHECK(inside.size() > 100);
        CHECK(count_points_inside(m, inside) == inside.size());
        CHECK(count_points_inside(m, outside) == 0);

        // Random points away from the surface agree with the exact sphere.
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> u(0, 21 * h);
        PointSet pts;
        std::size_t expected = 0;
        while (pts.size() < 20000) {
            const Vec3 p{u(rng), u(rng), u(rng)};
            const double r = dist(p, c);
            if (std::fabs(r - r0) < 0.1 * h) continue;
            pts.push_back(p);
            expected += r < r0;
        }
        CHECK(count_points_inside(m, pts) == expected);
    }
}

#ifdef SNVR_TEST_OMP
TEST_CASE("extraction and checks do not depend on the thread count") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> noise(-0.02, 0.02);
    const int n = 48;
    const double h = 1.0 / n;
    const Grid g = make_grid(n, n + 3, n - 5, h, {0, 0, 0}, [&](const Vec3& p, int, int, int) {
        return 2.5 * h - std::fabs(dist(p, {0.5, 0.52, 0.45}) - 0.3) + noise(rng) * h;
    });
    const int before = omp_get_max_threads();
    omp_set_num_threads(1);
    const Mesh one = extract_isosurface(g.field, g.domain);
    const MeshReport r1 = check_mesh(one);
    omp_set_num_threads(2);
    const Mesh two = extract_isosurface(g.field, g.domain);
    const MeshReport r2 = check_mesh(two);
    omp_set_num_threads(before);
    CHECK(one.vertices == two.vertices);
    CHECK(one.triangles == two.triangles);
    CHECK(r1.volume == r2.volume);
    CHECK(r1.components == r2.components);
    require_watertight(r1);
}
#endif

TEST_CASE("shell_warnings: one sentence per defect, none for a good shell") {
    snvr::MeshQuality q;
    q.report.triangles = 8;
    q.report.volume = 1;
    q.report.solids = 1;
    q.points_inside = 10;
    CHECK(snvr::shell_warnings(q, 10, 1).empty());
    q.report.solids = 3;  // two more solid pieces than the points' clusters
    q.report.boundary_edges = 4;
    q.report.misoriented_edges = 2;
    q.points_inside = 7;
    const std::vector<std::string> w = snvr::shell_warnings(q, 10, 1);
    REQUIRE(w.size() == 4);
    CHECK(w[0].find("fell apart into 3 solid pieces") != std::string::npos);
    CHECK(w[1].find("4 boundary edges") != std::string::npos);
    CHECK(w[2].find("2 misoriented edges") != std::string::npos);
    CHECK(w[3].find("encloses 7 of 10 points") != std::string::npos);
    q.report.solids = 1;  // cavities' extra components are no defect
    q.report.components = 2;
    q.report.boundary_edges = 0;
    q.report.misoriented_edges = 0;
    q.points_inside = 10;
    CHECK(snvr::shell_warnings(q, 10, 1).empty());
}

TEST_CASE("filter_pieces: a piece is a solid with its cavities; the smallest go first") {
    // A unit cube holding a cavity (a cube of side 0.5, turned inward), a tetrahedron of
    // volume 1/6 far off, and a tiny one (1/6000) farther still.
    Mesh hollow = unit_cube();
    for (Vec3& v : hollow.vertices)
        for (double& x : v) x = 0.25 + 0.5 * x;
    for (auto& t : hollow.triangles) std::swap(t[1], t[2]);
    const Mesh all = merge(merge(merge(unit_cube(), hollow), tetrahedron({3, 3, 3}, 1)), tetrahedron({6, 0, 0}, 0.1));
    REQUIRE(check_mesh(all).solids == 3);
    SUBCASE("no filter: nothing changes") {
        Mesh m = all;
        const PieceReport r = filter_pieces(m, {});
        CHECK(r.dropped == 0);
        CHECK(m.triangles.size() == all.triangles.size());
    }
    SUBCASE("by volume: the tiny tetrahedron goes, the cube keeps its cavity") {
        Mesh m = all;
        const PieceReport r = filter_pieces(m, {0.01, 0});
        CHECK(r.dropped == 1);
        CHECK(r.kept == 2);
        CHECK(r.dropped_volume == doctest::Approx(1.0 / 6000));
        const MeshReport c = check_mesh(m);
        CHECK(c.solids == 2);
        CHECK(c.components == 3);
        CHECK(c.closed());
        CHECK(c.volume == doctest::Approx(1 - 0.125 + 1.0 / 6));
        CHECK(m.vertices.size() == all.vertices.size() - 4);  // its vertices gone too
    }
    SUBCASE("the largest only: the hollow cube (0.875) over the tetrahedron (1/6)") {
        Mesh m = all;
        const PieceReport r = filter_pieces(m, {0, 1});
        CHECK(r.dropped == 2);
        const MeshReport c = check_mesh(m);
        CHECK(c.solids == 1);
        CHECK(c.components == 2);
        CHECK(c.volume == doctest::Approx(0.875));
    }
    CHECK_THROWS_AS(PieceFilter({-1, 0}).validate(), ParameterError);
}
