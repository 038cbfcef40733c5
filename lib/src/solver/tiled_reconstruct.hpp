// reconstruct() cut into tiles (Parameters::tile_cells): the whole run's plan, then each
// tile's core computed with a halo around it (tile_plan.hpp), one tile at a time, their
// cores put together into the whole grid's phase field.
#pragma once
#include "snvr/point_cloud.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/tiles.hpp"

namespace snvr {

// `tiles_on` (tiles.hpp) spreads the tiles over processes; null: all run here.
template <class Real>
void reconstruct_tiled(const PointCloud& points, const Parameters& params, const ProgressCallback& progress,
                       TileScheduler* tiles_on, Result& res);

}  // namespace snvr
