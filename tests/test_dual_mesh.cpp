// Dual marching cubes: printable (closed, manifold, oriented) meshes on every sign
// pattern, close to the exact surface, about a third of the tetrahedra mesher's triangles.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "mesh/dual_pieces.hpp"
#include "mesh_fields.hpp"
#include "snvr/error.hpp"
#include "snvr/quality.hpp"
#include "snvr/mesh.hpp"

using namespace snvr;
using namespace snvr::testing;

namespace {

// Printable, plus the counts a closed triangulated 2-manifold must satisfy.
bool watertight(const Mesh& m) {
    const MeshReport r = check_mesh(m);
    const bool ok = r.triangles > 0 && r.closed() && r.manifold() && r.misoriented_edges == 0 &&
                    r.triangles % 2 == 0 && (long(r.vertices) + long(r.triangles) / 2) % 2 == 0;
    std::vector<char> used(m.vertices.size(), 0);
    for (const auto& t : m.triangles)
        for (auto v : t) used[v] = 1;
    return ok && std::count(used.begin(), used.end(), 0) == 0;
}

void require_printable(const Mesh& m) {
    const MeshReport r = check_mesh(m);
    check_printable(r);
    CHECK(watertight(m));
}

// Every vertex lies in (or on) the cube of samples it belongs to: within the
// sample box, and no farther than a cube diagonal from the surface's crossings.
bool inside_sample_box(const Mesh& m, const Domain& d) {
    for (const Vec3& v : m.vertices)
        for (int a = 0; a < 3; ++a) {
            const int n = a == 0 ? d.nx : a == 1 ? d.ny : d.nz;
            if (v[a] < d.origin[a] + 0.5 * d.h || v[a] > d.origin[a] + (n - 0.5) * d.h) return false;
        }
    return true;
}

}  // namespace

TEST_CASE("dual: sphere of radius 20 h, close to the exact surface, a third of the tetrahedra's triangles") {
    const double h = 0.05, r0 = 20 * h;
    const Vec3 c{1.6 + 0.013, 1.6 - 0.021, 1.6 + 0.007};
    for (Precision precision : {Precision::Double, Precision::Single}) {
        const Grid g = make_grid(64, 64, 64, h, {0, 0, 0}, [&](const Vec3& p, int, int, int) {
            return std::tanh((r0 - dist(p, c)) / (1.5 * h));
        }, precision);
        const Mesh m = extract_dual_isosurface(g.field, g.domain);
        require_printable(m);
        const MeshReport r = check_mesh(m);
        CHECK(r.components == 1);
        CHECK(long(r.vertices) - long(r.triangles) / 2 == 2);  // a sphere: V - E + F = 2
        double sq = 0, sum = 0;
        for (const Vec3& v : m.vertices) {
            sq += std::pow(dist(v, c) - r0, 2);
            sum += dist(v, c) - r0;
        }
        const double rms = std::sqrt(sq / double(m.vertices.size())), mean = sum / double(m.vertices.size());
        MESSAGE("vertex error RMS " << rms / h << " h, mean " << mean / h << " h, " << r.triangles << " triangles");
        // Vertices on the trilinear interpolant of the unfolded field: what remains is
        // mostly its inward bias on a convex surface (the mean of the crossings: 0.012 h).
        CHECK(rms < 0.011 * h);
        const double exact = 4.0 / 3.0 * kPi * r0 * r0 * r0;
        CHECK(std::fabs(r.volume - exact) < 0.005 * exact);

        const MeshReport tet = check_mesh(extract_isosurface(g.field, g.domain, 0.0, Interpolation::PhaseField));
        const double ratio = double(r.triangles) / double(tet.triangles);
        MESSAGE("triangles: dual / tetrahedra = " << ratio);
        CHECK(ratio > 0.25);
        CHECK(ratio < 0.42);
    }
}

TEST_CASE("dual: thin spherical shell gives two sheets enclosing the shell's volume") {
    for (int n : {40, 41}) {
        const double h = 1.0 / n, r0 = 0.3, w = 2.2 * h;
        const Vec3 c{0.5, 0.5, 0.5};
        for (Interpolation mode : {Interpolation::Linear, Interpolation::PhaseField}) {
            const Grid g = make_grid(n, n, n, h, {0, 0, 0}, [&](const Vec3& p, int, int, int) {
                return std::tanh((w - std::fabs(dist(p, c) - r0)) / (2 * h));
            });
            const Mesh m = extract_dual_isosurface(g.field, g.domain, 0.0, mode);
            require_printable(m);
            const MeshReport r = check_mesh(m);
            CHECK(r.components == 2);
            CHECK(r.solids == 1);
            const double exact = 4.0 / 3.0 * kPi * (std::pow(r0 + w, 3) - std::pow(r0 - w, 3));
            CHECK(std::fabs(r.volume - exact) < 0.02 * exact);
            const PointSet in_shell{{0.5, 0.5, 0.5 + r0}, {0.5 + r0, 0.5, 0.5}, {0.5, 0.5 - r0, 0.5}};
            const PointSet out{{0.5, 0.5, 0.5}, {0.5, 0.5, 0.5 + 0.5 * r0}, {0.05, 0.05, 0.05}};
            CHECK(count_points_inside(m, in_shell) == in_shell.size());
            CHECK(count_points_inside(m, out) == 0);
        }
    }
}

TEST_CASE("dual: torus, genus one") {
    const double h = 0.05, big = 0.7, small = 0.25;
    const Grid g = make_grid(40, 40, 20, h, {-1.0, -1.0, -0.5}, [&](const Vec3& p, int, int, int) {
        const double q = std::hypot(p[0], p[1]) - big;
        return std::tanh((small - std::hypot(q, p[2])) / (1.5 * h));
    });
    const Mesh m = extract_dual_isosurface(g.field, g.domain);
    require_printable(m);
    const MeshReport r = check_mesh(m);
    CHECK(r.components == 1);
    CHECK(long(r.vertices) - long(r.triangles) / 2 == 0);  // V - E + F = 0
    const double exact = 2 * kPi * kPi * big * small * small;
    CHECK(std::fabs(r.volume - exact) < 0.025 * exact);  // a tube of radius 5 h: vertices cut its curve
}

TEST_CASE("dual: two blobs touching at a point or a near miss") {
    const double h = 0.1;
    for (double gap : {-0.02, 0.0, 0.003, 0.05}) {
        for (double shift : {0.0, 0.5 * h, 0.37 * h}) {
            const double r0 = 0.6;
            const Vec3 a{1.5 + shift, 1.5, 1.5}, b{1.5 + shift + 2 * r0 + gap, 1.5 + 0.3 * shift, 1.5};
            const Grid g = make_grid(36, 30, 30, h, {0, 0, 0}, [&](const Vec3& p, int, int, int) {
                return std::tanh(std::max(r0 - dist(p, a), r0 - dist(p, b)) / h);
            });
            for (Interpolation mode : {Interpolation::Linear, Interpolation::PhaseField}) {
                const Mesh m = extract_dual_isosurface(g.field, g.domain, 0.0, mode);
                require_printable(m);
                CHECK(inside_sample_box(m, g.domain));
            }
        }
    }
}

TEST_CASE("dual: every sign pattern of a single cube inside a negative border") {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> mag(0.05, 1.0);
    for (int mask = 1; mask < 256; ++mask)
        for (int trial = 0; trial < 8; ++trial)
            for (Interpolation mode : {Interpolation::Linear, Interpolation::PhaseField}) {
                CAPTURE(mask);
                CAPTURE(trial);
                std::array<double, 8> value;
                for (int c = 0; c < 8; ++c) value[c] = (mask >> c & 1 ? 1 : -1) * (trial == 0 ? 0.5 : mag(rng));
                const Grid g = make_grid(4, 4, 4, 1.0, {0, 0, 0}, [&](const Vec3&, int i, int j, int k) {
                    if (i == 0 || j == 0 || k == 0 || i == 3 || j == 3 || k == 3) return -1.0;
                    return value[(i - 1) | (j - 1) << 1 | (k - 1) << 2];
                });
                const Mesh m = extract_dual_isosurface(g.field, g.domain, 0.0, mode);
                CHECK(watertight(m));
                CHECK(check_mesh(m).oriented());
                CHECK(inside_sample_box(m, g.domain));
            }
}

TEST_CASE("dual: random sign patterns, every ambiguous case, stay printable") {
    enum Kind { Uniform, Ternary, Sparse };
    int checked = 0, failed = 0;
    for (Kind kind : {Uniform, Ternary, Sparse})
        for (const auto& n : {std::array<int, 3>{6, 6, 6}, std::array<int, 3>{5, 7, 9}, std::array<int, 3>{4, 4, 12}})
            for (unsigned seed = 1; seed <= 220; ++seed) {
                std::mt19937 rng(seed * 7919 + unsigned(kind) * 131 + unsigned(n[2]));
                std::uniform_real_distribution<double> u(-1.0, 1.0);
                std::uniform_int_distribution<int> t(-1, 1);
                const Grid g = make_grid(n[0], n[1], n[2], 0.5, {0.25, -1.0, 3.0}, [&](const Vec3&, int i, int j, int k) {
                    if (i == 0 || j == 0 || k == 0 || i == n[0] - 1 || j == n[1] - 1 || k == n[2] - 1) return -1.0;
                    if (kind == Ternary) return double(t(rng));
                    if (kind == Sparse) return u(rng) - 0.4;
                    return u(rng);
                }, seed % 2 ? Precision::Double : Precision::Single);
                for (Interpolation mode : {Interpolation::Linear, Interpolation::PhaseField}) {
                    const Mesh m = extract_dual_isosurface(g.field, g.domain, 0.0, mode);
                    ++checked;
                    if (m.triangles.empty()) continue;
                    const MeshReport r = check_mesh(m);
                    if (!watertight(m) || r.misoriented_edges != 0 || !inside_sample_box(m, g.domain)) ++failed;
                }
            }
    CHECK(checked > 3000);
    CHECK(failed == 0);
}

TEST_CASE("dual: a tunnel through an ambiguous face shared by two one-patch cubes") {
    // Cube A (samples k = 1..2) and cube B (k = 2..3) share the face at k = 2, whose
    // inside corners (1,1) and (2,2) are not joined across it; the planes k = 1 and
    // k = 3 are inside, so each cube has one patch holding both of the face's
    // segments.  The dual edge through the face must split in two.
    for (double low : {0.05, 0.2}) {
        const Grid g = make_grid(4, 4, 5, 1.0, {0, 0, 0}, [&](const Vec3&, int i, int j, int k) {
            if (i == 0 || j == 0 || k == 0 || i == 3 || j == 3 || k == 4) return -1.0;
            if (k != 2) return 1.0;
            return (i == j) ? low : -1.0;
        });
        for (Interpolation mode : {Interpolation::Linear, Interpolation::PhaseField}) {
            const Mesh m = extract_dual_isosurface(g.field, g.domain, 0.0, mode);
            require_printable(m);
            // The two extra vertices lie on the face, halfway along its segments.
            int on_face = 0;
            for (const Vec3& v : m.vertices) on_face += std::fabs(v[2] - 2.5) < 1e-12;
            CHECK(on_face == 2);
        }
    }
}

TEST_CASE("dual: a sign change on the grid boundary is an input error; no surface gives no mesh") {
    const Grid g = make_grid(6, 6, 6, 1.0, {0, 0, 0}, [](const Vec3&, int i, int j, int) {
        return i == 0 && j == 2 ? 1.0 : -1.0;
    });
    CHECK_THROWS_AS(extract_dual_isosurface(g.field, g.domain), InputError);
    const Grid none = make_grid(5, 5, 5, 1.0, {0, 0, 0}, [](const Vec3&, int, int, int) { return -1.0; });
    CHECK(extract_dual_isosurface(none.field, none.domain).triangles.empty());
    const Grid flat = make_grid(1, 5, 5, 1.0, {0, 0, 0}, [](const Vec3&, int, int, int) { return 1.0; });
    CHECK(extract_dual_isosurface(flat.field, flat.domain).triangles.empty());
    Grid bad = none;
    bad.domain.nx = 4;
    CHECK_THROWS_AS(extract_dual_isosurface(bad.field, bad.domain), ParameterError);
}

TEST_CASE("dual: a large field (the parallel path) is printable and deterministic") {
    // Enough samples for the parallel path; two passes must agree bit for bit.
    const double h = 0.02;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-0.3, 0.3);
    std::vector<double> bump(97);
    for (double& b : bump) b = u(rng);
    const Grid g = make_grid(96, 90, 84, h, {0, 0, 0}, [&](const Vec3& p, int i, int j, int k) {
        if (i == 0 || j == 0 || k == 0 || i == 95 || j == 89 || k == 83) return -1.0;
        const double s = std::sin(9 * p[0]) * std::sin(8 * p[1]) * std::sin(7 * p[2]);
        return std::tanh((s + 0.2 * bump[(i * 31 + j * 17 + k * 7) % 97]) * 4);
    });
    const Mesh a = extract_dual_isosurface(g.field, g.domain);
    const Mesh b = extract_dual_isosurface(g.field, g.domain);
    require_printable(a);
    CHECK(a.triangles == b.triangles);
    CHECK(a.vertices == b.vertices);
}

// The library's OpenMP runtime (linked with it).
extern "C" void omp_set_num_threads(int);
extern "C" int omp_get_max_threads();

TEST_CASE("dual: the same mesh on 1 and 2 threads, from doubles and from floats") {
    // Rows of 150 samples: two whole 64-bit words of signs and a partial one.
    const double h = 0.02;
    const auto value = [](const Vec3& p, int i, int j, int k) {
        if (i == 0 || j == 0 || k == 0 || i == 149 || j == 69 || k == 59) return -1.0;
        const double s = std::sin(11 * p[0]) * std::sin(9 * p[1]) * std::sin(13 * p[2]) + 0.1 * std::cos(29 * p[0]);
        return double(float(std::tanh(4 * s)));  // float-exact, so both precisions hold the same values
    };
    const Grid d = make_grid(150, 70, 60, h, {0, 0, 0}, value);
    const Grid f = make_grid(150, 70, 60, h, {0, 0, 0}, value, Precision::Single);
    const int before = omp_get_max_threads();
    omp_set_num_threads(1);
    const Mesh one = extract_dual_isosurface(d.field, d.domain);
    omp_set_num_threads(2);
    const Mesh two = extract_dual_isosurface(d.field, d.domain);
    const Mesh single = extract_dual_isosurface(f.field, f.domain);
    omp_set_num_threads(before);
    require_printable(one);
    CHECK(one.vertices.size() > 1000);
    CHECK(one.triangles == two.triangles);
    CHECK(one.vertices == two.vertices);
    CHECK(single.triangles == one.triangles);
    CHECK(single.vertices == one.vertices);
}

// The dual mesh in pieces (what a tiled run's tiles extract) welded by the whole grid's
// keys: the whole extraction's vertices and triangles, in its order, bit for bit.
namespace {
// Random samples in (-1, 1) inside a -1 border, voxel 0.5: every ambiguous face and tunnel.
Grid random_signs(unsigned seed, const std::array<int, 3>& n, Precision precision) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    return make_grid(n[0], n[1], n[2], 0.5, {0.25, -1.0, 3.0}, [&](const Vec3&, int i, int j, int k) {
        if (i == 0 || j == 0 || k == 0 || i == n[0] - 1 || j == n[1] - 1 || k == n[2] - 1) return -1.0;
        return u(rng);
    }, precision);
}
}  // namespace

TEST_CASE("dual: pieces of any size and margin, and their slices of planes, weld into the whole grid's mesh, bit for bit") {
    const auto same = [](const Mesh& a, const Mesh& b) { return a.vertices == b.vertices && a.triangles == b.triangles; };
    // A smooth field across many pieces, rows of 150 samples (partial 64-bit words), floats.
    const double h = 0.02;
    const Grid smooth = make_grid(150, 70, 61, h, {0.1, -0.2, 0.3}, [](const Vec3& p, int i, int j, int k) {
        if (i == 0 || j == 0 || k == 0 || i == 149 || j == 69 || k == 60) return -1.0;
        return std::tanh(4 * (std::sin(11 * p[0]) * std::sin(9 * p[1]) * std::sin(13 * p[2]) + 0.1 * std::cos(29 * p[0])));
    }, Precision::Single);
    const Mesh whole = extract_dual_isosurface(smooth.field, smooth.domain);
    REQUIRE(whole.triangles.size() > 10000);
    for (int cells : {8, 13, 64, 200})
        for (int margin : {0, 3}) {
            CAPTURE(cells);
            CAPTURE(margin);
            CHECK(same(detail::extract_in_pieces(smooth.field, smooth.domain, cells, margin), whole));
        }
    // Random signs: every ambiguous face and tunnel, many on the pieces' faces.
    int compared = 0, tunnels = 0;
    for (unsigned seed = 1; seed <= 12; ++seed) {
        const Grid g = random_signs(seed, {21, 18, 19}, seed % 2 ? Precision::Double : Precision::Single);
        for (Interpolation mode : {Interpolation::Linear, Interpolation::PhaseField}) {
            const Mesh m = extract_dual_isosurface(g.field, g.domain, 0.0, mode);
            for (const Vec3& v : m.vertices)  // tunnel vertices lie on a face between samples
                for (int a = 0; a < 3; ++a) tunnels += std::fabs(std::fmod(v[a] - g.domain.origin[a] - 0.25, 0.5)) < 1e-12;
            for (int cells : {1, 3, 8})
                for (int margin : {0, 2}) {
                    if (cells == 1 && margin) continue;  // every sample its own piece: once is enough
                    CAPTURE(seed);
                    CAPTURE(cells);
                    CHECK(same(detail::extract_in_pieces(g.field, g.domain, cells, margin, 0.0, mode), m));
                    ++compared;
                }
        }
    }
    CHECK(compared == 120);
    CHECK(tunnels > 0);
    // Pieces cut in slices of planes (as a run over processes cuts its tiles' parts) weld
    // into the same mesh; each vertex owned by one slice.
    for (unsigned seed = 1; seed <= 4; ++seed) {
        const Grid g = random_signs(seed, {21, 18, 23}, Precision::Double);
        const Mesh m = extract_dual_isosurface(g.field, g.domain, 0.0, Interpolation::PhaseField);
        const std::array<int, 3> n{21, 18, 23};
        for (int thickness : {1, 3, 8})
            for (int margin : {0, 2}) {
                CAPTURE(seed);
                CAPTURE(thickness);
                CAPTURE(margin);
                std::vector<detail::MeshPiece> slices;
                for (int k = 0; k < n[2]; k += 8)
                    for (int i = 0; i < n[0]; i += 8) {
                        const std::array<int, 3> lo{i, 0, k}, hi{std::min(n[0], i + 8), n[1], std::min(n[2], k + 8)};
                        std::array<int, 3> box_lo, box_hi;
                        detail::field_box(n, lo, hi, margin, box_lo, box_hi);
                        for (detail::MeshPiece& p : detail::split_planes(
                                 detail::extract_dual_piece(detail::field_part(g.field, box_lo, box_hi), g.domain,
                                                            detail::DualRegion::around(n, lo, hi, margin, box_lo, box_hi),
                                                            0.0, Interpolation::PhaseField),
                                 thickness))
                            slices.push_back(std::move(p));
                    }
                std::uint64_t counted = 0;  // each vertex owned by one slice
                for (const detail::MeshPiece& p : slices)
                    for (std::uint8_t owned : p.vertex_owned) counted += owned;
                CHECK(counted == m.vertices.size());
                CHECK(same(detail::weld_pieces(slices), m));
            }
    }
    // A sign change on the whole grid's boundary is still found in a piece.
    const Grid edge = make_grid(20, 20, 20, 1.0, {0, 0, 0}, [](const Vec3&, int i, int j, int) {
        return i == 19 && j == 12 ? 1.0 : -1.0;
    });
    CHECK_THROWS_AS(detail::extract_in_pieces(edge.field, edge.domain, 8, 0), InputError);
}
