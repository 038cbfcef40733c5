// plan_domain with a point index the caller already built (reconstruct reuses it).
#pragma once
#include "geometry/point_index.hpp"
#include "snvr/reconstruct.hpp"

namespace snvr {

DomainPlan plan_domain(const PointSet& points, const Parameters& params, const PointIndex& index);

}  // namespace snvr
