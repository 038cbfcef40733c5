// The unsigned distance d (eq. 1), exact wherever the phase field is not +-1:
// within l + band of some point. Other cells get a stand-in value beyond the band
// and are never queried one by one.
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "fresh_vector.hpp"
#include "grid/brick_tiling.hpp"
#include "geometry/point_tree.hpp"
#include "snvr/domain.hpp"

namespace snvr {

// The band in normalised units, as the phase-field initialisation sees it.
struct Band {
    double offset;  // l
    double cut;     // |l - d| beyond this: phi0 = +-1, g = 0
};

// Stored per brick, for the bricks near the points only: memory follows the band.
template <class Real>
struct BandDistance {
    std::vector<std::uint32_t> near_bricks;  // level-0 bricks within l + cut of a point (queried), ascending
    detail::FreshVector<Real> near_values;   // kBrick^3 per near brick, in near_bricks' order, x fastest
                                             // inside the brick (cells beyond the grid: far)
    Real far = 0;                            // every other cell: beyond the band
    std::vector<std::uint8_t> brick_mask;    // level-0 bricks holding a cell with |l - d| <= cut
    std::vector<std::uint8_t> inside_bricks; // level-0 bricks without band cells that lie inside (l > d)
    std::size_t active_cells = 0;            // cells with |l - d| <= cut
    std::size_t queried_cells = 0;           // cells that needed a nearest-point query

    const Real* brick_values(std::size_t near_index) const { return near_values.data() + near_index * kBrick * kBrick * kBrick; }
    // The whole grid, x fastest (for tests and checks; the solver never needs it).
    std::vector<Real> dense(const Domain& domain) const;
};

// Computes near_bricks, near_values, far and queried_cells. `before_values` hears how
// many bricks are near the points before their values are allocated (a memory check
// may throw there).
template <class Real>
BandDistance<Real> band_distance(const detail::PointTree& tree, const Domain& domain,
                                 const Band& band,
                                 const std::function<void(std::size_t near_bricks)>& before_values = {});

// Sets brick_mask, inside_bricks and active_cells from the distance.
template <class Real>
void classify_band(BandDistance<Real>& bd, const Domain& domain, const Band& band);

}  // namespace snvr
