// available_memory, memory_limit_text and settle_threads (process_limits.hpp).
#include "process_limits.hpp"

#include <sys/resource.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <unistd.h>

#include <algorithm>
#include <condition_variable>
#include <fstream>
#include <mutex>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include "spilled_memory.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace snvr::detail {
namespace {

constexpr std::size_t kUnknown = std::size_t(1) << 40;  // do not refuse

std::size_t meminfo_available() {
    std::ifstream in("/proc/meminfo");
    std::string key;
    std::size_t kb = 0;
    while (in >> key >> kb) {
        if (key == "MemAvailable:") return kb * 1024;
        in.ignore(256, '\n');
    }
    return kUnknown;
}

// This process's mapped size and its data segment (/proc/self/statm, in pages).
void process_sizes(std::size_t& mapped, std::size_t& data) {
    std::ifstream in("/proc/self/statm");
    std::size_t size = 0, resident = 0, shared = 0, text = 0, lib = 0, d = 0;
    in >> size >> resident >> shared >> text >> lib >> d;
    const std::size_t page = std::size_t(::sysconf(_SC_PAGESIZE));
    mapped = size * page;
    data = d * page;
}

// The cgroup (v2) memory.max and memory.current of this process, when one is set.
bool cgroup_memory(std::size_t& max, std::size_t& current) {
    std::ifstream in("/proc/self/cgroup");
    std::string line, path;
    while (std::getline(in, line))
        if (line.rfind("0::", 0) == 0) path = line.substr(3);
    if (path.empty()) return false;
    std::ifstream m("/sys/fs/cgroup" + path + "/memory.max"), c("/sys/fs/cgroup" + path + "/memory.current");
    std::string text;
    if (!(m >> text) || text == "max" || !(c >> current)) return false;
    max = std::size_t(std::stoull(text));
    if (spilled_any()) {
        // The spilled arrays' pages are the group's cached file pages, which the kernel
        // takes back as the group needs room: not counted as used.
        std::ifstream stat("/sys/fs/cgroup" + path + "/memory.stat");
        std::string key;
        std::size_t value = 0;
        while (stat >> key >> value)
            if (key == "file") current -= std::min(current, value);
    }
    return true;
}

struct Limit {
    std::size_t room = kUnknown;  // bytes left under it
    std::string text;
};

// The limit that leaves the least room.
Limit tightest_limit() {
    Limit best;
    std::size_t mapped = 0, data = 0;
    process_sizes(mapped, data);
    const auto consider = [&best](std::size_t limit, std::size_t used, const std::string& text) {
        const std::size_t room = limit > used ? limit - used : 0;
        if (room < best.room) best = {room, text + " is limited to " + std::to_string(limit >> 20) + " MiB"};
    };
    rlimit r{};
    if (::getrlimit(RLIMIT_AS, &r) == 0 && r.rlim_cur != RLIM_INFINITY)
        consider(std::size_t(r.rlim_cur), mapped, "the process's address space (ulimit -v)");
    if (::getrlimit(RLIMIT_DATA, &r) == 0 && r.rlim_cur != RLIM_INFINITY)
        consider(std::size_t(r.rlim_cur), data, "the process's data size (ulimit -d)");
    std::size_t max = 0, current = 0;
    if (cgroup_memory(max, current)) consider(max, current, "the control group's memory (memory.max)");
    return best;
}

}  // namespace

namespace {
// The budget in force and the resident bytes its run started from (its held bytes taken off).
std::size_t budget_bytes = 0, budget_base = 0;

std::string mib(std::size_t bytes) { return std::to_string(bytes >> 20) + " MiB"; }
}  // namespace

std::size_t resident_bytes() {
    std::ifstream in("/proc/self/statm");
    std::size_t size = 0, resident = 0;
    in >> size >> resident;
    return resident * std::size_t(::sysconf(_SC_PAGESIZE));
}

BudgetScope::BudgetScope(std::size_t budget, std::size_t held) {
    if (!budget || budget_bytes) return;
    outermost_ = true;
    const std::size_t now = resident_but_spilled();
    budget_base = now > held ? now - held : 0;
    budget_bytes = budget;
}

BudgetScope::~BudgetScope() {
    if (outermost_) budget_bytes = 0;
}

void release_free_memory() {
#if defined(__GLIBC__)
    ::malloc_trim(0);
#endif
}

std::size_t budget_in_force() { return budget_bytes; }

std::size_t budget_used() {
    // The spilled points' pages come and go (spilled_memory.hpp): the rest is what counts.
    const std::size_t now = resident_but_spilled();
    return budget_bytes && now > budget_base ? now - budget_base : 0;
}

std::size_t available_memory() {
    std::size_t room = std::min(meminfo_available(), tightest_limit().room);
    if (budget_bytes) room = std::min(room, budget_bytes > budget_used() ? budget_bytes - budget_used() : 0);
    return room;
}

std::string memory_limit_text() {
    const Limit tightest = tightest_limit();
    if (budget_bytes && budget_bytes - std::min(budget_bytes, budget_used()) <= tightest.room)
        return "the run's memory budget (--max-memory) is " + mib(budget_bytes) + ", " + mib(budget_used()) + " of it used";
    return tightest.text;
}

const std::string& settle_threads() {
    static std::once_flag once;
    static std::string why;
    std::call_once(once, [] {
#ifdef _OPENMP
        const int wanted = omp_get_max_threads();
        if (wanted <= 1) return;
        // Each thread is given room for its stack (8 MiB) and its own allocations, so
        // that a region later in the run does not meet a limit its threads cannot start in.
        constexpr std::size_t kPerThread = std::size_t(32) << 20;
        const std::size_t room = tightest_limit().room;
        if (room < std::size_t(wanted) * kPerThread)
            why = std::to_string(wanted) + " threads are given " + std::to_string(wanted * (kPerThread >> 20)) +
                  " MiB to start in, and " + std::to_string(room >> 20) + " MiB are left";
        // The team's other threads, started and held until all are up, each with its
        // stack (and no allocation: an arena of the C library's, once made, stays).
        std::mutex m;
        std::condition_variable all_up;
        bool go = false;
        std::vector<std::thread> team;
        try {
            for (int t = 1; t < wanted && why.empty(); ++t)
                team.emplace_back([&] {
                    std::unique_lock<std::mutex> lock(m);
                    all_up.wait(lock, [&] { return go; });
                });
        } catch (const std::system_error& e) {
            why = std::to_string(team.size() + 1) + " of " + std::to_string(wanted) + " threads could start (" +
                  e.what() + ")";
        }
        {
            std::lock_guard<std::mutex> lock(m);
            go = true;
        }
        all_up.notify_all();
        for (std::thread& t : team) t.join();
        if (why.empty()) {
            // The runtime's own team, started now in the room the probe's threads just
            // left, and kept for every later region (libgomp holds its idle threads).
#pragma omp parallel
            {
            }
            return;
        }
        const std::string limit = memory_limit_text();
        why += (limit.empty() ? "" : "; " + limit) + ": running on one thread";
        omp_set_num_threads(1);
#endif
    });
    return why;
}

}  // namespace snvr::detail
