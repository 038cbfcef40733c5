// Below these many items a loop runs on one thread: waking the team costs more than the
// work saves. Three kinds of item, by their cost.
#pragma once
#include <cstddef>

namespace snvr::detail {

constexpr std::ptrdiff_t kParallelCheapItems = 1 << 16;   // a few ns: copies, keys, boxes, samples, records
constexpr std::ptrdiff_t kParallelItems = 4096;           // 0.1-1 us: a vertex's ring, a triangle's measures
constexpr std::ptrdiff_t kParallelCostlyItems = 1 << 10;  // microseconds: a ray or a search per point

}  // namespace snvr::detail
