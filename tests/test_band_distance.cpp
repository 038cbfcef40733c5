// The band distance and the brick machinery, each against a plain dense computation.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>

#include "solver/backend.hpp"
#include "geometry/band_distance.hpp"
#include "solver/hierarchy.hpp"
#include "solver/multigrid.hpp"
#include "solver/problem.hpp"
#include "openmp/openmp_backend.hpp"
#include "snvr/point_cloud.hpp"

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
        const PointCloud cloud(points);
        points = cloud.to_point_set();  // as the cloud holds them (float)
        const Band band{0.05, 0.04};
        BandDistance<double> bd = band_distance<double>(detail::tree_of(cloud), d, band);
        classify_band(bd, d, band);
        const std::vector<double> distance = bd.dense(d);
        // The layout from the per-brick distance is the one the dense distance gives.
        const BrickLayout from_bricks = make_layout(d, bd.brick_mask, bd.inside_bricks);
        const BrickLayout from_dense = make_layout<double>(d, bd.brick_mask, distance.data(), band.offset);
        CHECK(from_bricks.grid(0).slot == from_dense.grid(0).slot);
        std::size_t in_band = 0, mismatched = 0;
        double worst = 0;
        for (int k = 0; k < d.nz; ++k)
            for (int j = 0; j < d.ny; ++j)
                for (int i = 0; i < d.nx; ++i) {
                    const Vec3 c = d.cell_center(i, j, k);
                    double best = 1e300;
                    for (const Vec3& p : points)
                        best = std::min(best, std::hypot(c[0] - p[0], c[1] - p[1], c[2] - p[2]));
                    const double got = distance[d.index(i, j, k)];
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

namespace {

// Checks band_distance against the nearest point found by trying every point (as the
// cloud holds them), with the squared distance written as the tree's queries evaluate it
// ((x^2 + y^2) + z^2, x = q - p per axis; ISO C++ mode, so no fused multiply-add), so
// the values must match bit for bit; only cells within a hair of the band radius may go
// either way.
// `distinct`, when given, stands for the cloud in the brute force (its distinct points:
// copies of one point change no distance).
template <class Real>
void check_exact(const PointSet& input, const Domain& d, const Band& band, const char* what,
                 const PointSet* distinct = nullptr) {
    const std::string label = what;
    CAPTURE(label);
    const PointCloud cloud(input);
    const PointSet points = distinct ? PointCloud(*distinct).to_point_set() : cloud.to_point_set();
    const BandDistance<Real> bd = band_distance<Real>(detail::tree_of(cloud), d, band);
    const std::vector<Real> distance = bd.dense(d);
    REQUIRE(distance.size() == d.cells());
    const Hierarchy shapes = make_levels(Domain{d.origin, d.h, d.nx, d.ny, d.nz, 1});
    const Level& lv = shapes.levels[0];
    std::vector<std::uint8_t> near(lv.brick_count(), 0);
    std::size_t cells_near = 0;
    for (std::size_t t = 0; t < bd.near_bricks.size(); ++t) {
        const std::uint32_t b = bd.near_bricks[t];
        REQUIRE(b < near.size());
        if (t > 0) CHECK(bd.near_bricks[t - 1] < b);  // ascending, no repeats
        near[b] = 1;
        const CellRange r = lv.range(b);
        cells_near += std::size_t(r.i1 - r.i0) * std::size_t(r.j1 - r.j0) * std::size_t(r.k1 - r.k0);
    }
    CHECK(bd.queried_cells == cells_near);

    const double L = d.length_scale();
    const double reach = (band.offset + band.cut) * L;
    const Real far = Real(band.offset + 2 * band.cut);
    std::size_t inside = 0, wrong = 0, not_far = 0, missing = 0;
    for (std::uint32_t b = 0; b < lv.brick_count(); ++b) {
        const CellRange r = lv.range(b);
        for (int k = r.k0; k < r.k1; ++k)
            for (int j = r.j0; j < r.j1; ++j)
                for (int i = r.i0; i < r.i1; ++i) {
                    const Vec3 q = d.cell_center(i, j, k);
                    double best = std::numeric_limits<double>::infinity();
                    for (const Vec3& p : points) {
                        const double x = q[0] - p[0], y = q[1] - p[1], z = q[2] - p[2];
                        best = std::min(best, x * x + y * y + z * z);
                    }
                    const double nearest = std::sqrt(best);
                    const Real exact = Real(nearest / L), got = distance[d.index(i, j, k)];
                    if (nearest < reach * (1 - 1e-7)) {
                        ++inside;
                        missing += !near[b];
                        wrong += got != exact;
                    } else if (nearest > reach * (1 + 1e-7)) {
                        not_far += got != far;
                    } else {
                        wrong += got != exact && got != far;
                    }
                }
    }
    std::printf("%-44s %s: %zu cells within reach\n", what, sizeof(Real) == 4 ? "float " : "double", inside);
    CHECK(inside > 0);
    CHECK(missing == 0);
    CHECK(wrong == 0);
    CHECK(not_far == 0);
}

template <class Real>
void check_clouds() {
    std::mt19937 rng(2024);
    std::uniform_real_distribution<double> unit(0, 1);
    // 37 x 21 x 50 cells: bricks and 4^3 blocks cut at every far edge.
    Domain d;
    d.origin = {0.1, -0.2, 0.3};
    d.h = 0.01;
    d.nx = 37, d.ny = 21, d.nz = 50;
    const double L = d.length_scale();
    auto spot = [&](double spill) {  // uniform over the grid's box, widened by `spill` of it
        Vec3 p;
        const int n[3] = {d.nx, d.ny, d.nz};
        for (int a = 0; a < 3; ++a) p[a] = d.origin[a] + (unit(rng) * (1 + 2 * spill) - spill) * n[a] * d.h;
        return p;
    };
    const Band band{0.03 / L, 0.02 / L};  // reach 5 cells

    PointSet scattered;
    for (int n = 0; n < 400; ++n) scattered.push_back(spot(0.15));  // some beyond the grid
    for (int n = 0; n < 60; ++n) scattered.push_back(scattered[rng() % scattered.size()]);  // duplicates
    check_exact<Real>(scattered, d, band, "scattered, spilling out, with duplicates");

    PointSet clusters;
    for (int c = 0; c < 8; ++c) {
        const Vec3 m = spot(0.05);
        std::normal_distribution<double> jitter(0, 1e-5);
        for (int n = 0; n < 150; ++n) clusters.push_back({m[0] + jitter(rng), m[1] + jitter(rng), m[2] + jitter(rng)});
        for (int n = 0; n < 30; ++n) clusters.push_back(m);
    }
    check_exact<Real>(clusters, d, band, "tight clusters of near and exact duplicates");

    check_exact<Real>({spot(0)}, d, band, "a single point");
    check_exact<Real>({Vec3{0.1 - 0.02, -0.2 + 0.1, 0.3 + 0.25}}, d, band, "a single point beyond the grid");
    check_exact<Real>({d.cell_center(36, 20, 49), d.cell_center(0, 0, 0)}, d, band, "points in the corner cells");

    // Points exactly on cell centres: those cells are at distance 0.
    PointSet centred = scattered;
    for (int n = 0; n < 40; ++n) centred.push_back(d.cell_center(int(rng() % 37), int(rng() % 21), int(rng() % 50)));
    check_exact<Real>(centred, d, band, "points on cell centres");

    check_exact<Real>(scattered, d, Band{0.2 / L, 0.05 / L}, "a band many bricks wide");
    check_exact<Real>({spot(0), spot(0.1)}, d, Band{0.2 / L, 0.05 / L}, "two points, a band many bricks wide");
    // Just past multiples of 4 and 8 cells, with reaches just past 8 and 16 cells: where
    // coarse bounds on whole blocks of cells or points (bricks, buckets) cut it closest.
    for (double reach : {8.8, 16.7}) {
        const PointSet edgy = {{d.origin[0] + 16.1 * d.h, d.origin[1] + 8.1 * d.h, d.origin[2] + 24.1 * d.h},
                               {d.origin[0] + 7.9 * d.h, d.origin[1] + 7.9 * d.h, d.origin[2] + 40.02 * d.h},
                               {d.origin[0] + 32.1 * d.h, d.origin[1] + 16.1 * d.h, d.origin[2] + 8.05 * d.h},
                               {d.origin[0] + 23.9 * d.h, d.origin[1] + 0.1 * d.h, d.origin[2] + 31.9 * d.h}};
        check_exact<Real>(edgy, d, Band{3 * d.h / L, (reach - 3) * d.h / L}, "points just past block edges");
    }

    // Far from the origin: the rounding slack must scale with the coordinates.
    Domain shifted = d;
    shifted.origin = {1e6 + 0.1, -2e6 - 0.2, 5e5 + 0.3};
    PointSet moved = scattered;
    for (Vec3& p : moved)
        for (int a = 0; a < 3; ++a) p[a] += shifted.origin[a] - d.origin[a];
    check_exact<Real>(moved, shifted, band, "a million units from the origin");

    // A cloud far denser than the cells (two sheets, about 60 points per cell each):
    // bricks there take the per-cell kd-tree path.
    Domain coarse;
    coarse.origin = {0, 0, 0};
    coarse.h = 1.0 / 16;
    coarse.nx = coarse.ny = coarse.nz = 16;
    PointSet sheets;
    for (double z : {0.43, 0.57})
        for (int n = 0; n < 16 * 16 * 60; ++n) sheets.push_back({unit(rng), unit(rng), z});
    for (int n = 0; n < 6; ++n) sheets.push_back(coarse.cell_center(3 + 2 * n, 5 + n, 0));  // alone on cell centres
    check_exact<Real>(sheets, coarse, Band{0.1, 0.15}, "two dense sheets");

    // The same density on the odd grid (packets cut by the grid's far edges), tilted.
    PointSet tilted;
    for (int n = 0; n < 40000; ++n) {  // some 50 a cell of the sheet
        const double u = unit(rng), v = unit(rng);
        tilted.push_back({d.origin[0] + u * 0.37, d.origin[1] + v * 0.21, d.origin[2] + 0.1 + 0.3 * u + 0.05 * v});
    }
    check_exact<Real>(tilted, d, band, "a dense tilted sheet across the odd grid");

    // A million copies of one point beside a few others, and every point in one cell.
    PointSet copies(1000000, d.cell_center(20, 10, 25));
    PointSet few = {d.cell_center(20, 10, 25), spot(0), spot(0), spot(0.1)};
    copies.insert(copies.end(), few.begin() + 1, few.end());
    check_exact<Real>(copies, d, band, "a million copies of one point and three others", &few);
    PointSet one_cell;
    const Vec3 c = d.cell_center(5, 17, 44);
    for (int n = 0; n < 5000; ++n)
        one_cell.push_back({c[0] + 0.4 * d.h * (unit(rng) - 0.5), c[1] + 0.4 * d.h * (unit(rng) - 0.5),
                            c[2] + 0.4 * d.h * (unit(rng) - 0.5)});
    check_exact<Real>(one_cell, d, band, "5000 points in one cell");
}

}  // namespace

TEST_CASE("band distance is the exact nearest distance on awkward clouds and grids") {
    check_clouds<double>();
    check_clouds<float>();
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
    backend->init_phase(pack_level0(layout, dist.data()), l, 1 / (std::sqrt(2.0) * xi), cut);
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
