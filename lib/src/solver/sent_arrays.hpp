// Arrays of plain values between the processes of a run spread over them (tiles.hpp's
// send_bytes and receive_bytes, received in the order sent): the points' tree filed by
// all (shared_filing.cpp) and the depth guard's search (pipeline/shared_guard.cpp).
#pragma once
#include <cstddef>

#include "snvr/error.hpp"
#include "snvr/tiles.hpp"

namespace snvr::detail {

template <class T>
void send_array(TileScheduler& on, int to, const T* data, std::size_t n) {
    on.send_bytes(to, data, n * sizeof(T));
}
// Received into `into`, resized to what came.
template <class Array>
void receive_array(TileScheduler& on, int from, Array& into) {
    using T = typename Array::value_type;
    on.receive_bytes(from, [&into](std::size_t bytes) -> void* {
        if (bytes % sizeof(T)) throw Error("a message from another process is not whole");
        into.resize(bytes / sizeof(T));
        return into.data();
    });
}
// Received into n elements at `at`, which must be what came.
template <class T>
void receive_into(TileScheduler& on, int from, T* at, std::size_t n) {
    on.receive_bytes(from, [at, n](std::size_t bytes) -> void* {
        if (bytes != n * sizeof(T)) throw Error("a message from another process is not the size agreed");
        return at;
    });
}

// With every other process q: give(q) sends to it and take(q) receives from it, the lower
// of the two sending first, so that no two wait on each other.
template <class Give, class Take>
void exchange_pairwise(TileScheduler& on, const Give& give, const Take& take) {
    const int me = on.rank();
    for (int q = 0; q < on.processes(); ++q) {
        if (q == me) continue;
        if (me < q) give(q), take(q);
        else take(q), give(q);
    }
}

}  // namespace snvr::detail
