// The points' arrays beyond a budget kept in files (lib/src/spilled_memory.hpp): under a
// scope, a large PointArray is a mapping of an unnamed file in the folder, its values
// kept while its pages are given back to hold the budget; small ones, and any outside a
// scope, are the heap's; nothing is left in the folder; a folder that cannot hold them is
// an error naming it.
#include <doctest/doctest.h>

#include <chrono>
#include <cstdint>
#include <string>
#include <thread>

#include "process_limits.hpp"
#include "snvr/error.hpp"
#include "spilled_memory.hpp"
#include "temp_dir.hpp"

using namespace snvr;
using snvr::detail::PointArray;

namespace {
constexpr std::size_t kMiB = std::size_t(1) << 20;
}

TEST_CASE("arrays beyond the budget: in a file, their values kept while the pages go back; none left after") {
    const testing::TempDir folder("spill");
    {
        const PointArray<std::uint64_t> before(4 * kMiB);  // no scope: the heap's
        CHECK(!detail::spilled(before.data()));
    }
    const std::size_t budget = 64 * kMiB;
    const detail::SpillScope scope(budget, 0, folder.path.string());
    const detail::SpillScope nested(8 * kMiB, 0, "/nonexistent");  // the outermost stays in force
    PointArray<std::uint64_t> small(budget / 16 / 8 - 1);  // under a sixteenth: the heap's
    CHECK(!detail::spilled(small.data()));
    // Three times the budget, written and read again: the governor gives pages back.
    PointArray<std::uint64_t> large(3 * budget / 8);
    REQUIRE(detail::spilled(large.data()));
    CHECK(folder.entries() == 0);  // unnamed
    for (std::size_t i = 0; i < large.size(); ++i) large[i] = i * 7 + 3;
    for (int wait = 0; wait < 200 && detail::spill_facts().trims == 0; ++wait)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    CHECK(detail::spill_facts().trims > 0);
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < large.size(); ++i) wrong += large[i] != i * 7 + 3;
    CHECK(wrong == 0);
    // Grown, copied, freed: each large array its own file, the copy's values the same.
    PointArray<std::uint64_t> copy = large;
    CHECK(detail::spilled(copy.data()));
    CHECK(copy == large);
    CHECK(detail::spill_facts().arrays >= 2);
    CHECK(detail::spill_facts().most_bytes >= 2 * large.size() * sizeof(std::uint64_t));
    CHECK(detail::spill_facts().folder == folder.path.string());
    const void* was = copy.data();
    PointArray<std::uint64_t>().swap(copy);
    CHECK(!detail::spilled(was));
    // The heap's share of the resident memory leaves the spilled pages out.
    CHECK(detail::resident_but_spilled() <= detail::resident_bytes());
    CHECK(folder.entries() == 0);
}

TEST_CASE("a temporary folder that cannot hold the arrays: an error naming it") {
    const detail::SpillScope scope(64 * kMiB, 0, "/nonexistent-snvr-folder");
    std::string what;
    try {
        PointArray<std::uint64_t> large(2 * kMiB);
    } catch (const ResourceError& e) {
        what = e.what();
    }
    CAPTURE(what);
    CHECK(what.find("/nonexistent-snvr-folder") != std::string::npos);
    CHECK(what.find("--temp-dir") != std::string::npos);
}
