// Spilled arrays (spilled_memory.hpp): each its own unnamed file, mapped shared, and a
// thread that gives their pages back when the process's resident memory nears the budget.
#include "spilled_memory.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <new>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include "process_limits.hpp"
#include "snvr/error.hpp"

namespace snvr::detail {
namespace {

struct Mapping {
    void* at;
    std::size_t bytes;
};

// The scope's settings and the live mappings, under one lock.
struct Spill {
    std::mutex lock;
    std::vector<Mapping> mappings;
    std::size_t bytes = 0;  // the live mappings'
    std::size_t budget = 0, limit = 0, least = 0;
    std::string folder;
    SpillFacts facts;
    std::size_t read_before = 0, written_before = 0;  // /proc/self/io's when the facts began
    // The resident file pages before the first spill (the program's own), so that the
    // spilled ones are what grew past them.
    std::size_t file_pages_before = 0;
    bool file_pages_known = false;
    // The governor.
    std::thread governor;
    std::condition_variable wake;
    bool stop = false;
};
Spill& spill() {
    static Spill s;
    return s;
}
std::atomic<std::size_t> live{0};   // mappings alive (a fast path for the heap's arrays)
std::atomic<bool> in_force{false};  // a scope lives

// The process's resident bytes from one look at /proc/self/status: anonymous and shared
// memory, and file-backed pages (the spilled arrays' among them).
struct Resident {
    std::size_t heap = 0, file = 0;
};
Resident resident_now() {
    std::ifstream in("/proc/self/status");
    std::string key;
    std::size_t value = 0;
    Resident r;
    while (in >> key) {
        if (key == "RssAnon:" || key == "RssShmem:" || key == "RssFile:") {
            in >> value;
            (key == "RssFile:" ? r.file : r.heap) += value << 10;
        }
        in.ignore(1 << 12, '\n');
    }
    return r;
}

// The process's bytes read from and written to storage so far (/proc/self/io).
void storage_bytes(std::size_t& read, std::size_t& written) {
    std::ifstream in("/proc/self/io");
    std::string key;
    std::size_t value = 0;
    read = written = 0;
    while (in >> key >> value) {
        if (key == "read_bytes:") read = value;
        if (key == "write_bytes:") written = value;
    }
}

std::string gib(std::size_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g GiB", double(bytes) / double(std::size_t(1) << 30));
    return text;
}

// An unnamed file in `folder` with `bytes` reserved, or throws naming the folder.
int reserved_file(const std::string& folder, std::size_t bytes) {
    int fd = -1;
#ifdef O_TMPFILE
    fd = ::open(folder.c_str(), O_TMPFILE | O_RDWR | O_EXCL | O_CLOEXEC, 0600);
#endif
    if (fd < 0) {  // a file system without unnamed files: named, then unlinked at once
        std::string name = folder + "/.snvr-points-XXXXXX";
        fd = ::mkstemp(name.data());
        if (fd >= 0) ::unlink(name.c_str());
    }
    if (fd < 0)
        throw ResourceError("cannot make a file for the points beyond the memory budget in the temporary folder '" +
                            folder + "' (--temp-dir): " + std::strerror(errno));
    const int failed = ::posix_fallocate(fd, 0, off_t(bytes));
    if (failed != 0) {
        ::close(fd);
        throw ResourceError("the temporary folder '" + folder + "' (--temp-dir) cannot hold " + gib(bytes) +
                            " more of the points beyond the memory budget (" + std::strerror(failed) +
                            "): free space there, give another folder, or a larger --max-memory");
    }
    return fd;
}

// Unmapped, the pages stay the file's: the kernel keeps them cached while memory is free
// (touched again, they come back cheaply) and writes them out and drops them when it is
// short (MADV_PAGEOUT, which writes them out at once, took the 98.5 M-point sphere from
// 25 to 37 s with memory to spare).
void give_pages_back(Spill& s) {
    for (const Mapping& m : s.mappings) ::madvise(m.at, m.bytes, MADV_DONTNEED);
    ++s.facts.trims;
}

// Every 2 ms: past the limit, the spilled pages go back (a stage touches a few at a time
// and takes them again as it needs them).
void govern(Spill& s) {
    std::unique_lock<std::mutex> hold(s.lock);
    while (!s.stop) {
        s.wake.wait_for(hold, std::chrono::milliseconds(2));
        if (s.stop) break;
        if (!s.mappings.empty() && resident_bytes() > s.limit) give_pages_back(s);
    }
}

}  // namespace

SpillScope::SpillScope(std::size_t budget, std::size_t held, const std::string& folder) {
    Spill& s = spill();
    if (!budget || in_force.load()) return;
    outermost_ = true;
    const std::size_t now = resident_but_spilled();
    std::lock_guard<std::mutex> hold(s.lock);
    s.budget = budget;
    std::error_code failed;
    s.folder = folder.empty() ? std::filesystem::temp_directory_path(failed).string() : folder;
    if (s.folder.empty()) s.folder = ".";
    // Arrays from a sixteenth of the budget; the governor's margin a third: on two busy
    // cores its looks were up to 0.19 s apart (a trim's unmapping, the others' faults), the
    // resident memory up to 230 MB past its limit (the 98.5 M-point sphere under 1 GiB).
    s.least = std::max<std::size_t>(budget / 16, std::size_t(1) << 20);
    const std::size_t margin = std::max<std::size_t>(budget / 3, std::size_t(64) << 20);
    const std::size_t base = now - std::min(now, held);
    s.limit = base + budget - std::min(budget, margin);
    if (s.mappings.empty()) {  // a new run's facts (a read's files are its run's)
        s.facts = SpillFacts{};
        storage_bytes(s.read_before, s.written_before);
    }
    s.facts.folder = s.folder;
    s.stop = false;
    try {
        s.governor = std::thread(govern, std::ref(s));
    } catch (const std::system_error&) {  // no thread to hold the budget: nothing spills
        outermost_ = false;
        return;
    }
    in_force = true;
}

SpillScope::~SpillScope() {
    if (!outermost_) return;
    Spill& s = spill();
    {
        std::lock_guard<std::mutex> hold(s.lock);
        s.stop = true;
        in_force = false;
    }
    s.wake.notify_all();
    s.governor.join();
}

void* spill_allocate(std::size_t bytes) {
    if (!in_force.load()) return nullptr;
    Spill& s = spill();
    std::string folder;
    {
        std::lock_guard<std::mutex> hold(s.lock);
        if (!in_force.load() || bytes < s.least) return nullptr;
        if (!s.file_pages_known) {
            s.file_pages_before = resident_now().file;
            s.file_pages_known = true;
        }
        folder = s.folder;
    }
    // The file and its mapping made without the lock: the governor goes on meanwhile.
    const int fd = reserved_file(folder, bytes);
    void* at = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    ::close(fd);  // the mapping keeps the file
    if (at == MAP_FAILED) throw std::bad_alloc();
    std::lock_guard<std::mutex> hold(s.lock);
    s.mappings.push_back({at, bytes});
    s.bytes += bytes;
    ++s.facts.arrays;
    s.facts.most_bytes = std::max(s.facts.most_bytes, s.bytes);
    ++live;
    return at;
}

void* heap_allocate(std::size_t bytes) {
    // Plain malloc: on huge pages (advised) the 98.5 M-point sphere peaked 0.29 GB
    // higher.
    if (void* p = std::malloc(std::max<std::size_t>(bytes, 1))) return p;
    throw std::bad_alloc();
}

void advise_huge_pages(void* p, std::size_t bytes) noexcept {
    if (spilled(p)) return;
    constexpr std::uintptr_t kHugePage = std::uintptr_t(2) << 20;
    const std::uintptr_t begin = (reinterpret_cast<std::uintptr_t>(p) + kHugePage - 1) & ~(kHugePage - 1);
    const std::uintptr_t end = (reinterpret_cast<std::uintptr_t>(p) + bytes) & ~(kHugePage - 1);
    if (end > begin) ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);  // advice only
}

bool spill_release(void* p) noexcept {
    if (!p || live.load() == 0) return false;
    Spill& s = spill();
    Mapping gone{nullptr, 0};
    {
        std::lock_guard<std::mutex> hold(s.lock);
        const auto at = std::find_if(s.mappings.begin(), s.mappings.end(), [p](const Mapping& m) { return m.at == p; });
        if (at == s.mappings.end()) return false;
        gone = *at;
        s.bytes -= at->bytes;
        s.mappings.erase(at);
        --live;
    }
    ::munmap(gone.at, gone.bytes);
    return true;
}

bool spilled(const void* p) noexcept {
    if (!p || live.load() == 0) return false;
    Spill& s = spill();
    std::lock_guard<std::mutex> hold(s.lock);
    return std::any_of(s.mappings.begin(), s.mappings.end(), [p](const Mapping& m) { return m.at == p; });
}

bool spilled_any() noexcept { return live.load() > 0; }

std::size_t resident_but_spilled() {
    if (live.load() == 0) return resident_bytes();
    Spill& s = spill();
    std::size_t before = 0;
    {
        std::lock_guard<std::mutex> hold(s.lock);
        before = s.file_pages_before;
    }
    const Resident now = resident_now();
    return now.heap + std::min(now.file, before);
}

SpillFacts spill_facts() {
    Spill& s = spill();
    std::size_t read = 0, written = 0;
    storage_bytes(read, written);
    std::lock_guard<std::mutex> hold(s.lock);
    SpillFacts facts = s.facts;
    facts.read_bytes = read - std::min(read, s.read_before);
    facts.written_bytes = written - std::min(written, s.written_before);
    return facts;
}

}  // namespace snvr::detail
