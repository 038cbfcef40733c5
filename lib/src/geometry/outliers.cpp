// split_outliers (reconstruct.hpp): uniform random outliers sit far from the surface
// and from each other, so they fall out of the surface's clusters as singletons or
// small groups; a sparse but real part of a scan is still linked at a few spacings.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "geometry/point_clusters.hpp"
#include "geometry/point_index.hpp"
#include "snvr/error.hpp"
#include "snvr/reconstruct.hpp"

namespace snvr {
namespace {


// The median of v (reordered).
double median(std::vector<double>& v) {
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
}

}  // namespace

void OutlierSettings::validate() const {
    if (!(reach_factor > 0) || !std::isfinite(reach_factor) || neighbours < 1)
        throw ParameterError("the outliers' reach factor must be a positive number and neighbours at least 1");
}

OutlierSplit split_outliers(const PointSet& points, const Parameters& params, const OutlierSettings& s) {
    s.validate();
    OutlierSplit split;
    if (points.size() < 2) {
        split.kept = points;
        return split;
    }
    // Each point's distance to its k-th neighbour; the surface's is the median.
    std::vector<double> reach(points.size());
    {
        const PointIndex index(points);
        const std::ptrdiff_t n = std::ptrdiff_t(points.size());
#pragma omp parallel for schedule(dynamic, 1024)
        for (std::ptrdiff_t i = 0; i < n; ++i) reach[std::size_t(i)] = index.kth_nearest(std::size_t(i), s.neighbours);
    }
    std::vector<double> sorted = reach;
    const double typical = median(sorted);
    if (!(typical > 0)) {  // most points at one place: nothing stands out
        split.kept = points;
        return split;
    }
    // Sparse where the surface is dense: too few neighbours near by.
    PointSet dense;
    std::vector<char> out(points.size(), 0);
    for (std::size_t i = 0; i < points.size(); ++i) {
        out[i] = reach[i] > s.reach_factor * typical;
        if (!out[i]) dense.push_back(points[i]);
    }
    // Among the rest, what the shell would carry as loose beads: clusters that the
    // offset the run will use (planned on the points kept) leaves apart, if small.
    // Dropping them can lower the offset (they may set the sampling gap), which can
    // part more: again until nothing changes (two rounds in the cases tried).
    for (int round = 0; round < 8; ++round) {
        split.link = 2 * plan_domain(dense, params).offset;
        const std::vector<std::size_t> label = point_cluster_labels(dense, split.link);
        std::vector<std::size_t> size(dense.size(), 0);
        for (std::size_t l : label) ++size[l];
        PointSet kept;
        bool dropped = false;
        for (std::size_t i = 0, d = 0; i < points.size(); ++i) {
            if (out[i]) continue;
            const std::size_t members = size[label[d]];
            out[i] = members < s.min_cluster && double(members) < 0.01 * double(points.size());
            if (out[i]) dropped = true;
            else kept.push_back(dense[d]);
            ++d;
        }
        dense = std::move(kept);
        if (!dropped) break;
    }
    for (std::size_t i = 0; i < points.size(); ++i) (out[i] ? split.outliers : split.kept).push_back(points[i]);
    return split;
}

}  // namespace snvr
