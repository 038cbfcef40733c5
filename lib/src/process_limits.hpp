// What this process may use, in our own words: the memory limits in force (RLIMIT_AS,
// RLIMIT_DATA, the cgroup's memory.max) and whether its threads can start. The OpenMP
// runtime ends the process itself when it cannot allocate or start a thread inside a
// parallel region, so both are settled before the first one.
#pragma once
#include <cstddef>
#include <string>

namespace snvr::detail {

// Bytes this process can still take: the machine's available memory, less where a limit
// in force leaves less room.
std::size_t available_memory();

// The tightest memory limit in force, in words ("the process's address space is limited
// to 150 MiB (ulimit -v)"); empty when none is set.
std::string memory_limit_text();

// Starts, once a process, as many threads as the OpenMP runtime would use; where they
// cannot all start (a thread limit, an address space too small for their stacks), runs
// on one thread from then on and returns why (the same text on every later call); empty
// when they can.
const std::string& settle_threads();

}  // namespace snvr::detail
