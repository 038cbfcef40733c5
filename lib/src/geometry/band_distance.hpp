// The unsigned distance d (eq. 1), exact wherever the phase field is not +-1:
// within l + band of some point. Other cells get a stand-in value beyond the band
// and are never queried one by one.
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "solver/backend.hpp"
#include "geometry/point_index.hpp"
#include "snvr/domain.hpp"
#include "snvr/reconstruct.hpp"

namespace snvr {

// The band in normalised units, as the phase-field initialisation sees it.
struct Band {
    double offset;  // l
    double cut;     // |l - d| beyond this: phi0 = +-1, g = 0
};

// The band of a planned run: cut = band_xi * xi, but at least a cell, because d changes
// by at most h from cell to cell: then no cell jumps across the band, and a brick
// without band cells is all +1 or all -1.
Band band_of(const DomainPlan& plan, double band_xi);

// The tube of a planned run (backend.hpp), normalised; off for a free flow.
template <class Real>
Tube<Real> tube_of(const DomainPlan& plan) {
    Tube<Real> t;
    if (plan.tube_inner <= 0) return t;
    const double L = plan.domain.length_scale();
    t.inner = Real((plan.offset - plan.tube_inner) / L);
    t.outer = Real((plan.offset + plan.tube_outer) / L);
    t.s = Real(L / (std::sqrt(2.0) * plan.xi));
    return t;
}

template <class Real>
struct BandDistance {
    std::vector<Real> distance;           // normalised, one per cell
    std::vector<std::uint32_t> near_bricks;  // level-0 bricks within l + cut of a point (queried)
    std::vector<std::uint8_t> brick_mask; // level-0 bricks holding a cell with |l - d| <= cut
    std::size_t active_cells = 0;         // cells with |l - d| <= cut
    std::size_t queried_cells = 0;        // cells that needed a nearest-point query
};

// Computes distance, near_bricks and queried_cells.
template <class Real>
BandDistance<Real> band_distance(const PointSet& points, const PointIndex& index, const Domain& domain,
                                 const Band& band);

// Sets brick_mask and active_cells from the distance (after any adjustment of it).
template <class Real>
void classify_band(BandDistance<Real>& bd, const Domain& domain, const Band& band);

}  // namespace snvr
