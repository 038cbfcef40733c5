// Running a test's work on a given number of OpenMP threads.
#pragma once
#include <omp.h>

namespace snvr::testing {

// f() run with n OpenMP threads.
template <class F>
auto with_threads(int n, F f) {
    const int before = omp_get_max_threads();
    omp_set_num_threads(n);
    auto r = f();
    omp_set_num_threads(before);
    return r;
}

}  // namespace snvr::testing
