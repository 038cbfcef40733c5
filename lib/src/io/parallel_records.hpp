// Fixed-size binary records (PLY vertices without lists, LAS points) into floats about an
// origin: the records split evenly between threads, each point stored in its place.
#pragma once
#include <omp.h>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

#include "io/float_origin.hpp"
#include "parallel_sizes.hpp"

namespace snvr::detail {

// OpenMP's thread count unless a positive one is asked for.
inline int thread_count(int requested) { return requested > 0 ? requested : omp_get_max_threads(); }

// Fewer records than this are converted by one thread: starting more costs more.


// The box of the first `sample` of `count` records; decode(i) gives record i's point.
template <class Decode>
SampleBox sample_records(std::size_t count, const Decode& decode, std::size_t sample) {
    SampleBox box;
    for (std::size_t i = 0; i < std::min(count, sample); ++i) box.add(decode(i));
    return box;
}

struct ConvertedRecords {
    std::size_t first_refused;  // the first record to_float could not hold; `count` when none
    SampleBox box;              // of the points held (origin + float), to check the origin by
};

// Stores records 0 .. count-1 in `out` (resized to count) as floats about `origin`.
template <class Decode>
ConvertedRecords convert_records(std::size_t count, const Decode& decode, const Vec3& origin, std::vector<Float3>& out,
                                 int threads) {
    out.resize(count);
    ConvertedRecords result{count, {}};
    const std::ptrdiff_t n = std::ptrdiff_t(count);
#pragma omp parallel num_threads(thread_count(threads)) if (count >= std::size_t(kParallelCheapItems))
    {
        std::size_t refused = count;
        const float inf = std::numeric_limits<float>::infinity();
        Float3 lo{inf, inf, inf}, hi{-inf, -inf, -inf};
#pragma omp for schedule(static) nowait
        for (std::ptrdiff_t i = 0; i < n; ++i) {
            Float3& q = out[std::size_t(i)];
            if (!to_float(decode(std::size_t(i)), origin, q)) {
                refused = std::min(refused, std::size_t(i));
                continue;
            }
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], q[a]);
                hi[a] = std::max(hi[a], q[a]);
            }
        }
#pragma omp critical(snvr_convert_records)
        {
            result.first_refused = std::min(result.first_refused, refused);
            if (lo[0] <= hi[0]) {  // some point held
                result.box.add({origin[0] + lo[0], origin[1] + lo[1], origin[2] + lo[2]});
                result.box.add({origin[0] + hi[0], origin[1] + hi[1], origin[2] + hi[2]});
            }
        }
    }
    return result;
}

}  // namespace snvr::detail
