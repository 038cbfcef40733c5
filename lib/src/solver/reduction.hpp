// One summation order for the residual norm on every backend, so both backends give
// the same bits from the same residuals: 256 consecutive chunks, each summed in order,
// then the chunk sums in order (kernels/sum_partials.cl does the same on a device).
#pragma once
#include <algorithm>
#include <cstddef>
#include <vector>

namespace snvr {

constexpr std::size_t kSumChunks = 256;

inline double chunked_sum(const std::vector<double>& v) {
    const std::size_t n = v.size(), per = (n + kSumChunks - 1) / kSumChunks;
    double total = 0;
    for (std::size_t c = 0; c < kSumChunks; ++c) {
        double s = 0;
        for (std::size_t t = std::min(n, c * per); t < std::min(n, c * per + per); ++t) s += v[t];
        total += s;
    }
    return total;
}

}  // namespace snvr
