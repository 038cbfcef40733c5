// reconstruct() cut into tiles (Parameters::tile_cells): the whole run's plan, then each
// tile's core computed with a halo around it (tile_plan.hpp), one tile at a time, their
// cores put together into the whole grid's phase field.
#pragma once
#include "snvr/point_cloud.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/tiles.hpp"
#include "solver/session.hpp"

namespace snvr {

// On the whole run's plan and the points it measures (those added included); the first
// tile's backend from `start`. `tiles_on` (tiles.hpp) spreads the tiles over processes;
// null: all run here.
template <class Real>
// `points`: the run's own (measured less those added), which the slabs' depth guard keeps
// deep (Parameters::surface_guard).
void reconstruct_tiled(const PointCloud& measured, const PointCloud& points, const DomainPlan& plan,
                       const Parameters& params, BackendStart<Real>& start, const ProgressCallback& progress,
                       TileScheduler* tiles_on, Result& res);

// Another process's share of a tiled run the root spreads (tiles.hpp): the plan, the
// owners and its points from the root, its tiles run and sent.
template <class Real>
void reconstruct_tiles_given(const Parameters& params, TileScheduler& on, Result& res);

}  // namespace snvr
