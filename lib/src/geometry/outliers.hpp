// The outlier rules on a cloud (outliers.cpp), given the lengths of the run that will
// follow; which run that is, is the pipeline's to say (pipeline/outlier_policy.cpp).
#pragma once
#include <cstddef>
#include <functional>
#include <utility>
#include <vector>

#include "geometry/neighbour_counts.hpp"
#include "geometry/point_clusters.hpp"
#include "geometry/stray_points.hpp"
#include "snvr/point_cloud.hpp"

namespace snvr::detail {

class PointTree;

// The lengths the rules take from the run planned for a set of points.
struct RunLengths {
    double voxel = 0;   // h: the stray rule's scale
    double offset = 0;  // l: clusters apart by over 2 l are the shell's loose beads
};
using RunLengthsOf = std::function<RunLengths(const PointCloud&)>;

// The rules of OutlierSettings on the cloud, in place; the outliers by input index,
// ascending, with their world points. `link` is the clusters' last link (2 l; 0 when none
// was looked for), `clusters` the kept points' clusters at it when the last round counted
// them (else 0). lengths_of is asked again whenever points were dropped since.
// The rules' questions of every point that other processes may answer in part
// (solver/shared_filing.hpp); each null: this process alone.
struct RuleQuestions {
    ShortOf short_of;     // neighbours within a reach
    RootsOf roots_of;     // clusters at a link
    AskStrays strays_of;  // the lonely points' planes
};
// `told`: how far the stray rule's tests have come (most of the rules' time on a sparse scan).
std::vector<std::pair<std::size_t, Vec3>> remove_outliers(PointCloud& cloud, const OutlierSettings& settings,
                                                          const RunLengthsOf& lengths_of, double& link,
                                                          std::size_t& clusters, const RuleQuestions& asked = {},
                                                          const Told& told = nullptr);

}  // namespace snvr::detail
