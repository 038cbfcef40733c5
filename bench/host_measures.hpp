// Host-side measures shared by the benchmarks: the memory bandwidth plain OpenMP loops
// reach (a STREAM-like triad) and the process's peak resident memory.
#pragma once
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <vector>

namespace snvr::bench {

// Triad a = b + s c over arrays far larger than the caches; best of 5, bytes per second.
inline double triad_bandwidth(std::size_t n = std::size_t(1) << 25) {  // 3 x 256 MiB by default
    std::vector<double> a(n), b(n), c(n);
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) a[i] = 0, b[i] = 1, c[i] = 2;
    double best = 0;
    for (int rep = 0; rep < 5; ++rep) {
        const auto t0 = std::chrono::steady_clock::now();
#pragma omp parallel for schedule(static)
        for (std::size_t i = 0; i < n; ++i) a[i] = b[i] + 3.0 * c[i];
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        best = std::max(best, 3.0 * double(n) * sizeof(double) / s);
    }
    if (a[n / 2] != 7.0) std::fprintf(stderr, "triad check failed\n");
    return best;
}

inline double peak_rss_mib() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_maxrss) / 1024.0;
}

}  // namespace snvr::bench
