// The unsigned distance d (eq. 1), exact wherever the phase field is not +-1:
// within l + band of some point. Other cells get a stand-in value beyond the band
// and are never queried one by one.
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "solver/hierarchy.hpp"
#include "geometry/point_index.hpp"
#include "snvr/domain.hpp"
#include "snvr/reconstruct.hpp"

namespace snvr {

// The band in normalised units, as the phase-field initialisation sees it.
struct Band {
    double offset;  // l
    double cut;     // |l - d| beyond this: phi0 = +-1, g = 0
};

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
