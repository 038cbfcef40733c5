// What this process may use, in our own words: the memory limits in force (RLIMIT_AS,
// RLIMIT_DATA, the cgroup's memory.max) and whether its threads can start. The OpenMP
// runtime ends the process itself when it cannot allocate or start a thread inside a
// parallel region, so both are settled before the first one.
#pragma once
#include <cstddef>
#include <string>

namespace snvr::detail {

// Bytes this process can still take: the machine's available memory, less where a limit
// in force leaves less room, or a run's budget (BudgetScope) does.
std::size_t available_memory();

// This process's resident memory now (/proc/self/statm).
std::size_t resident_bytes();

// A run's memory budget (Parameters::max_memory) while the scope lives: what the run may
// add to the process's resident memory from the scope's start, counting `held` (what it
// was given and now holds, e.g. the points' coordinates) as already added. Nested scopes
// leave the outermost in force. Without a budget the scope does nothing.
class BudgetScope {
public:
    BudgetScope(std::size_t budget, std::size_t held);
    ~BudgetScope();
    BudgetScope(const BudgetScope&) = delete;
    BudgetScope& operator=(const BudgetScope&) = delete;
private:
    bool outermost_ = false;
};

// Gives the heap's free memory back to the system (the C library keeps what large
// freed blocks leave, up to 32 MiB a block): between stages, so that the next one's peak
// is its own and not the last one's leftovers.
void release_free_memory();

// The budget in force (0: none), and what the run has used of it.
std::size_t budget_in_force();
std::size_t budget_used();

// The tightest memory limit in force, in words (the budget's too) ("the process's address space is limited
// to 150 MiB (ulimit -v)"); empty when none is set.
std::string memory_limit_text();

// Starts, once a process, as many threads as the OpenMP runtime would use; where they
// cannot all start (a thread limit, an address space too small for their stacks), runs
// on one thread from then on and returns why (the same text on every later call); empty
// when they can.
const std::string& settle_threads();

}  // namespace snvr::detail
