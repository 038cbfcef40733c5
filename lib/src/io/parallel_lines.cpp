// The parts of parse_lines (parallel_lines.hpp) that do not depend on the format.
#include "io/parallel_lines.hpp"

#include <algorithm>
#include <string>

namespace snvr::detail {

std::size_t count_line_ends(std::string_view text, char end, int threads) {
    const std::size_t parts = std::size_t(thread_count(threads));
    const std::size_t part = text.size() / parts + 1;
    std::size_t count = 0;
#pragma omp parallel for num_threads(int(parts)) reduction(+ : count) if (text.size() >= (std::size_t(1) << 22))
    for (std::ptrdiff_t k = 0; k < std::ptrdiff_t(parts); ++k) {
        const std::size_t from = std::min(text.size(), std::size_t(k) * part);
        const std::size_t to = std::min(text.size(), from + part);
        count += std::size_t(std::count(text.data() + from, text.data() + to, end));
    }
    return count;
}

std::size_t line_number_at(const LineRegion& region, char end, std::size_t offset) {
    return region.lines_before + count_line_ends(region.text.substr(0, offset), end, 0) + 1;
}

std::size_t last_line_number(const LineRegion& region, char end) {
    const std::string_view text = region.text;
    const bool open_last = !text.empty() && text.back() != end;  // a last line without its end
    return region.lines_before + count_line_ends(text, end, 0) + (open_last ? 1 : 0);
}

std::size_t block_start(const LineRegion& region, char end, std::size_t block_bytes, std::size_t k, std::size_t blocks) {
    if (k == 0) return region.begin;
    if (k >= blocks) return region.text.size();
    // From the byte before the nominal start: a line ending just there starts the block there.
    const std::size_t found = region.text.find(end, region.begin + k * block_bytes - 1);
    return found == std::string_view::npos ? region.text.size() : found + 1;
}

bool append_block(ParsedBlock& block, std::uint64_t limit, PointArray<Float3>& out, LinesOutcome& outcome) {
    if (block.thrown) {
        outcome.thrown = block.thrown;
        return true;
    }
    const std::uint64_t before = out.size();
    const std::size_t take = std::size_t(std::min<std::uint64_t>(block.points.size(), limit - before));
    if (block.refused < take && outcome.refused == std::numeric_limits<std::uint64_t>::max()) {
        outcome.refused = before + block.refused;
        outcome.refused_point = block.refused_point;
    }
    try {
        out.insert(out.end(), block.points.begin(), block.points.begin() + std::ptrdiff_t(take));
    } catch (...) {
        outcome.thrown = std::current_exception();
        return true;
    }
    if (out.size() == limit) return true;  // what follows belongs to another element
    if (block.failure == kNoFailure) return false;
    outcome.failure = block.failure;
    outcome.failure_item = out.size();
    outcome.what = std::move(block.what);
    return true;
}

void raise_outcome(const LinesOutcome& outcome, const LineRegion& region, char end, std::uint64_t points,
                   const std::string& item_prefix, const Vec3& origin, const std::string& path) {
    if (outcome.thrown) std::rethrow_exception(outcome.thrown);
    if (outcome.failure != kNoFailure)
        throw InputError(path + ": line " + std::to_string(line_number_at(region, end, outcome.failure)) + ": " +
                         item_prefix + outcome.what);
    if (region.limit != std::numeric_limits<std::uint64_t>::max() && points < region.limit)
        throw InputError(path + ": " + ends_early(region.limit, points, region.items) + " (line " +
                         std::to_string(last_line_number(region, end)) + ")");
    if (outcome.refused != std::numeric_limits<std::uint64_t>::max())
        refuse_point(path, outcome.refused, outcome.refused_point, origin);
}

}  // namespace snvr::detail
