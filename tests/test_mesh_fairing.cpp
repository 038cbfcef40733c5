// fair_mesh: Taubin smoothing damps vertex-scale noise and leaves the shape where it was.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>

#include "mesh_fields.hpp"
#include "snvr/error.hpp"
#include "snvr/quality.hpp"
#include "snvr/shell.hpp"
#include "snvr/mesh.hpp"
#include "mesh/vertex_lists.hpp"

using namespace snvr;
using namespace snvr::testing;

namespace {

constexpr double kH = 0.05, kR = 0.5;  // a sphere 10 cells in radius
const Vec3 kCentre{0.011, -0.007, 0.003};

Mesh sphere() {
    const int n = int(std::ceil(2 * (kR + 3 * kH) / kH)) + 2;
    const Vec3 origin{kCentre[0] - n * kH / 2, kCentre[1] - n * kH / 2, kCentre[2] - n * kH / 2};
    const Grid g = make_grid(n, n, n, kH, origin,
                             [](const Vec3& p, int, int, int) { return std::tanh((kR - dist(p, kCentre)) / (1.5 * kH)); });
    return extract_dual_isosurface(g.field, g.domain);
}

// Every vertex moved radially by up to +-amplitude (a fixed hash, not a random draw).
void roughen(Mesh& m, double amplitude) {
    for (std::size_t v = 0; v < m.vertices.size(); ++v) {
        const std::uint32_t x = std::uint32_t(v) * 2654435761u;
        const double u = double(x >> 8) / double(1u << 24) * 2 - 1;
        Vec3& p = m.vertices[v];
        const double r = dist(p, kCentre);
        for (int d = 0; d < 3; ++d) p[d] = kCentre[d] + (p[d] - kCentre[d]) * (r + amplitude * u) / r;
    }
}

struct Radii {
    double mean = 0, rms_deviation = 0;
};
Radii radii(const Mesh& m) {
    Radii r;
    for (const Vec3& p : m.vertices) r.mean += dist(p, kCentre);
    r.mean /= double(m.vertices.size());
    for (const Vec3& p : m.vertices) r.rms_deviation += std::pow(dist(p, kCentre) - r.mean, 2);
    r.rms_deviation = std::sqrt(r.rms_deviation / double(m.vertices.size()));
    return r;
}

}  // namespace

TEST_CASE("vertex noise is damped, the sphere keeps its radius, the triangles stay") {
    Mesh m = sphere();
    roughen(m, 0.3 * kH);
    const Mesh rough = m;
    const Radii before = radii(m);
    fair_mesh(m);
    const Radii after = radii(m);
    MESSAGE("radius " << before.mean << " -> " << after.mean << ", deviation " << before.rms_deviation / kH << " -> "
                      << after.rms_deviation / kH << " h");
    // White noise has energy at every scale, the filter damps the vertex scale: about half goes.
    CHECK(after.rms_deviation < 0.6 * before.rms_deviation);
    // No shrinking: two plain umbrella steps of 0.5 would take about 0.05 h off this radius.
    CHECK(std::abs(after.mean - before.mean) < 0.01 * kH);
    CHECK(m.triangles == rough.triangles);
    check_printable(check_mesh(m));
}

TEST_CASE("a smooth sphere stays within a hundredth of a voxel of where it was") {
    Mesh m = sphere();
    const Radii before = radii(m);
    fair_mesh(m);
    MESSAGE("radius " << before.mean << " -> " << radii(m).mean << ", deviation " << before.rms_deviation / kH << " -> "
                      << radii(m).rms_deviation / kH << " h");
    CHECK(std::abs(radii(m).mean - before.mean) < 0.01 * kH);
    // The vertices slide along the surface a little; the sphere stays as round.
    CHECK(radii(m).rms_deviation < 0.01 * kH);
}

TEST_CASE("no passes, or no triangles: nothing changes; bad settings are named") {
    Mesh m = sphere();
    roughen(m, 0.3 * kH);
    const Mesh rough = m;
    MeshFairing none;
    none.passes = 0;
    fair_mesh(m, none);
    CHECK(m.vertices == rough.vertices);
    Mesh empty;
    fair_mesh(empty);
    CHECK(empty.vertices.empty());

    MeshFairing bad;
    bad.passes = -1;
    CHECK_THROWS_AS(fair_mesh(m, bad), ParameterError);
    bad = {};
    bad.lambda = 1;
    CHECK_THROWS_WITH_AS(fair_mesh(m, bad), doctest::Contains("lambda"), ParameterError);
    bad = {};
    bad.pass_band = std::nan("");
    CHECK_THROWS_WITH_AS(fair_mesh(m, bad), doctest::Contains("pass band"), ParameterError);
    CHECK(m.vertices == rough.vertices);
}

// The library's OpenMP runtime (linked with it).
extern "C" void omp_set_num_threads(int);
extern "C" int omp_get_max_threads();

TEST_CASE("fairing with prebuilt rings (as shell_mesh runs it) and on 1 or 2 threads moves the same") {
    Mesh m = sphere();
    roughen(m, 0.3 * kH);
    Mesh a = m, b = m, c = m;
    const int before = omp_get_max_threads();
    omp_set_num_threads(1);
    fair_mesh(a);
    omp_set_num_threads(2);
    fair_mesh(b);
    detail::fair_mesh(c, MeshFairing{}, detail::rings(c));
    omp_set_num_threads(before);
    CHECK(a.vertices == b.vertices);
    CHECK(c.vertices == a.vertices);
    CHECK(a.vertices != m.vertices);
}
