#include "geometry/sampling_gap.hpp"

#include <algorithm>
#include <vector>

#include "geometry/point_samples.hpp"

namespace snvr {

double sampling_gap(const detail::PointTree& tree) {
    if (tree.size() < 2) return 0;
    const std::vector<std::uint32_t> sample = detail::strided_sample(tree, 20000);
    std::vector<double> nn(sample.size());
    const std::ptrdiff_t n = std::ptrdiff_t(sample.size());
#pragma omp parallel for schedule(dynamic, 256)
    for (std::ptrdiff_t s = 0; s < n; ++s) nn[s] = tree.nearest_other(sample[s]);
    const std::size_t at = std::min(nn.size() - 1, std::size_t(0.99 * double(nn.size())));
    std::nth_element(nn.begin(), nn.begin() + std::ptrdiff_t(at), nn.end());
    return nn[at];
}

}  // namespace snvr
