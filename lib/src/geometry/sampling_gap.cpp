#include "geometry/sampling_gap.hpp"

#include <algorithm>
#include <vector>

namespace snvr {

double sampling_gap(const PointSet& points, const PointIndex& index) {
    const std::size_t n = points.size();
    if (n < 2) return 0;
    const std::size_t samples = std::min<std::size_t>(n, 20000);
    std::vector<double> nn(samples);
#pragma omp parallel for schedule(dynamic, 256)
    for (std::size_t s = 0; s < samples; ++s) nn[s] = index.nearest_other(s * n / samples);
    const std::size_t at = std::min(samples - 1, std::size_t(0.99 * double(samples)));
    std::nth_element(nn.begin(), nn.begin() + std::ptrdiff_t(at), nn.end());
    return nn[at];
}

}  // namespace snvr
