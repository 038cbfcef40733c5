#include "geometry/band_distance.hpp"

#include <algorithm>
#include <cmath>

#include "solver/hierarchy.hpp"

namespace snvr {

namespace {

// Level-0 bricks whose cell centres come within `radius` (world) of some point.
std::vector<std::uint8_t> bricks_near_points(const PointSet& points, const Domain& d, const Level& lv,
                                             double radius) {
    std::vector<std::uint8_t> near(lv.brick_count(), 0);
    const int nb[3] = {lv.bx, lv.by, lv.bz};
    const int n[3] = {d.nx, d.ny, d.nz};
    const double span = kBrick * d.h;
    for (const Vec3& p : points) {
        int lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::max(0, int(std::floor((p[a] - radius - d.origin[a]) / span)));
            hi[a] = std::min(nb[a] - 1, int(std::floor((p[a] + radius - d.origin[a]) / span)));
        }
        for (int bk = lo[2]; bk <= hi[2]; ++bk)
            for (int bj = lo[1]; bj <= hi[1]; ++bj)
                for (int bi = lo[0]; bi <= hi[0]; ++bi) {
                    const int b[3] = {bi, bj, bk};
                    double dsq = 0;
                    for (int a = 0; a < 3; ++a) {  // distance to the box of the brick's cell centres
                        const double c0 = d.origin[a] + (b[a] * kBrick + 0.5) * d.h;
                        const double c1 = d.origin[a] + (std::min(n[a], (b[a] + 1) * kBrick) - 0.5) * d.h;
                        const double gap = std::max({c0 - p[a], 0.0, p[a] - c1});
                        dsq += gap * gap;
                    }
                    if (dsq <= radius * radius)
                        near[std::size_t(bi) + std::size_t(lv.bx) * (std::size_t(bj) + std::size_t(lv.by) * std::size_t(bk))] = 1;
                }
    }
    return near;
}

double dist_sq(const Vec3& a, const Vec3& b) {
    const double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
    return x * x + y * y + z * z;
}

}  // namespace

Band band_of(const DomainPlan& plan, double band_xi) {
    const double L = plan.domain.length_scale();
    return {plan.offset / L, std::max(band_xi * plan.xi, plan.domain.h) / L};
}

template <class Real>
BandDistance<Real> band_distance(const PointSet& points, const PointIndex& index, const Domain& d, const Band& band) {
    const double L = d.length_scale();
    const double radius = (band.offset + band.cut) * L * (1 + 1e-9);  // world units
    const Real far = Real(band.offset + 2 * band.cut);

    const Hierarchy shapes = make_levels(Domain{d.origin, d.h, d.nx, d.ny, d.nz, 1});
    const Level& lv = shapes.levels[0];
    std::vector<std::uint8_t> near = bricks_near_points(points, d, lv, radius);
    std::vector<std::uint32_t> todo;
    for (std::uint32_t b = 0; b < near.size(); ++b)
        if (near[b]) todo.push_back(b);

    BandDistance<Real> out;
    out.distance.assign(d.cells(), far);
    out.near_bricks = todo;
    std::size_t queried = 0;
#pragma omp parallel for schedule(dynamic, 4) reduction(+ : queried)
    for (std::size_t t = 0; t < todo.size(); ++t) {
        const CellRange r = lv.range(todo[t]);
        // A neighbour's nearest point is nearly always this cell's nearest too, or close:
        // its distance bounds the query so tightly that the tree prunes almost everything.
        std::size_t known[kBrick][kBrick][kBrick];
        for (int k = r.k0; k < r.k1; ++k)
            for (int j = r.j0; j < r.j1; ++j)
                for (int i = r.i0; i < r.i1; ++i) {
                    const int a = i - r.i0, b = j - r.j0, c = k - r.k0;
                    const Vec3 q = d.cell_center(i, j, k);
                    double bound_sq = radius * radius;
                    auto tighten = [&](std::size_t p) {
                        if (p != PointIndex::npos) bound_sq = std::min(bound_sq, dist_sq(q, index.point(p)) * (1 + 1e-12));
                    };
                    if (a > 0) tighten(known[c][b][a - 1]);
                    if (b > 0) tighten(known[c][b - 1][a]);
                    if (c > 0) tighten(known[c - 1][b][a]);
                    const PointIndex::Hit hit = index.nearest(q, bound_sq);
                    ++queried;
                    known[c][b][a] = hit.index;
                    if (hit.index == PointIndex::npos) continue;  // nothing within the radius
                    out.distance[d.index(i, j, k)] = Real(std::sqrt(hit.dist_sq) / L);
                }
    }
    out.queried_cells = queried;
    return out;
}

template <class Real>
void classify_band(BandDistance<Real>& bd, const Domain& d, const Band& band) {
    const Hierarchy shapes = make_levels(Domain{d.origin, d.h, d.nx, d.ny, d.nz, 1});
    const Level& lv = shapes.levels[0];
    const Real l = Real(band.offset), cut = Real(band.cut);
    bd.brick_mask.assign(lv.brick_count(), 0);
    std::size_t active = 0;
#pragma omp parallel for schedule(static) reduction(+ : active)
    for (std::size_t t = 0; t < bd.near_bricks.size(); ++t) {
        const CellRange r = lv.range(bd.near_bricks[t]);
        std::size_t here = 0;
        for (int k = r.k0; k < r.k1; ++k)
            for (int j = r.j0; j < r.j1; ++j)
                for (int i = r.i0; i < r.i1; ++i) here += std::abs(l - bd.distance[d.index(i, j, k)]) <= cut;
        if (here) bd.brick_mask[bd.near_bricks[t]] = 1;
        active += here;
    }
    bd.active_cells = active;
}

template BandDistance<double> band_distance<double>(const PointSet&, const PointIndex&, const Domain&, const Band&);
template BandDistance<float> band_distance<float>(const PointSet&, const PointIndex&, const Domain&, const Band&);
template void classify_band<double>(BandDistance<double>&, const Domain&, const Band&);
template void classify_band<float>(BandDistance<float>&, const Domain&, const Band&);

}  // namespace snvr
