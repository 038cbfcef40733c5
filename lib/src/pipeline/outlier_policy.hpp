// drop_outliers (shell.hpp) with the rules' neighbour counts and clusters answered in
// part by other processes (solver/shared_filing.hpp's NeighbourCountsShared); each
// question null: by this one alone; told how far the stray rule has come.
#pragma once
#include "geometry/outliers.hpp"
#include "snvr/shell.hpp"

namespace snvr::detail {

DroppedOutliers drop_outliers_shared(PointCloud& points, const Parameters& params, const OutlierSettings& settings,
                                     const RuleQuestions& asked, const Told& told = nullptr);

}  // namespace snvr::detail
