// drop_outliers and split_outliers (shell.hpp): the outlier rules measured by
// the run the parameters plan for the points kept so far (its voxel and offset); the
// sparse rule's counts shared with other processes where they filed the points too
// (detail::drop_outliers_shared, outlier_policy.hpp).
#include <cstdint>
#include <vector>

#include "geometry/outliers.hpp"
#include "pipeline/outlier_policy.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/shell.hpp"

namespace snvr {
namespace {

detail::RunLengthsOf planned_by(const Parameters& params) {
    // The lengths alone: the points the run would add do not change them, and finding
    // where it would add them (the sampling's holes) is not free.
    Parameters lengths = params;
    lengths.add_points = false;
    return [lengths](const PointCloud& cloud) {
        const DomainPlan plan = plan_domain(cloud, lengths);
        return detail::RunLengths{plan.domain.h, plan.offset};
    };
}

}  // namespace

DroppedOutliers drop_outliers(PointCloud& points, const Parameters& params, const OutlierSettings& s) {
    return detail::drop_outliers_shared(points, params, s, {});
}

DroppedOutliers detail::drop_outliers_shared(PointCloud& points, const Parameters& params, const OutlierSettings& s,
                                             const RuleQuestions& asked, const Told& told) {
    DroppedOutliers d;
    for (const auto& o : detail::remove_outliers(points, s, planned_by(params), d.link, d.clusters, asked, told)) {
        d.points.push_back(o.second);
        d.input_indices.push_back(o.first);
    }
    return d;
}

OutlierSplit split_outliers(const PointSet& points, const Parameters& params, const OutlierSettings& s) {
    s.validate();
    OutlierSplit split;
    PointCloud cloud(points);
    std::vector<std::uint8_t> out(points.size(), 0);
    std::size_t clusters = 0;
    for (const auto& o : detail::remove_outliers(cloud, s, planned_by(params), split.link, clusters)) out[o.first] = 1;
    // The caller's own coordinates, not the cloud's floats.
    for (std::size_t i = 0; i < points.size(); ++i) (out[i] ? split.outliers : split.kept).push_back(points[i]);
    return split;
}

}  // namespace snvr
