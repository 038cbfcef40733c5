// The points' arrays beyond a run's memory budget, kept in files (the run's temporary
// folder) rather than on the heap: while a SpillScope lives, a PointArray of at least a
// sixteenth of the budget is mapped from an unnamed file there (its blocks reserved
// first, so a full disk is an error naming the folder, never a fault later), and a thread
// keeps the process's resident memory under the budget by giving the mapped pages back
// to the kernel, which writes them to the file and reads them again when they are
// touched. The stages walk the points in their tree's (Morton) order, so the pages they
// need are few at a time: the file is the points' partition, and each tile's points are
// a few runs of it. Nothing else changes: the arrays hold what they would on the heap,
// so the run's answers are the same bytes.
#pragma once
#include <cstddef>
#include <cstdlib>
#include <memory>
#include <new>
#include <string>
#include <type_traits>
#include <vector>

#include "unset_vector.hpp"

namespace snvr::detail {

// While it lives (the outermost of nested scopes in force), large PointArrays go to files
// in `folder` and the resident memory is held under `budget`: bytes the run may add to
// what the process held at the scope's start, `held` (what the run already holds on the
// heap) counted as added. A budget of 0: nothing spills.
class SpillScope {
public:
    SpillScope(std::size_t budget, std::size_t held, const std::string& folder);
    ~SpillScope();
    SpillScope(const SpillScope&) = delete;
    SpillScope& operator=(const SpillScope&) = delete;
private:
    bool outermost_ = false;
};

// A mapping of at least `bytes` from a file, or nullptr where no scope is in force or the
// array is small. Throws ResourceError where the folder cannot hold it.
void* spill_allocate(std::size_t bytes);
// Unmaps p if it is a spilled array (true), else leaves it (false).
bool spill_release(void* p) noexcept;
// Heap storage for an array, freed with std::free; throws bad_alloc.
void* heap_allocate(std::size_t bytes);
// Asks for huge pages under an array on the heap that the threads fill piecemeal (a page
// fault per 4 KiB otherwise, the threads' faults queued on one lock); none for a spilled one.
void advise_huge_pages(void* p, std::size_t bytes) noexcept;
// Whether p begins a spilled array.
bool spilled(const void* p) noexcept;
// Whether any array is in a file now.
bool spilled_any() noexcept;
// This process's resident bytes but its spilled arrays' pages (which come and go).
std::size_t resident_but_spilled();

// What spilling did since a scope began with no array in a file (a run's, its read's
// included).
struct SpillFacts {
    std::size_t arrays = 0;     // arrays spilled
    std::size_t most_bytes = 0; // the most their files held at once
    std::size_t trims = 0;      // times their pages were given back to stay in the budget
    std::string folder;         // where the last scope spilled
    // Bytes the process read from storage and wrote to it meanwhile (/proc/self/io: the
    // input's reading counted; the files' pages read again where memory was short).
    std::size_t read_bytes = 0, written_bytes = 0;
};
SpillFacts spill_facts();

// UnsetAllocator (unset_vector.hpp, new elements left unset) that spills large arrays
// under a SpillScope.
template <class T>
struct PointsAllocator : UnsetAllocator<T> {
    static_assert(std::is_trivially_destructible_v<T>, "points' arrays hold plain values");
    template <class U>
    struct rebind {
        using other = PointsAllocator<U>;
    };
    PointsAllocator() = default;
    template <class U>
    PointsAllocator(const PointsAllocator<U>&) noexcept {}
    T* allocate(std::size_t n) {
        if (n > std::size_t(-1) / sizeof(T)) throw std::bad_alloc();
        if (void* p = spill_allocate(n * sizeof(T))) return static_cast<T*>(p);
        return static_cast<T*>(heap_allocate(n * sizeof(T)));
    }
    void deallocate(T* p, std::size_t) noexcept {
        if (!spill_release(p)) std::free(p);
    }
};

// An array with an element a point (or so many): in a file beyond the budget.
template <class T>
using PointArray = std::vector<T, PointsAllocator<T>>;

}  // namespace snvr::detail
