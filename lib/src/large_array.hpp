// large_array: storage for many objects of a trivial type, left unset, on the kernel's
// huge pages where it offers them (transparent huge pages on request, as Debian has them
// by default). A large array that the threads fill piecemeal takes a page fault per 4 KiB
// otherwise, and the faults of two threads queue on one lock: the check's triangle
// frames are 331 MB at 4.6 M triangles.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdlib>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace snvr::detail {

struct FreeStorage {
    void operator()(void* p) const { std::free(p); }
};
template <class T>
using LargeArray = std::unique_ptr<T[], FreeStorage>;

template <class T>
LargeArray<T> large_array(std::size_t n) {
    static_assert(std::is_trivially_default_constructible_v<T> && std::is_trivially_destructible_v<T>,
                  "the objects are neither made nor destroyed");
    constexpr std::size_t kHugePage = std::size_t(2) << 20;
    if (n > (std::size_t(-1) - kHugePage) / sizeof(T)) throw std::bad_alloc();
    const std::size_t bytes = std::max<std::size_t>(1, n * sizeof(T));
    void* p = nullptr;
    if (bytes < kHugePage) {
        p = std::malloc(bytes);
    } else {
        const std::size_t whole = (bytes + kHugePage - 1) / kHugePage * kHugePage;
        p = std::aligned_alloc(kHugePage, whole);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        if (p) ::madvise(p, whole, MADV_HUGEPAGE);  // advice only: plain pages where refused
#endif
    }
    if (!p) throw std::bad_alloc();
    T* objects = static_cast<T*>(p);
    for (std::size_t i = 0; i < n; ++i) new (objects + i) T;  // trivial: no code, no writes
    return LargeArray<T>(objects);
}

// For a std::vector whose resize() leaves the new elements unset, for the threads to
// fill: the value-initialising kind zeroes them first, on one thread (at 25 M points,
// the tree's coordinates and indices, 390 MB, were a fifth of its build).
template <class T>
struct UnsetAllocator : std::allocator<T> {
    static_assert(std::is_trivially_default_constructible_v<T>, "a default-constructed element is left unset");
    template <class U>
    struct rebind {
        using other = UnsetAllocator<U>;
    };
    UnsetAllocator() = default;
    template <class U>
    UnsetAllocator(const UnsetAllocator<U>&) noexcept {}
    template <class U>
    void construct(U* p) noexcept {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};
template <class T>
using UnsetVector = std::vector<T, UnsetAllocator<T>>;

}  // namespace snvr::detail
