// The band distance and the brick machinery, each against a plain dense computation.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "solver/backend.hpp"
#include "geometry/band_distance.hpp"
#include "solver/hierarchy.hpp"
#include "solver/multigrid.hpp"
#include "solver/problem.hpp"
#include "openmp/openmp_backend.hpp"
#include "geometry/point_index.hpp"

using namespace snvr;

namespace {

Domain box_domain(int nx, int ny, int nz, int levels) {
    Domain d;
    d.nx = nx, d.ny = ny, d.nz = nz, d.levels = levels;
    d.h = 1.0 / std::max({nx, ny, nz});
    return d;
}

}  // namespace

TEST_CASE("band distance equals brute force wherever it is inside the band") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.2, 0.8);
    for (int count : {1, 5, 200, 3000}) {
        PointSet points(static_cast<std::size_t>(count));
        for (Vec3& p : points) p = {u(rng), u(rng), u(rng) * 0.7};
        const Domain d = box_domain(24, 30, 20, 1);
        const PointIndex index(points);
        const Band band{0.05, 0.04};
        BandDistance<double> bd = band_distance<double>(points, index, d, band);
        classify_band(bd, d, band);
        std::size_t in_band = 0, mismatched = 0;
        double worst = 0;
        for (int k = 0; k < d.nz; ++k)
            for (int j = 0; j < d.ny; ++j)
                for (int i = 0; i < d.nx; ++i) {
                    const Vec3 c = d.cell_center(i, j, k);
                    double best = 1e300;
                    for (const Vec3& p : points)
                        best = std::min(best, std::hypot(c[0] - p[0], c[1] - p[1], c[2] - p[2]));
                    const double got = bd.distance[d.index(i, j, k)];
                    const bool inside = std::abs(band.offset - best) <= band.cut;
                    in_band += inside;
                    if (inside) worst = std::max(worst, std::abs(got - best));
                    else mismatched += std::abs(band.offset - got) <= band.cut;  // must be classified outside too
                }
        std::printf("%d points: %zu band cells, max |error| %.3e\n", count, in_band, worst);
        CHECK(worst < 1e-15);
        CHECK(mismatched == 0);
        CHECK(bd.active_cells == in_band);
    }
}

TEST_CASE("solved fields satisfy the dense equation on odd grids with partial and constant bricks") {
    // 20 x 28 x 36: partial bricks on every axis; a sphere's band leaves constant bricks
    // inside (+1) and outside (-1).
    const Domain d = box_domain(20, 28, 36, 3);
    const double l = 0.08, xi = 0.01, cut = 12 * xi, dt = 2e-4;
    std::vector<double> dist(d.cells());
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) {
                const Vec3 c = d.cell_center(i, j, k);
                dist[d.index(i, j, k)] = std::abs(std::hypot(c[0] - 0.3, c[1] - 0.45, c[2] - 0.5) - 0.25);
            }
    Hierarchy hier = make_levels(d);
    std::vector<std::uint8_t> mask(hier.levels[0].brick_count(), 0);
    for (std::uint32_t b = 0; b < mask.size(); ++b) {
        const CellRange r = hier.levels[0].range(b);
        for (int k = r.k0; k < r.k1; ++k)
            for (int j = r.j0; j < r.j1; ++j)
                for (int i = r.i0; i < r.i1; ++i) mask[b] |= std::abs(l - dist[d.index(i, j, k)]) <= cut;
    }
    set_active_bricks(hier, mask);
    REQUIRE(hier.levels[0].bricks.size() < mask.size());  // some constant bricks

    // Coarse levels 10x14x18 and 5x7x9: the coarsest by sweeps, or the finest small one by its inverse.
    for (bool exact : {false, true}) {
    const BrickLayout layout = make_layout<double>(d, mask, dist.data(), l);
    auto backend = make_openmp_backend<double>();
    backend->setup(layout);
    backend->init_phase(pack_level0(layout, dist.data()).data(), l, 1 / (std::sqrt(2.0) * xi), cut);
    MultigridSettings s = multigrid_settings(Parameters{}, dt);
    s.tol = 1e-13;
    s.exact_coarse = exact;
    s.exact_level = prepare_coarse_levels(*backend, hier, s);
    CHECK((s.exact_level > 0) == exact);
    std::vector<double> rhs(d.cells()), phi(d.cells());
    backend->download(0, FieldKind::phi, rhs.data());
    const LinearSolveStats st = solve_linear(*backend, hier, s);
    backend->download(0, FieldKind::phi, phi.data());
    CHECK(st.converged);

    // r = rhs - (phi - dt g Lap phi), mirror boundary, plain loops on the flat arrays.
    const double c = dt_over_h2(dt, hier.levels[0]);
    double worst = 0;
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) {
                const std::size_t n = d.index(i, j, k);
                const double p0 = std::abs(l - dist[n]) > cut ? 1.0 : std::tanh((l - dist[n]) / (std::sqrt(2.0) * xi));
                const double g = std::abs(l - dist[n]) > cut ? 0.0 : 1 - p0 * p0;
                double lap = 0;
                const int size[3] = {d.nx, d.ny, d.nz};
                for (int a = 0; a < 3; ++a)
                    for (int side : {-1, 1}) {
                        int q[3] = {i, j, k};
                        q[a] += side;
                        if (q[a] >= 0 && q[a] < size[a]) lap += phi[d.index(q[0], q[1], q[2])] - phi[n];
                    }
                worst = std::max(worst, std::abs(rhs[n] - (phi[n] - c * g * lap)));
            }
    std::printf("dense residual of the multigrid solution (coarsest %s): %.3e after %d V-cycles\n",
                exact ? "exact" : "by sweeps", worst, st.cycles);
    CHECK(worst < 1e-11);
    }
}
