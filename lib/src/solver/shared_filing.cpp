// The points' tree filed by every process (shared_filing.hpp).
#include "solver/shared_filing.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <exception>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "geometry/neighbour_counts.hpp"
#include "geometry/point_clusters.hpp"
#include "geometry/point_tree.hpp"
#include "io/point_readers.hpp"
#include "process_limits.hpp"
#include "solver/sent_arrays.hpp"
#include "snvr/error.hpp"

namespace snvr::detail {
namespace {

using Filing = PointTree::Filing;

// What the first tells each other process, in this order: the points in all (0: none
// filed together), the filing's cell bits, its frame (low corner, scale), the origin, and
// the part of the input given (its first index, its count).
using Figures = std::array<double, 11>;

// Process p's part of the input: an equal run of it.
std::size_t part_begin(std::size_t n, int p, int processes) { return n * std::size_t(p) / std::size_t(processes); }

// A process's part sorted by coarse cell, and where each cell begins in it.
struct SortedPart {
    PointArray<Vec3f> xyz;
    PointArray<std::uint32_t> input;
    std::vector<std::uint32_t> cell_start;
};

// The cells each process files: ranges of about equal points, by the counts summed over
// all (range q is cells [first[q], first[q + 1])); and where each cell begins in the tree.
struct CellRanges {
    std::vector<std::size_t> first;
    std::vector<std::uint32_t> start;  // cells + 1 of them
};
CellRanges cell_ranges(TileScheduler& on, const SortedPart& part, std::size_t cells, std::size_t n) {
    std::vector<std::uint64_t> counts(cells);
    for (std::size_t c = 0; c < cells; ++c) counts[c] = part.cell_start[c + 1] - part.cell_start[c];
    on.sum(counts);
    CellRanges r;
    r.start.assign(cells + 1, 0);
    for (std::size_t c = 0; c < cells; ++c) r.start[c + 1] = r.start[c] + std::uint32_t(counts[c]);
    if (r.start[cells] != n) throw Error("the processes' parts of the points do not add up");
    const int processes = on.processes();
    r.first.assign(std::size_t(processes) + 1, cells);
    r.first[0] = 0;
    for (int q = 1; q < processes; ++q)
        r.first[std::size_t(q)] = std::size_t(
            std::lower_bound(r.start.begin(), r.start.end() - 1, std::uint32_t(part_begin(n, q, processes))) - r.start.begin());
    return r;
}

// This process's range of cells filled from every process's part (its own and those
// received), each cell's points in process order, so in input order; then its cells
// sorted by key. The range goes at the start of xyz, input and keys: on the first they
// are the whole tree's arrays (its range comes first), on the others the range alone.
void file_range(TileScheduler& on, const Filing& filing, SortedPart& mine, const CellRanges& ranges, PointArray<Vec3f>& xyz,
                PointArray<std::uint32_t>& input, PointArray<std::uint64_t>& keys) {
    const int me = on.rank(), processes = on.processes();
    const std::size_t lo = ranges.first[std::size_t(me)], hi = ranges.first[std::size_t(me) + 1];
    const std::uint32_t base = ranges.start[lo];
    // What every process's part holds of this range: its cells' counts and points.
    std::vector<std::vector<std::uint32_t>> counts(static_cast<std::size_t>(processes));
    std::vector<SortedPart> parts(static_cast<std::size_t>(processes));
    exchange_pairwise(
        on,
        [&](int q) {
            const std::size_t qlo = ranges.first[std::size_t(q)], qhi = ranges.first[std::size_t(q) + 1];
            const std::uint32_t b = mine.cell_start[qlo], e = mine.cell_start[qhi];
            std::vector<std::uint32_t> c(qhi - qlo);
            for (std::size_t k = qlo; k < qhi; ++k) c[k - qlo] = mine.cell_start[k + 1] - mine.cell_start[k];
            send_array(on, q, c.data(), c.size());
            send_array(on, q, mine.xyz.data() + b, e - b);
            send_array(on, q, mine.input.data() + b, e - b);
        },
        [&](int q) {
            SortedPart& got = parts[std::size_t(q)];
            receive_array(on, q, counts[std::size_t(q)]);
            if (counts[std::size_t(q)].size() != hi - lo) throw Error("a filing's counts are not the range's");
            receive_array(on, q, got.xyz);
            receive_array(on, q, got.input);
            if (got.input.size() != got.xyz.size()) throw Error("a filing's points are not whole");
        });
    {
        std::vector<std::uint32_t>& own = counts[std::size_t(me)];
        own.resize(hi - lo);
        for (std::size_t k = lo; k < hi; ++k) own[k - lo] = mine.cell_start[k + 1] - mine.cell_start[k];
    }
    const std::size_t range = ranges.start[hi] - base;
    if (xyz.size() < range) {
        xyz.resize(range);
        input.resize(range);
    }
    std::vector<std::size_t> next(static_cast<std::size_t>(processes), 0);
    next[std::size_t(me)] = mine.cell_start[lo];
    for (std::size_t c = lo; c < hi; ++c) {
        std::size_t to = ranges.start[c] - base;
        for (int p = 0; p < processes; ++p) {
            const std::uint32_t k = counts[std::size_t(p)][c - lo];
            if (k == 0) continue;
            const SortedPart& from = p == me ? mine : parts[std::size_t(p)];
            std::size_t& f = next[std::size_t(p)];
            if (f + k > from.xyz.size()) throw Error("a filing's points are fewer than its counts");
            std::copy_n(from.xyz.begin() + std::ptrdiff_t(f), k, xyz.begin() + std::ptrdiff_t(to));
            std::copy_n(from.input.begin() + std::ptrdiff_t(f), k, input.begin() + std::ptrdiff_t(to));
            f += k;
            to += k;
        }
    }
    mine = SortedPart();
    parts.clear();
    keys.resize(xyz.size());  // the whole tree's on the first
    std::vector<std::uint32_t> start(hi - lo + 1);
    for (std::size_t c = lo; c <= hi; ++c) start[c - lo] = ranges.start[c] - base;
    filing.sort_cells(start.data(), hi - lo, xyz.data(), input.data(), keys.data());
}

// A part of the input sorted by coarse cell.
SortedPart sorted_part(const Filing& filing, const Vec3f* p, std::size_t n, std::size_t first_input) {
    SortedPart part;
    part.xyz.resize(n);
    part.input.resize(n);
    part.cell_start.resize(filing.cells() + 1);
    filing.by_cell(p, n, std::uint32_t(first_input), nullptr, part.xyz.data(), part.input.data(), part.cell_start.data());
    return part;
}

// Another process, its range filed, before it builds its range's tree: the nodes the
// first asks of it, those within its range (PointTree::Grafts), their subtrees' sizes then
// their nodes. (Taken from its built tree, they came 0.2 s later.)
void answer_grafts(TileScheduler& on, const PointArray<std::uint64_t>& keys, const PointArray<Vec3f>& xyz) {
    std::vector<PointTree::Asked> asked;
    receive_array(on, 0, asked);
    const PointTree::Grafted grafted = PointTree::subtrees(keys.data(), xyz, asked);
    send_array(on, 0, grafted.sizes.data(), grafted.sizes.size());
    send_array(on, 0, grafted.nodes.data(), grafted.nodes.size());
}

// At the first: the grafts its tree takes from the others (their nodes of their ranges).
PointTree::Grafts grafts_from(TileScheduler& on, std::vector<std::size_t> bounds) {
    PointTree::Grafts grafts;
    grafts.bounds = std::move(bounds);
    grafts.ask = [&on](int range, const std::vector<PointTree::Asked>& asked) {
        send_array(on, range, asked.data(), asked.size());
    };
    grafts.take = [&on](int range) {
        PointTree::Grafted got;
        receive_array(on, range, got.sizes);
        receive_array(on, range, got.nodes);
        return got;
    };
    return grafts;
}

// From each process's part sorted by cell on: the ranges filed, the first taking them
// back in order into the tree (its ranges' bounds in PointTree::shared_ranges); each
// other keeping its own range as a tree of its own (for the outlier rules' counts and
// the check's depths), the first taking the nodes within each other's range from it
// rather than build them: on P processes it builds a P-th of them and copies the rest (on
// two, 0.74 s where building them all took 0.78 on the 50 M-point city block).
KeptRange file_parts(TileScheduler& on, const Filing& filing, SortedPart mine, std::size_t n, const Vec3& origin) {
    require_point_count(n);
    const CellRanges ranges = cell_ranges(on, mine, filing.cells(), n);
    PointArray<Vec3f> xyz;
    PointArray<std::uint32_t> input;
    PointArray<std::uint64_t> keys;
    if (on.rank() != 0) {
        file_range(on, filing, mine, ranges, xyz, input, keys);
        send_array(on, 0, xyz.data(), xyz.size());
        send_array(on, 0, input.data(), input.size());
        send_array(on, 0, keys.data(), keys.size());
        const int me = on.rank(), shift = filing.shift();
        answer_grafts(on, keys, xyz);
        auto tree = std::make_unique<PointTree>(std::move(xyz), std::move(input), origin, filing.frame, keys.data());
        return {std::move(tree), n, 0, std::uint64_t(ranges.first[std::size_t(me)]) << shift,
                std::uint64_t(ranges.first[std::size_t(me) + 1]) << shift};
    }
    // The whole tree's arrays: this process's range first, then each other's in turn.
    xyz.resize(n);
    input.resize(n);
    file_range(on, filing, mine, ranges, xyz, input, keys);
    for (int q = 1; q < on.processes(); ++q) {
        const std::size_t b = ranges.start[ranges.first[std::size_t(q)]];
        const std::size_t e = ranges.start[ranges.first[std::size_t(q) + 1]];
        receive_into(on, q, xyz.data() + b, e - b);
        receive_into(on, q, input.data() + b, e - b);
        receive_into(on, q, keys.data() + b, e - b);
    }
    std::vector<std::size_t> bounds;
    for (int q = 0; q <= on.processes(); ++q) bounds.push_back(ranges.start[ranges.first[std::size_t(q)]]);
    const PointTree::Grafts grafts = grafts_from(on, bounds);
    KeptRange whole{std::make_unique<PointTree>(std::move(xyz), std::move(input), origin, filing.frame, keys.data(), &grafts),
                    n, 0};
    whole.tree->shared_ranges = std::move(bounds);
    whole.tree->numbered_whole();  // each part numbered by its place in the input
    return whole;
}

// Another process, its range kept: the first's outlier rules ask it, in turn, which of
// its points have fewer than `need` points within a reach among its range (the first
// decides those over the whole cloud; the rest have as many there, so in the whole too),
// or its range's own clusters at a link (the first links the rest: cluster_roots), with
// the points scaled as the first's were since; between the questions the first
// tells it the points it drops, which it drops too, so that its range stays the first's;
// until it says there is nothing more. The places named are within the range as it is,
// which is kept for the check (the first drops no point after its outlier rules).
constexpr double kCountsDone = -1, kCountsDropped = -2, kLinkAsked = -3, kStraysAsked = -4;
void answer_counts(TileScheduler& on, KeptRange& range) {
    std::vector<std::uint64_t> gone;  // a bit an input index: dropped by the first
    for (;;) {
        std::vector<double> asked;
        receive_array(on, 0, asked);
        if (asked.size() < 2 || asked[0] == kCountsDone) break;
        PointTree& t = *range.tree;
        if (asked[0] == kCountsDropped) {
            std::vector<std::uint32_t> dropped;
            receive_array(on, 0, dropped);
            if (gone.empty()) gone.assign(range.whole / 64 + 1, 0);
            for (const std::uint32_t i : dropped) {
                if (i >= range.whole) throw Error("the first process dropped a point the cloud does not have");
                gone[i / 64] |= std::uint64_t(1) << (i % 64);
            }
            std::vector<std::uint8_t> keep(t.size());
            for (std::size_t k = 0; k < t.size(); ++k) keep[k] = !(gone[t.input[k] / 64] >> (t.input[k] % 64) & 1);
            if (std::find(keep.begin(), keep.end(), 0) != keep.end()) t.keep_only(keep);
            continue;
        }
        for (std::size_t k = 2 + range.scaled; k < asked.size(); ++k, ++range.scaled) t.scale(asked[k]);
        if (asked[0] == kLinkAsked) {
            const PointArray<std::uint32_t> roots = cluster_roots(t, asked[1]);
            send_array(on, 0, roots.data(), roots.size());
            continue;
        }
        if (asked[0] == kStraysAsked) {
            std::vector<double> rule;
            std::vector<std::uint32_t> lonely;
            receive_array(on, 0, rule);
            receive_array(on, 0, lonely);
            if (rule.size() != 3) throw Error("the first process asked the stray rule without its settings");
            StraySettings s;
            s.neighbours = std::size_t(rule[0]);
            s.plane_sigmas = rule[1];
            s.plane_reach = rule[2];
            std::vector<std::uint8_t> alone(t.size(), 0);
            for (const std::uint32_t k : lonely) {
                if (k >= t.size()) throw Error("the first process named a lonely point beyond this range");
                alone[k] = 1;
            }
            // Each scaling since the filing may round a point across a cell's edge.
            const RangeStrays got = range_strays(t, s, alone, range.keys_lo, range.keys_hi, 2 + int(range.scaled));
            send_array(on, 0, got.strays.data(), got.strays.size());
            send_array(on, 0, got.undecided.data(), got.undecided.size());
            continue;
        }
        if (!(asked[0] >= 0)) throw Error("the first process asked the neighbours' counts at no reach");
        const std::vector<std::uint8_t> few = points_short_of(t, asked[0], std::size_t(asked[1]));
        std::vector<std::uint32_t> places;
        for (std::size_t k = 0; k < few.size(); ++k)
            if (few[k]) places.push_back(std::uint32_t(k));
        send_array(on, 0, places.data(), places.size());
    }
    // No point is dropped from here on and the check names points by place: the input
    // indices go (4 bytes a point held through the tiles).
    PointArray<std::uint32_t>().swap(range.tree->input);
}

// Every process, its part read from the file: the filing the whole input would have (its
// box the least and greatest over the parts), agreed with the others, which must have
// read the same file (the same count and origin).
Filing agreed_filing(TileScheduler& on, const PointArray<Vec3f>& part, const Vec3& origin, std::size_t n) {
    Vec3f lo, hi;
    PointTree::box_of(part, lo, hi);
    const double in_files = spilled(part.data()) ? 1 : 0;
    std::vector<double> least{lo[0], lo[1], lo[2], -double(hi[0]), -double(hi[1]), -double(hi[2]), -in_files,
                              double(n), -double(n), origin[0], -origin[0], origin[1], -origin[1], origin[2], -origin[2]};
    on.least(least);
    for (int k = 7; k < 15; k += 2)
        if (least[std::size_t(k)] != -least[std::size_t(k) + 1])
            throw Error("the processes read different points (the input changed while they read it?)");
    return PointTree::filing_for({float(least[0]), float(least[1]), float(least[2])},
                                 {float(-least[3]), float(-least[4]), float(-least[5])}, n, least[6] < 0);
}

}  // namespace

PointTree& kept_as_first(KeptRange* kept, std::size_t size, const std::vector<double>& scaled, const Vec3& origin) {
    if (!kept || !kept->tree || kept->tree->size() != size)
        throw Error("the points this process kept are not its range of the first's (" +
                    std::to_string(kept && kept->tree ? kept->tree->size() : 0) + " where the first has " +
                    std::to_string(size) + ")");
    PointTree& tree = *kept->tree;
    for (; kept->scaled < scaled.size(); ++kept->scaled) tree.scale(scaled[kept->scaled]);
    tree.origin = origin;
    return tree;
}

void no_shared_filing(TileScheduler& on) {
    const Figures none{};
    for (int p = 1; p < on.processes(); ++p) send_array(on, p, none.data(), none.size());
}

PointCloud cloud_filed_with(TileScheduler& on, PointArray<Vec3f>&& coordinates, const Vec3& origin) {
    const int processes = on.processes();
    if (processes < 2 || coordinates.size() < kSharedFilingPoints) {
        no_shared_filing(on);
        return cloud_of(std::move(coordinates), origin);
    }
    return cloud_filed(std::move(coordinates), origin, [&on, processes](PointArray<Vec3f>&& all, const Vec3& at) {
        settle_threads();
        const std::size_t n = all.size();
        const Filing filing = PointTree::filing_of(all);
        for (int p = 1; p < processes; ++p) {
            const std::size_t first = part_begin(n, p, processes), count = part_begin(n, p + 1, processes) - first;
            const Figures figures{double(n),  double(filing.bits), filing.frame.lo[0], filing.frame.lo[1],
                                  filing.frame.lo[2], filing.frame.scale, at[0], at[1], at[2], double(first),
                                  double(count)};
            send_array(on, p, figures.data(), figures.size());
            send_array(on, p, all.data() + first, count);
        }
        SortedPart mine = sorted_part(filing, all.data(), part_begin(n, 1, processes), 0);
        PointArray<Vec3f>().swap(all);
        return std::move(file_parts(on, filing, std::move(mine), n, at).tree);
    });
}

std::shared_ptr<KeptRange> file_for_root(TileScheduler& on) {
    settle_threads();
    std::vector<double> figures;
    receive_array(on, 0, figures);
    if (figures.size() != Figures().size()) throw Error("the filing's figures from the first process are not whole");
    const std::size_t n = std::size_t(figures[0]);
    if (n == 0) return nullptr;
    Filing filing;
    filing.bits = int(figures[1]);
    filing.frame = PointTree::Frame::of(&figures[2]);
    const Vec3 origin{figures[6], figures[7], figures[8]};
    PointArray<Vec3f> given;
    receive_array(on, 0, given);
    if (given.size() != std::size_t(figures[10])) throw Error("the first process's points for filing are not whole");
    SortedPart mine = sorted_part(filing, given.data(), given.size(), std::size_t(figures[9]));
    PointArray<Vec3f>().swap(given);
    auto kept = std::make_shared<KeptRange>(file_parts(on, filing, std::move(mine), n, origin));
    answer_counts(on, *kept);
    return kept;
}

std::size_t parts_to_read(TileScheduler* on, const std::string& path) {
    if (!on || on->processes() < 2) return 0;
    // Every process must see the same file so: one that cannot (not there, not readable)
    // has the first give it its part instead (its own errors come from the first's read).
    std::size_t n = 0;
    try {
        n = points_in_parts(path);
    } catch (const std::exception&) {
        n = 0;
    }
    std::vector<double> least{double(n), -double(n)};
    on->least(least);
    return least[0] == -least[1] && n >= kSharedFilingPoints ? n : 0;
}

FloatPoints read_my_part(TileScheduler& on, const std::string& path, std::size_t n, const std::string& temp_folder) {
    ParseOptions options;
    options.part = std::size_t(on.rank());
    options.parts = std::size_t(on.processes());
    FloatPoints part = read_float_points(path, options, temp_folder);
    if (part.first != n * options.part / options.parts || part.first + part.xyz.size() != n * (options.part + 1) / options.parts)
        throw Error(path + ": the part read is not this process's (the input changed while it was read?)");
    return part;
}

PointCloud cloud_read_with(TileScheduler& on, FloatPoints&& part, std::size_t n) {
    return cloud_filed(std::move(part.xyz), part.origin, [&on, n](PointArray<Vec3f>&& mine, const Vec3& at) {
        settle_threads();
        const Filing filing = agreed_filing(on, mine, at, n);
        SortedPart sorted = sorted_part(filing, mine.data(), mine.size(), 0);
        PointArray<Vec3f>().swap(mine);
        return std::move(file_parts(on, filing, std::move(sorted), n, at).tree);
    });
}

std::shared_ptr<KeptRange> file_part_for_root(TileScheduler& on, FloatPoints&& part, std::size_t n) {
    settle_threads();
    const Filing filing = agreed_filing(on, part.xyz, part.origin, n);
    SortedPart sorted = sorted_part(filing, part.xyz.data(), part.xyz.size(), part.first);
    PointArray<Vec3f>().swap(part.xyz);
    auto kept = std::make_shared<KeptRange>(file_parts(on, filing, std::move(sorted), n, part.origin));
    answer_counts(on, *kept);
    return kept;
}

NeighbourCountsShared::NeighbourCountsShared(TileScheduler* on, PointCloud& points)
    : on_(on && !tree_of(points).shared_ranges.empty() ? on : nullptr), tree_(CloudAccess::tree_of(points).get()) {
    if (!on_) return;
    tree_->tell_dropped = [on](const std::vector<std::uint32_t>& dropped) {
        const std::vector<double> told{kCountsDropped, 0};
        for (int p = 1; p < on->processes(); ++p) {
            send_array(*on, p, told.data(), told.size());
            send_array(*on, p, dropped.data(), dropped.size());
        }
    };
}

NeighbourCountsShared::~NeighbourCountsShared() {
    if (!on_) return;
    // The others keep their ranges for the check; a point dropped from here on gives them up.
    tree_->tell_dropped = nullptr;
    const std::vector<double> done{kCountsDone, 0};
    for (int p = 1; p < on_->processes(); ++p) send_array(*on_, p, done.data(), done.size());
}

RootsOf NeighbourCountsShared::roots_of() {
    if (!on_) return nullptr;
    return [this](const PointTree& t, double link) {
        if (&t != tree_ || t.shared_ranges.size() != std::size_t(on_->processes()) + 1)
            return cluster_roots(t, link);  // not the points filed together
        std::vector<double> ask{kLinkAsked, link};
        ask.insert(ask.end(), t.scaled_since.begin(), t.scaled_since.end());
        for (int p = 1; p < on_->processes(); ++p) send_array(*on_, p, ask.data(), ask.size());
        return cluster_roots(t, link, t.shared_ranges, [this](int p) {
            PointArray<std::uint32_t> theirs;
            receive_array(*on_, p, theirs);
            return theirs;
        });
    };
}

AskStrays NeighbourCountsShared::strays_of() {
    if (!on_) return nullptr;
    return [this](const PointTree& t, const StraySettings& s, const std::vector<std::uint8_t>& alone) {
        const int processes = on_->processes();
        if (&t != tree_ || t.shared_ranges.size() != std::size_t(processes) + 1)
            return StraysElsewhere{t.size(), nullptr};  // not the points filed together
        std::vector<double> ask{kStraysAsked, 0};
        ask.insert(ask.end(), t.scaled_since.begin(), t.scaled_since.end());
        const std::vector<double> rule{double(s.neighbours), s.plane_sigmas, s.plane_reach};
        for (int p = 1; p < processes; ++p) {
            const std::size_t begin = t.shared_ranges[std::size_t(p)], end = t.shared_ranges[std::size_t(p) + 1];
            std::vector<std::uint32_t> lonely;
            for (std::size_t k = begin; k < end; ++k)
                if (alone[k]) lonely.push_back(std::uint32_t(k - begin));
            send_array(*on_, p, ask.data(), ask.size());
            send_array(*on_, p, rule.data(), rule.size());
            send_array(*on_, p, lonely.data(), lonely.size());
        }
        StraysElsewhere elsewhere{t.shared_end(), nullptr};
        elsewhere.collect = [this, &t, processes](std::vector<std::uint8_t>& stray, std::vector<std::uint32_t>& undecided) {
            for (int p = 1; p < processes; ++p) {
                const std::size_t begin = t.shared_ranges[std::size_t(p)], end = t.shared_ranges[std::size_t(p) + 1];
                std::vector<std::uint32_t> strays, unsure;
                receive_array(*on_, p, strays);
                receive_array(*on_, p, unsure);
                for (const auto* named : {&strays, &unsure})
                    for (const std::uint32_t k : *named)
                        if (begin + k >= end)
                            throw Error("process " + std::to_string(p) + " named a point its range does not have");
                for (const std::uint32_t k : strays) stray[begin + k] = 1;
                for (const std::uint32_t k : unsure) undecided.push_back(std::uint32_t(begin + k));
            }
        };
        return elsewhere;
    };
}

ShortOf NeighbourCountsShared::short_of() {
    if (!on_) return nullptr;
    return [this](const PointTree& t, double r2, std::size_t need) {
        if (&t != tree_ || t.shared_ranges.size() != std::size_t(on_->processes()) + 1)
            return points_short_of(t, r2, need);  // not the points filed together
        std::vector<double> ask{r2, double(need)};
        ask.insert(ask.end(), t.scaled_since.begin(), t.scaled_since.end());
        for (int p = 1; p < on_->processes(); ++p) send_array(*on_, p, ask.data(), ask.size());
        std::vector<std::uint8_t> few = points_short_of(t, r2, need, t.shared_end());
        for (int p = 1; p < on_->processes(); ++p) {
            std::vector<std::uint32_t> places;
            receive_array(*on_, p, places);
            const std::size_t begin = t.shared_ranges[std::size_t(p)], end = t.shared_ranges[std::size_t(p) + 1];
            const std::ptrdiff_t m = std::ptrdiff_t(places.size());
#pragma omp parallel for schedule(dynamic, 256)
            for (std::ptrdiff_t i = 0; i < m; ++i) {
                const std::size_t k = begin + places[std::size_t(i)];
                if (k >= end) continue;  // checked below, outside the threads
                few[k] = t.count_within(t.point(k), r2, need) < need;
            }
            for (const std::uint32_t k : places)
                if (begin + k >= end) throw Error("process " + std::to_string(p) + " named a point its range does not have");
        }
        return few;
    };
}

}  // namespace snvr::detail
