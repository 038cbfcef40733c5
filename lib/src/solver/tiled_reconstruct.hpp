// reconstruct() cut into tiles (Parameters::tile_cells): the whole run's plan, then each
// tile's core computed with a halo around it (tile_plan.hpp), one tile at a time, their
// cores put together into the whole grid's phase field.
#pragma once
#include "snvr/point_cloud.hpp"
#include "snvr/reconstruct.hpp"

namespace snvr {

template <class Real>
void reconstruct_tiled(const PointCloud& points, const Parameters& params, const ProgressCallback& progress,
                       Result& res);

}  // namespace snvr
