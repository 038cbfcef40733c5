// Fixed-size binary records (PLY vertices without lists, LAS points) into floats about an
// origin, read from their source part by part: each thread reads its share of the records
// into a buffer of ParseOptions::read_part bytes, reused, and stores each point in its
// place. The file is never held whole (the points are the peak), and a read that fails
// or falls short leaves its part unconverted for InputSource::finish() to name.
#pragma once
#include <omp.h>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <string_view>
#include <vector>

#include "io/float_origin.hpp"
#include "io/input_source.hpp"
#include "io/point_readers.hpp"
#include "parallel_sizes.hpp"
#include "process_limits.hpp"

namespace snvr::detail {

// OpenMP's thread count unless a positive one is asked for.
inline int thread_count(int requested) { return requested > 0 ? requested : omp_get_max_threads(); }

// Records 0 .. count-1 of `length` bytes each, the first at byte `first` of the source.
struct RecordSpan {
    std::size_t first = 0, length = 0, count = 0;
};

// Record i's point; decode(record) gives the point of a record's bytes. Throws as
// InputSource::finish() where the read falls short.
template <class Decode>
Vec3 record_point(const InputSource& source, const RecordSpan& records, const Decode& decode, std::size_t i) {
    std::vector<char> buffer;
    std::string_view bytes;
    const std::size_t at = records.first + i * records.length;
    if (!source.part(at, at + records.length, buffer, bytes)) source.finish();
    return decode(bytes.data());
}

// The box of the first `sample` records; empty where their read falls short.
template <class Decode>
SampleBox sample_records(const InputSource& source, const RecordSpan& records, const Decode& decode,
                         std::size_t sample) {
    SampleBox box;
    const std::size_t n = std::min(records.count, sample);
    std::vector<char> buffer;
    std::string_view bytes;
    if (n == 0 || !source.part(records.first, records.first + n * records.length, buffer, bytes)) return box;
    for (std::size_t i = 0; i < n; ++i) box.add(decode(bytes.data() + i * records.length));
    return box;
}

struct ConvertedRecords {
    std::size_t first_refused;  // the first record to_float could not hold; `count` when none
    SampleBox box;              // of the points held (origin + float), to check the origin by
};

// Stores the records in `out` (resized to their count) as floats about `origin`, each
// thread converting an even, contiguous share in order.
template <class Decode>
ConvertedRecords convert_records(const InputSource& source, const RecordSpan& records, const Decode& decode,
                                 const Vec3& origin, PointArray<Float3>& out, const ParseOptions& options) {
    const std::size_t count = records.count;
    out.resize(count);
    ConvertedRecords result{count, {}};
    const std::size_t per_part = std::max<std::size_t>(1, options.read_part / records.length);
    const int threads = thread_count(options.threads);
    settle_threads();  // before the first parallel region: the OpenMP runtime cannot fail softly
    // Allocated here: nothing may throw inside the parallel region.
    std::vector<std::vector<char>> buffers(std::size_t(threads), std::vector<char>(std::min(per_part, count) * records.length));
#pragma omp parallel num_threads(threads) if (count >= std::size_t(kParallelCheapItems))
    {
        const std::size_t t = std::size_t(omp_get_thread_num()), team = std::size_t(omp_get_num_threads());
        const std::size_t begin = count * t / team, end = count * (t + 1) / team;
        std::size_t refused = count;
        const float inf = std::numeric_limits<float>::infinity();
        Float3 lo{inf, inf, inf}, hi{-inf, -inf, -inf};
        std::string_view bytes;
        for (std::size_t b = begin; b < end; b += per_part) {
            const std::size_t e = std::min(end, b + per_part);
            if (!source.part(records.first + b * records.length, records.first + e * records.length, buffers[t], bytes))
                break;
            for (std::size_t i = b; i < e; ++i) {
                Float3& q = out[i];
                if (!to_float(decode(bytes.data() + (i - b) * records.length), origin, q)) {
                    refused = std::min(refused, i);
                    continue;
                }
                for (int a = 0; a < 3; ++a) {
                    lo[a] = std::min(lo[a], q[a]);
                    hi[a] = std::max(hi[a], q[a]);
                }
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
