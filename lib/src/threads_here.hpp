// The one thread-count helper: how many threads a parallel region started here gets,
// and which of them is running.
#pragma once
#ifdef _OPENMP
#include <omp.h>
#endif

#include <algorithm>

namespace snvr::detail {

// The most threads a `#pragma omp parallel` (without num_threads) started at this
// point can have. Outside any parallel region, or inside one while nesting is on:
// omp_get_max_threads(). Inside an active region with nesting off (the default): 1,
// as the inner region runs on the calling thread alone, and splitting work by thread
// there would only repeat it. So it sizes per-thread buffers indexed by
// thread_number() and splits work by thread.
inline int threads_here() {
#ifdef _OPENMP
    return omp_get_active_level() >= omp_get_max_active_levels() ? 1 : std::max(1, omp_get_max_threads());
#else
    return 1;
#endif
}

// This thread's number in the innermost parallel region (0 outside any).
inline int thread_number() {
#ifdef _OPENMP
    return omp_get_thread_num();
#else
    return 0;
#endif
}

}  // namespace snvr::detail
