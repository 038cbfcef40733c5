// Text point formats parsed in parallel: the lines from a starting byte on are cut into
// blocks at line ends, each block parsed by one thread into floats about the origin, and
// the blocks' points appended in file order (so memory holds the points once, plus a
// block's worth per thread). Line numbers are counted only for a message.
//
// A format gives a line parser: LineKind operator()(std::string_view line, Vec3& point,
// std::string& what) const, which reads one line (its end removed) and says whether it
// held a point (stored in `point`), nothing, or an error (described in `what`); and
// std::string item_prefix(std::uint64_t item) const, put before `what` in the message
// (a PLY's "vertex 3: ", or nothing), item being the points before the failing line.
#pragma once
#include <atomic>
#include <cstdint>
#include <cstring>
#include <exception>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "io/float_origin.hpp"
#include "io/parallel_records.hpp"
#include "io/point_readers.hpp"
#include "io/text_scan.hpp"
#include "snvr/error.hpp"

namespace snvr::detail {

enum class LineKind { Skip, Point, Error };

// The lines to parse: `text`'s from byte `begin` (a line's start) on, numbered after
// `lines_before` (a PLY's header lines). With a limit the points end after that many (a
// PLY or OFF vertex count: other elements follow) and fewer is an error counting `items`.
struct LineRegion {
    std::string_view text;
    std::size_t begin = 0;
    std::size_t lines_before = 0;
    std::uint64_t limit = std::numeric_limits<std::uint64_t>::max();
    std::string items = "vertices";
};

constexpr std::size_t kNoFailure = std::string_view::npos;

// How many `end` bytes the text holds, counted by `threads` threads.
std::size_t count_line_ends(std::string_view text, char end, int threads);

// The number, in the file, of the line that starts at byte `offset` of region.text.
std::size_t line_number_at(const LineRegion& region, char end, std::size_t offset);

// The number of the file's last line (the one a LineScanner stops after).
std::size_t last_line_number(const LineRegion& region, char end);

// Where block k of `blocks` starts: just after the first line end at or after its
// nominal start, begin + k * block_bytes (the text's end for k == blocks).
std::size_t block_start(const LineRegion& region, char end, std::size_t block_bytes, std::size_t k, std::size_t blocks);

// Parses the lines of text[from, to) (each ended by `end`, a trailing '\r' removed) and
// calls sink(point) for each point until it returns false. Returns the offset of the
// first line the parser refused (its reason in `what`), or kNoFailure.
template <class Parser, class Sink>
std::size_t for_each_line_point(std::string_view text, std::size_t from, std::size_t to, char end, const Parser& parser,
                                Sink&& sink, std::string& what) {
    const char* base = text.data();
    Vec3 point{};
    for (std::size_t pos = from; pos < to;) {
        const void* hit = std::memchr(base + pos, end, to - pos);
        const std::size_t stop = hit ? std::size_t(static_cast<const char*>(hit) - base) : to;
        std::string_view line(base + pos, stop - pos);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        switch (parser(line, point, what)) {
            case LineKind::Skip: break;
            case LineKind::Point:
                if (!sink(point)) return kNoFailure;
                break;
            case LineKind::Error: return pos;
        }
        pos = stop + 1;
    }
    return kNoFailure;
}

// One block's outcome, kept by the thread that parsed it until its turn to append.
struct ParsedBlock {
    std::vector<Float3> points;
    std::size_t failure = kNoFailure;  // offset of the line the parser refused
    std::string what;
    std::size_t refused = kNoFailure;  // the first point to_float could not hold (index in the block)
    Vec3 refused_point{};
    std::exception_ptr thrown;
};

// What the appends in file order found first.
struct LinesOutcome {
    std::size_t failure = kNoFailure;
    std::uint64_t failure_item = 0;  // points before the failing line
    std::string what;
    std::uint64_t refused = std::numeric_limits<std::uint64_t>::max();
    Vec3 refused_point{};
    std::exception_ptr thrown;
};

// Appends a parsed block (the next in file order) to `out`, up to the limit; true when
// no further block can matter (the limit is reached, or a failure or throw recorded).
bool append_block(ParsedBlock& block, std::uint64_t limit, PointArray<Float3>& out, LinesOutcome& outcome);

// Throws what the outcome holds, in the order a serial reader meets it: an exception, a
// line refused, too few points for the limit, a point floats cannot hold.
void raise_outcome(const LinesOutcome& outcome, const LineRegion& region, char end, std::uint64_t points,
                   const std::string& item_prefix, const Vec3& origin, const std::string& path);

// The points of the region's lines, in order, as floats about an origin chosen from the
// first of them (FloatPoints); throws as raise_outcome.
template <class Parser>
FloatPoints parse_lines(const LineRegion& region, const Parser& parser, const std::string& path,
                        const ParseOptions& options) {
    FloatPoints result;
    if (region.limit == 0) return result;
    const std::string_view text = region.text;
    const char end = line_end_of(text);

    // The origin, from the first points (parsed again below: a few thousand lines).
    SampleBox sample;
    std::string ignored;
    std::uint64_t sampled = 0;
    const std::uint64_t wanted = std::min<std::uint64_t>(options.origin_sample, region.limit);
    if (wanted > 0)
        for_each_line_point(text, region.begin, text.size(), end, parser,
                            [&](const Vec3& p) {
                                sample.add(p);
                                return ++sampled < wanted;
                            },
                            ignored);
    result.origin = choose_origin(sample);

    // Room for one point a line, reserved (not touched) so that appends never move them.
    const std::uint64_t lines = count_line_ends(text.substr(region.begin), end, options.threads) + 1;
    result.xyz.reserve(std::size_t(std::min(region.limit, lines)));

    const std::size_t block_bytes = std::max<std::size_t>(options.text_block, 1);
    const std::size_t span = text.size() - region.begin;
    const std::size_t blocks = span / block_bytes + (span % block_bytes != 0);
    LinesOutcome outcome;
    std::atomic<bool> finished{false};
#pragma omp parallel num_threads(thread_count(options.threads)) if (blocks > 1)
    {
        ParsedBlock block;
#pragma omp for ordered schedule(dynamic, 1)
        for (std::ptrdiff_t k = 0; k < std::ptrdiff_t(blocks); ++k) {
            block.points.clear();
            block.failure = block.refused = kNoFailure;
            block.thrown = nullptr;
            if (!finished.load(std::memory_order_relaxed)) {
                try {
                    const std::size_t from = block_start(region, end, block_bytes, std::size_t(k), blocks);
                    const std::size_t to = block_start(region, end, block_bytes, std::size_t(k) + 1, blocks);
                    const auto keep = [&](const Vec3& p) {
                        Float3 q;
                        if (!to_float(p, result.origin, q) && block.refused == kNoFailure) {
                            block.refused = block.points.size();
                            block.refused_point = p;
                        }
                        block.points.push_back(q);
                        return true;
                    };
                    block.failure = for_each_line_point(text, from, to, end, parser, keep, block.what);
                } catch (...) {
                    block.thrown = std::current_exception();
                }
            }
#pragma omp ordered
            {
                if (!finished.load(std::memory_order_relaxed) && append_block(block, region.limit, result.xyz, outcome))
                    finished.store(true, std::memory_order_relaxed);
            }
        }
    }
    const std::uint64_t points = result.xyz.size();
    const bool failed = outcome.failure != kNoFailure;
    raise_outcome(outcome, region, end, points, failed ? parser.item_prefix(outcome.failure_item) : std::string(),
                  result.origin, path);
    return result;
}

}  // namespace snvr::detail
