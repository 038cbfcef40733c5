// UnsetVector: a std::vector of a trivial type whose resize() leaves the new elements
// unset, for the threads to fill.
#pragma once
#include <cstddef>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace snvr::detail {

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
