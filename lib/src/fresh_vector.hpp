// A std::vector whose resize leaves new elements of trivial types unwritten: for large
// arrays that a parallel loop then writes in full, so that each thread touches its own
// part's pages first (a serial zeroing pass first faults them all on one core, which on
// a VM cost 0.65 s a GB).
#pragma once
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace snvr::detail {

template <class T>
struct DefaultInitAllocator : std::allocator<T> {
    template <class U>
    struct rebind {
        using other = DefaultInitAllocator<U>;
    };
    DefaultInitAllocator() = default;
    template <class U>
    DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
    template <class U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
        ::new (static_cast<void*>(p)) U;  // default-initialised: a float is left as it is
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

template <class T>
using FreshVector = std::vector<T, DefaultInitAllocator<T>>;

}  // namespace snvr::detail
