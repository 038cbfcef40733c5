#pragma once
#include <omp.h>

#include <algorithm>

namespace snvr::detail {

// The threads a parallel region started here would get: one inside another
// region (unless nested parallelism is on), where splitting work by thread
// would only repeat it.
inline int threads_here() {
    return omp_get_active_level() >= omp_get_max_active_levels() ? 1 : std::max(1, omp_get_max_threads());
}

}  // namespace snvr::detail
