// Field in shared bricks: dense values in and out unchanged, uniform bricks stored
// once, malformed tables refused, meshes the same however the bricks are shared, and a
// reconstruction's band field equal to the dense download of the solver's phi.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "snvr/error.hpp"
#include "snvr/mesh_io.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/mesh.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/shapes.hpp"
#include "solver/session.hpp"

using namespace snvr;

namespace {

std::vector<double> random_values(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<double> v(n);
    for (double& x : v) x = u(rng);
    return v;
}

// The same cells with every brick stored on its own (no sharing).
template <class Real>
Field unshared(const Field& f, const std::vector<Real>& stored) {
    std::vector<std::uint32_t> table(f.brick_table().size());
    std::vector<Real> values;
    for (std::size_t b = 0; b < table.size(); ++b) {
        const std::size_t from = std::size_t(f.brick_table()[b]) * Field::kBrickCells;
        values.insert(values.end(), stored.begin() + std::ptrdiff_t(from), stored.begin() + std::ptrdiff_t(from + Field::kBrickCells));
        table[b] = std::uint32_t(b);
    }
    return Field::from_bricks(f.nx, f.ny, f.nz, std::move(table), std::move(values));
}
Field unshared(const Field& f) {
    return f.precision == Precision::Double ? unshared(f, f.stored_f64()) : unshared(f, f.stored_f32());
}

// A ball of radius r (cells) in an nx x ny x nz grid: a tanh profile, +-1 far from it.
std::vector<double> ball(int nx, int ny, int nz, double r) {
    std::vector<double> v(std::size_t(nx) * std::size_t(ny) * std::size_t(nz));
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                const double x = i - nx / 2.0, y = j - ny / 2.0, z = k - nz / 2.0;
                const double s = r - std::sqrt(x * x + y * y + z * z);
                v[std::size_t(i) + std::size_t(nx) * (std::size_t(j) + std::size_t(ny) * std::size_t(k))] =
                    std::abs(s) > 4 ? (s > 0 ? 1.0 : -1.0) : std::tanh(s);
            }
    return v;
}

Domain domain_of(const Field& f) {
    Domain d;
    d.nx = f.nx, d.ny = f.ny, d.nz = f.nz;
    d.h = 0.1;
    return d;
}

}  // namespace

TEST_CASE("dense values go into bricks and come back unchanged, in both precisions") {
    const int nx = 13, ny = 9, nz = 17;  // partial bricks on every axis
    const std::vector<double> v = random_values(std::size_t(nx) * ny * nz, 7);
    const Field fd = Field::from_dense(nx, ny, nz, v);
    const Field ff = Field::from_dense(nx, ny, nz, std::vector<float>(v.begin(), v.end()));
    CHECK(fd.brick_count() == 2 * 2 * 3);
    CHECK(fd.stored_bricks() == fd.brick_count());  // nothing uniform here
    CHECK(fd.to_dense() == v);
    CHECK_NOTHROW(fd.validate(""));
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                const std::size_t n = std::size_t(i) + std::size_t(nx) * (std::size_t(j) + std::size_t(ny) * std::size_t(k));
                REQUIRE(fd.at(i, j, k) == v[n]);
                REQUIRE(fd[n] == v[n]);
                REQUIRE(ff.at(i, j, k) == double(float(v[n])));
            }
    CHECK(ff.precision == Precision::Single);
    // Asked for single precision from doubles: rounded once.
    const Field fs = Field::from_dense(nx, ny, nz, v, Precision::Single);
    CHECK(fs.to_dense() == ff.to_dense());
}

TEST_CASE("uniform bricks are stored once") {
    const int n = 64;
    const std::vector<double> v = ball(n, n, n, 10);
    const Field f = Field::from_dense(n, n, n, v);
    CHECK(f.to_dense() == v);
    CHECK(f.stored_bricks() < f.brick_count() / 4);
    const Field all_minus = Field::from_dense(20, 20, 20, std::vector<double>(8000, -1.0));
    CHECK(all_minus.stored_bricks() == 1);
    CHECK(all_minus.bytes() < 8000 * sizeof(double) / 2);
}

TEST_CASE("malformed fields and counts are refused with the reason") {
    CHECK_THROWS_AS(Field::from_dense(4, 4, 4, std::vector<double>(63)), ParameterError);
    CHECK_THROWS_AS(Field::from_dense(-1, 4, 4, std::vector<double>()), ParameterError);
    const Field good = Field::from_dense(9, 9, 9, random_values(729, 3));
    std::vector<std::uint32_t> table = good.brick_table();
    table.pop_back();
    CHECK_THROWS_WITH_AS(Field::from_bricks(9, 9, 9, table, good.stored_f64()), doctest::Contains("brick entries"),
                         InputError);
    std::vector<double> values = good.stored_f64();
    values.pop_back();
    CHECK_THROWS_WITH_AS(Field::from_bricks(9, 9, 9, good.brick_table(), values), doctest::Contains("whole bricks"),
                         InputError);
    table = good.brick_table();
    table[3] = 99;
    CHECK_THROWS_WITH_AS(Field::from_bricks(9, 9, 9, table, good.stored_f64()), doctest::Contains("stored brick 99"),
                         InputError);
    // A shape changed after the bricks were made.
    Field bad = good;
    bad.nx = 17;
    CHECK_THROWS_WITH_AS(bad.validate("x: "), doctest::Contains("brick entries"), InputError);
    CHECK_THROWS_AS(write_field(bad, domain_of(bad), "never_written.nrrd"), InputError);
}

TEST_CASE("meshes do not depend on how the bricks are shared") {
    for (const Precision p : {Precision::Double, Precision::Single}) {
        const Field shared = Field::from_dense(50, 41, 37, ball(50, 41, 37, 12.3), p);
        const Field own = unshared(shared);
        REQUIRE(shared.stored_bricks() < own.stored_bricks());
        const Domain d = domain_of(shared);
        const Mesh a = extract_dual_isosurface(shared, d), b = extract_dual_isosurface(own, d);
        CHECK(!a.triangles.empty());
        CHECK(a.vertices == b.vertices);
        CHECK(a.triangles == b.triangles);
        const Mesh c = extract_isosurface(shared, d), e = extract_isosurface(own, d);
        CHECK(!c.triangles.empty());
        CHECK(c.vertices == e.vertices);
        CHECK(c.triangles == e.triangles);
    }
}

TEST_CASE("a reconstruction's band field holds the solver's phi cell for cell") {
    Parameters p;
    p.device = "openmp";
    p.resolution = 48;
    const PointSet points = shapes::sphere({0.5, 0.5, 0.5}, 0.3, 1.0 / 64);
    SolverSession<float> session(PointCloud(points), p);
    while (session.steps_done() < session.problem().steps) session.step();
    const Domain d = session.domain();
    std::vector<float> dense(d.cells());
    session.field(dense.data());
    const Field f = session.take_field();
    REQUIRE(f.nx == d.nx);
    CHECK(f.stored_bricks() < f.brick_count());  // only the band is stored
    const std::vector<double> out = f.to_dense();
    std::size_t differ = 0;
    for (std::size_t n = 0; n < dense.size(); ++n) differ += out[n] != double(dense[n]);
    CHECK(differ == 0);
    // And reconstruct() returns the same.
    p.precision = Precision::Single;
    CHECK(reconstruct(points, p).phi.to_dense() == out);
}
