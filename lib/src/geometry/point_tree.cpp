// PointTree: the counting sort that files the points, the octree over their Morton
// order, and the queries every stage shares.
#include "geometry/point_tree.hpp"
#include "parallel_sizes.hpp"
#include "process_limits.hpp"
#include "snvr/error.hpp"
#include "threads_here.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>

namespace snvr::detail {
namespace {

constexpr int kBits = 21;  // per axis: a 63-bit key

// Each byte spread to every third bit of 24 (three lookups make a key's axis: the
// shifts and masks took a fifth of the tree's build).
struct SpreadTable {
    std::uint64_t byte[256];
    constexpr SpreadTable() : byte() {
        for (unsigned v = 0; v < 256; ++v)
            for (int b = 0; b < 8; ++b) byte[v] |= std::uint64_t((v >> b) & 1u) << (3 * b);
    }
};
constexpr SpreadTable kSpread;

// 21 bits spread to every third bit of 63.
std::uint64_t spread(std::uint32_t v) {
    return kSpread.byte[v & 255u] | kSpread.byte[(v >> 8) & 255u] << 24 | kSpread.byte[(v >> 16) & 31u] << 48;
}

unsigned digit(std::uint64_t key, int level) { return unsigned(key >> (3 * (kBits - 1 - level))) & 7u; }

// The smallest and largest of each axis, in parallel.
void float_box(const PointArray<Vec3f>& p, Vec3f& lo, Vec3f& hi) {
    const float inf = std::numeric_limits<float>::infinity();
    lo = {inf, inf, inf};
    hi = {-inf, -inf, -inf};
    const std::ptrdiff_t n = std::ptrdiff_t(p.size());
#pragma omp parallel if (n > kParallelCheapItems)
    {
        Vec3f l = lo, h = hi;
#pragma omp for schedule(static) nowait
        for (std::ptrdiff_t i = 0; i < n; ++i)
            for (int a = 0; a < 3; ++a) {
                l[a] = std::min(l[a], p[i][a]);
                h[a] = std::max(h[a], p[i][a]);
            }
#pragma omp critical(snvr_point_tree_box)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], l[a]);
            hi[a] = std::max(hi[a], h[a]);
        }
    }
}

// Sorts the few children of a node by their distance, nearest last (popped first).
struct Pending {
    std::uint32_t node;
    double dist_sq;
};
void sort_far_first(Pending* p, int n) {
    for (int i = 1; i < n; ++i)
        for (int j = i; j > 0 && p[j - 1].dist_sq < p[j].dist_sq; --j) std::swap(p[j - 1], p[j]);
}

using Keyed = std::pair<std::uint64_t, std::uint32_t>;

// Sorts n (key, index) pairs of `data` (indices ascending; the keys agree above bit
// `shift`), `scratch` as long: a stable counting sort by the next three digits, then each
// bucket by the same again where it is large (a dense scan's cell holds thousands of
// points, most of them in a few of its buckets), else by insertion (a point or two).
// Linear, where a comparison sort of hundreds took a sixth of the tree's build, and
// insertion into buckets of hundreds (98.5 M points) a fifth again.
void sort_keys(Keyed* data, Keyed* scratch, std::size_t n, int shift) {
    constexpr int kDigits = 9;
    constexpr std::size_t kLarge = 64;
    if (n < kLarge || shift < kDigits) {
        std::sort(data, data + n);
        return;
    }
    const int below = shift - kDigits;
    const auto digit = [below](const Keyed& x) { return unsigned((x.first >> below) & ((1u << kDigits) - 1)); };
    std::uint32_t start[(1u << kDigits) + 1] = {};
    for (std::size_t i = 0; i < n; ++i) ++start[digit(data[i]) + 1];
    for (unsigned d = 1; d <= (1u << kDigits); ++d) start[d] += start[d - 1];
    std::uint32_t next[1u << kDigits];
    std::copy(start, start + (1u << kDigits), next);
    for (std::size_t i = 0; i < n; ++i) scratch[next[digit(data[i])]++] = data[i];
    for (unsigned d = 0; d < (1u << kDigits); ++d) {
        Keyed* bucket = scratch + start[d];
        const std::size_t size = start[d + 1] - start[d];
        if (size >= kLarge) {
            sort_keys(bucket, data + start[d], size, below);
            continue;
        }
        for (std::size_t i = 1; i < size; ++i)
            for (std::size_t j = i; j > 0 && bucket[j] < bucket[j - 1]; --j) std::swap(bucket[j], bucket[j - 1]);
    }
    std::copy(scratch, scratch + n, data);
}

void sort_cell(std::vector<Keyed>& v, std::vector<Keyed>& spare, int shift) {
    spare.resize(v.size());
    sort_keys(v.data(), spare.data(), v.size(), shift);
}

}  // namespace

// The Morton frame: cubic cells of the points' box, 2^21 a side.
std::uint64_t PointTree::Frame::key(const Vec3f& p) const { return key(Vec3{double(p[0]), double(p[1]), double(p[2])}); }

std::uint64_t PointTree::Frame::key(const Vec3& p) const {
    std::uint64_t k = 0;
    for (int a = 0; a < 3; ++a) {
        const double t = (p[a] - lo[a]) * scale;
        const std::uint32_t c = t > 0 ? (t < double(1u << kBits) ? std::uint32_t(t) : (1u << kBits) - 1) : 0;
        k |= spread(c) << a;
    }
    return k;
}

PointTree::Filing PointTree::filing_of(const PointArray<Vec3f>& coordinates, const Frame* frame) {
    Vec3f lo{0, 0, 0}, hi{0, 0, 0};
    if (!frame) float_box(coordinates, lo, hi);
    Filing f = filing_for(lo, hi, coordinates.size(), spilled(coordinates.data()));
    if (frame) f.frame = *frame;
    return f;
}

PointTree::Filing PointTree::filing_for(const Vec3f& lo, const Vec3f& hi, std::size_t n, bool in_files) {
    const double extent = std::max({double(hi[0]) - lo[0], double(hi[1]) - lo[1], double(hi[2]) - lo[2]});
    Filing f;
    f.frame = {{lo[0], lo[1], lo[2]}, extent > 0 ? double(1u << kBits) / extent : 1.0};
    // About 8 points a coarse cell, at most 2^21 cells. Points in a file
    // (spilled_memory.hpp) go to at most 4096 cells, so that the scatter writes a few
    // pages at a time; the cells' sorts then do more, with the same order.
    const int finest = in_files ? 4 : 7;
    f.bits = std::clamp(int(std::log2(std::max(1.0, double(n) / 8)) / 3), 1, finest);
    return f;
}

void PointTree::box_of(const PointArray<Vec3f>& coordinates, Vec3f& lo, Vec3f& hi) { float_box(coordinates, lo, hi); }

int PointTree::Filing::shift() const { return 3 * (kBits - bits); }

std::uint32_t PointTree::Filing::cell(const Vec3f& p) const { return std::uint32_t(frame.key(p) >> shift()); }

void PointTree::Filing::by_cell(const Vec3f* p, std::size_t n, std::uint32_t first_input, const std::uint32_t* order,
                                Vec3f* xyz, std::uint32_t* input, std::uint32_t* cell_start) const {
    // Each thread counts, then scatters, its own part, so that the sort is stable: within
    // a cell the points keep their input order.
    const std::size_t cells = this->cells();
    const int parts = n > (1u << 16) ? threads_here() : 1;
    std::vector<std::uint32_t> count(std::size_t(parts) * cells, 0);
    const auto part_begin = [&](int t) { return n * std::size_t(t) / std::size_t(parts); };
#pragma omp parallel for num_threads(parts) schedule(static, 1)
    for (int t = 0; t < parts; ++t) {
        std::uint32_t* c = count.data() + std::size_t(t) * cells;
        for (std::size_t i = part_begin(t); i < part_begin(t + 1); ++i) ++c[cell(p[i])];
    }
    std::uint32_t at_slot = 0;
    for (std::size_t c = 0; c < cells; ++c) {
        cell_start[c] = at_slot;
        for (int t = 0; t < parts; ++t) {
            std::uint32_t& slot = count[std::size_t(t) * cells + c];
            const std::uint32_t here = slot;
            slot = at_slot;
            at_slot += here;
        }
    }
    cell_start[cells] = at_slot;
#pragma omp parallel for num_threads(parts) schedule(static, 1)
    for (int t = 0; t < parts; ++t) {
        std::uint32_t* next = count.data() + std::size_t(t) * cells;
        for (std::size_t i = part_begin(t); i < part_begin(t + 1); ++i) {
            const std::uint32_t to = next[cell(p[i])]++;
            xyz[to] = p[i];
            input[to] = order ? order[i] : first_input + std::uint32_t(i);
        }
    }
}

void PointTree::Filing::sort_cells(const std::uint32_t* cell_start, std::size_t cells, Vec3f* xyz, std::uint32_t* input,
                                   std::uint64_t* keys) const {
    // Each coarse cell by its points' full keys (ties in input order). `keys` is left unset
    // until the threads fill it: zeroing it first took a tenth of the build, on one thread.
    const std::ptrdiff_t ncells = std::ptrdiff_t(cells);
    const int shift = this->shift();
#pragma omp parallel if (std::ptrdiff_t(cell_start[cells] - cell_start[0]) > kParallelCheapItems)
    {
        std::vector<std::pair<std::uint64_t, std::uint32_t>> sorted, spare;
        std::vector<Vec3f> p;
        std::vector<std::uint32_t> in;
#pragma omp for schedule(dynamic, 256)
        for (std::ptrdiff_t c = 0; c < ncells; ++c) {
            const std::uint32_t b = cell_start[c], e = cell_start[c + 1];
            if (b == e) continue;
            sorted.clear();
            for (std::uint32_t i = b; i < e; ++i) sorted.emplace_back(frame.key(xyz[i]), i);
            if (!std::is_sorted(sorted.begin(), sorted.end())) {
                sort_cell(sorted, spare, shift);
                p.assign(xyz + b, xyz + e);
                in.assign(input + b, input + e);
                for (std::uint32_t i = b; i < e; ++i) {
                    xyz[i] = p[sorted[i - b].second - b];
                    input[i] = in[sorted[i - b].second - b];
                }
            }
            for (std::uint32_t i = b; i < e; ++i) keys[i] = sorted[i - b].first;
        }
    }
}

PointTree::PointTree(PointArray<Vec3f> coordinates, PointArray<std::uint32_t> order, const Vec3& at,
                     const Frame* frame)
    : origin(at) {
    settle_threads();  // every stage's first parallel region is here or after a read
    const std::size_t n = coordinates.size();
    if (n == 0) return;
    const bool no_order = order.empty();  // the points numbered as they come
    if (frame) {
        frame_ = *frame;
        if (file_in_order(coordinates, order)) {
            if (no_order) numbered_whole();
            return;
        }
    }
    const Filing filing = filing_of(coordinates, frame);
    frame_ = filing.frame;
    // A counting sort by the coarse cell, then each cell by its points' keys.
    std::vector<std::uint32_t> cell_start(filing.cells() + 1);
    xyz.resize(n);
    input.resize(n);
    filing.by_cell(coordinates.data(), n, 0, order.empty() ? nullptr : order.data(), xyz.data(), input.data(),
                   cell_start.data());
    PointArray<Vec3f>().swap(coordinates);
    PointArray<std::uint32_t>().swap(order);
    PointArray<std::uint64_t> keys(n);
    filing.sort_cells(cell_start.data(), filing.cells(), xyz.data(), input.data(), keys.data());
    build_nodes(keys.data());
    if (no_order) numbered_whole();
}

PointTree::PointTree(PointArray<Vec3f> sorted, PointArray<std::uint32_t> inputs, const Vec3& at, const Frame& frame,
                     const std::uint64_t* keys, const Grafts* grafts)
    : origin(at), xyz(std::move(sorted)), input(std::move(inputs)), frame_(frame) {
    if (!xyz.empty()) build_nodes(keys, grafts);
}

bool PointTree::in_frame_order() const {
    for (std::size_t k = 1; k < xyz.size(); ++k)
        if (frame_.key(xyz[k]) < frame_.key(xyz[k - 1])) return false;
    return true;
}

bool PointTree::file_in_order(PointArray<Vec3f>& coordinates, PointArray<std::uint32_t>& order) {
    // Each key once, checked as it is made; the coordinates become the tree's own (the
    // 200 M-point city block's other process filed 122 M points in 6.9 s with the keys made
    // twice and the points copied into fresh memory). At most 24 bytes a point.
    const std::size_t n = coordinates.size();
    PointArray<std::uint64_t> keys(n);
    for (std::size_t i = 0; i < n; ++i) {
        keys[i] = frame_.key(coordinates[i]);
        if (i && keys[i] < keys[i - 1]) return false;
    }
    xyz = std::move(coordinates);
    input.resize(n);
    for (std::size_t i = 0; i < n; ++i) input[i] = order.empty() ? std::uint32_t(i) : order[i];
    PointArray<std::uint32_t>().swap(order);
    build_nodes(keys.data());
    return true;
}

void PointTree::keep_only(const std::vector<std::uint8_t>& flags) {
    // The places dropped (a few: the outlier rules'), in order; the kept points move down
    // in runs between them, and a place `at` (a node's end, a shared range's bound) moves
    // down by the drops before it: where a loop over every point moved them one by one,
    // 0.5 s of the 50 M-point city block's outlier rules each time.
    const std::size_t n = xyz.size();
    std::vector<std::uint32_t> dropped;
    for (std::size_t k = 0; k < n; ++k)
        if (!flags[k]) dropped.push_back(std::uint32_t(k));
    const bool known = numbering_known();
    if (tell_dropped || (known && !dropped.empty())) {
        std::vector<std::uint32_t> inputs(dropped.size());
        for (std::size_t i = 0; i < dropped.size(); ++i) inputs[i] = input[dropped[i]];
        if (tell_dropped) tell_dropped(inputs);
        if (known) {
            std::sort(inputs.begin(), inputs.end());
            const std::size_t had = inputs_dropped.size();
            inputs_dropped.insert(inputs_dropped.end(), inputs.begin(), inputs.end());
            std::inplace_merge(inputs_dropped.begin(), inputs_dropped.begin() + std::ptrdiff_t(had), inputs_dropped.end());
        }
    }
    if (!tell_dropped && !dropped.empty()) filed_alone();  // no one told: the others' ranges are not these points any more
    for (std::size_t i = 0; i < dropped.size(); ++i) {
        const std::size_t from = dropped[i] + 1, end = i + 1 < dropped.size() ? dropped[i + 1] : n;
        std::copy(xyz.begin() + std::ptrdiff_t(from), xyz.begin() + std::ptrdiff_t(end), xyz.begin() + std::ptrdiff_t(from - i - 1));
        std::copy(input.begin() + std::ptrdiff_t(from), input.begin() + std::ptrdiff_t(end),
                  input.begin() + std::ptrdiff_t(from - i - 1));
    }
    const std::uint32_t to = std::uint32_t(n - dropped.size());
    // A place moves down by the drops before it: counted on bits, a word's drops before
    // it summed once, where each node's two ends searched the drops (with the nodes' arrays
    // below made at their size, three drops of 70 k points from the 50 M-point city block
    // took 1.2-1.35 s where 2.0-2.2).
    std::vector<std::uint64_t> gone(n / 64 + 1, 0);
    for (const std::uint32_t k : dropped) gone[k / 64] |= std::uint64_t(1) << (k % 64);
    std::vector<std::uint32_t> before(gone.size(), 0);
    for (std::size_t w = 1; w < gone.size(); ++w) before[w] = before[w - 1] + std::uint32_t(__builtin_popcountll(gone[w - 1]));
    const auto place = [&gone, &before](std::uint32_t at) {
        const std::uint64_t below = gone[at / 64] & ((std::uint64_t(1) << (at % 64)) - 1);
        return at - before[at / 64] - std::uint32_t(__builtin_popcountll(below));
    };
    for (std::size_t& bound : shared_ranges) bound = place(std::uint32_t(bound));
    // Shrunk only after a large drop: a new array beside the old one would hold every
    // point twice for a moment (the outlier rules drop a few).
    const bool shrink = to < xyz.size() / 8 * 7;
    xyz.resize(to);
    input.resize(to);
    if (shrink) {
        xyz.shrink_to_fit();
        input.shrink_to_fit();
    }
    // The nodes again, those left with points only, breadth first from the root (each
    // one's children together, after it).
    PointArray<Node> kept;
    std::vector<std::uint32_t> was;  // the node each kept one was
    kept.reserve(nodes.size());  // at most as many
    was.reserve(nodes.size());
    if (to > 0) {
        Node root = nodes[0];
        root.begin = 0;
        root.end = to;
        kept.push_back(root);
        was.push_back(0);
    }
    for (std::size_t i = 0; i < kept.size(); ++i) {
        const Node old = nodes[was[i]];
        if (old.leaf()) continue;
        const std::uint32_t first = std::uint32_t(kept.size());
        for (std::uint32_t k = 0; k < old.children; ++k) {
            Node child = nodes[old.child + k];
            child.begin = place(child.begin);
            child.end = place(child.end);
            if (child.begin == child.end) continue;
            kept.push_back(child);
            was.push_back(old.child + k);
        }
        kept[i].child = first;
        kept[i].children = std::uint32_t(kept.size()) - first;
    }
    // Only a node that lost points has a new box (the others hold the same points).
    std::vector<std::uint8_t> lost(kept.size());
    for (std::size_t i = 0; i < kept.size(); ++i) lost[i] = kept[i].count() != nodes[was[i]].count();
    nodes = std::move(kept);
    tighten_boxes(nodes.size() > (1u << 12) && threads_here() > 1, &lost);
}

namespace {

// Builds the octree over sorted keys, depth first: each node's children are made
// consecutive at once and filled after. Subtrees at or below `task_size` points are left
// as tasks (their root made, not split) when `tasks` is given.
struct NodeBuilder {
    const std::uint64_t* keys;
    PointArray<PointTree::Node>& out;
    struct Task {
        std::uint32_t slot;
        int level;
    };
    std::vector<Task>* tasks = nullptr;
    std::uint32_t task_size = 0;
    // Grafts: a node within one process's range is left (a task; `foreign`, by range, where
    // another's).
    const std::vector<std::size_t>* bounds = nullptr;
    std::vector<std::vector<Task>>* foreign = nullptr;

    // The range holding all of points [b, e), or -1.
    int range_of(std::uint32_t b, std::uint32_t e) const {
        const std::size_t r = std::size_t(std::upper_bound(bounds->begin(), bounds->end(), std::size_t(b)) - bounds->begin()) - 1;
        return r + 1 < bounds->size() && e <= (*bounds)[r + 1] ? int(r) : -1;
    }

    // Whether points [b, e) split (else a leaf, or a task when tasks are taken), from the
    // level where they first differ (`level` moved there): their children's bounds in cut.
    bool split(std::uint32_t b, std::uint32_t e, int& level, std::uint32_t (&cut)[9]) const {
        // Levels where every point shares the next digit make no node.
        while (level < kBits && e - b > PointTree::kLeafSize && digit(keys[b], level) == digit(keys[e - 1], level))
            ++level;
        if (e - b <= PointTree::kLeafSize || level >= kBits || (tasks && e - b <= task_size) ||
            (bounds && range_of(b, e) >= 0))
            return false;
        cut[0] = b;
        for (unsigned d = 1; d < 8; ++d)
            cut[d] = std::uint32_t(std::partition_point(keys + cut[d - 1], keys + e,
                                                        [&](std::uint64_t k) { return digit(k, level) < d; }) -
                                   keys);
        cut[8] = e;
        return true;
    }

    // The nodes fill makes below a node of points [b, e): the array is made at its size
    // once, not grown by copies into fresh pages (the 50 M-point city block's tree, two
    // processes building one each at once: 5.35-5.4 s where 5.6-5.8).
    std::size_t below(std::uint32_t b, std::uint32_t e, int level) const {
        std::uint32_t cut[9];
        if (!split(b, e, level, cut)) return 0;
        std::size_t made = 0;
        for (int d = 0; d < 8; ++d)
            if (cut[d + 1] > cut[d]) made += 1 + below(cut[d], cut[d + 1], level + 1);
        return made;
    }

    void fill(std::uint32_t self, int level) {
        const std::uint32_t b = out[self].begin, e = out[self].end;
        out[self].children = 0;
        std::uint32_t cut[9];
        if (!split(b, e, level, cut)) {
            if (e - b <= PointTree::kLeafSize || level >= kBits) return;  // a leaf
            const int range = bounds ? range_of(b, e) : -1;
            if (range > 0) (*foreign)[std::size_t(range)].push_back({self, level});
            else if (tasks) tasks->push_back({self, level});
            return;
        }
        const std::uint32_t first = std::uint32_t(out.size());
        std::uint32_t made = 0;
        for (int d = 0; d < 8; ++d)
            if (cut[d + 1] > cut[d]) {
                PointTree::Node child{};
                child.begin = cut[d];
                child.end = cut[d + 1];
                out.push_back(child);
                ++made;
            }
        out[self].child = first;
        out[self].children = made;
        for (std::uint32_t c = 0; c < made; ++c) fill(first + c, level + 1);
    }
};

}  // namespace

void PointTree::build_nodes(const std::uint64_t* keys, const Grafts* grafts) {
    nodes.clear();
    const std::uint32_t n = std::uint32_t(xyz.size());
    if (n == 0) return;
    Node root{};
    root.end = n;
    nodes.push_back(root);
    // The top levels here; the subtrees below them in parallel (and the others' grafted),
    // then appended.
    std::vector<NodeBuilder::Task> tasks;
    const std::size_t ranges = grafts ? grafts->bounds.size() - 1 : 0;
    std::vector<std::vector<NodeBuilder::Task>> foreign(ranges);
    NodeBuilder top{keys, nodes};
    const bool parallel = n > (1u << 16) && threads_here() > 1;
    if (parallel) top.task_size = std::max<std::uint32_t>(kLeafSize, n / std::uint32_t(32 * threads_here()));
    if (parallel || grafts) top.tasks = &tasks;
    if (grafts) {
        top.bounds = &grafts->bounds;
        top.foreign = &foreign;
    }
    nodes.reserve(1 + top.below(0, n, 0));
    top.fill(0, 0);
    // The others build theirs meanwhile.
    for (std::size_t r = 1; r < ranges; ++r) {
        std::vector<Asked> asked;
        const std::uint32_t from = std::uint32_t(grafts->bounds[r]);
        for (const NodeBuilder::Task& t : foreign[r])
            asked.push_back({nodes[t.slot].begin - from, nodes[t.slot].end - from, std::uint32_t(t.level)});
        grafts->ask(int(r), asked);
    }
    std::vector<PointArray<Node>> local(tasks.size());
    const std::ptrdiff_t nt = std::ptrdiff_t(tasks.size());
#pragma omp parallel for schedule(dynamic, 1) if (parallel)
    for (std::ptrdiff_t t = 0; t < nt; ++t) {
        NodeBuilder sub{keys, local[t]};
        const Node& root = nodes[tasks[t].slot];
        local[t].reserve(1 + sub.below(root.begin, root.end, tasks[t].level));
        local[t].push_back(root);
        sub.fill(0, tasks[t].level);
    }
    // The grafts after the tasks, their points moved to their ranges' places: each task's
    // nodes where they lie (the grafts' in the arrays they came in).
    struct Part {
        Node* first;
        std::size_t size;
        std::uint32_t moved;
    };
    std::vector<Part> parts;
    for (PointArray<Node>& t : local) parts.push_back({t.data(), t.size(), 0});
    std::vector<Grafted> grafted(ranges);
    for (std::size_t r = 1; r < ranges; ++r) {
        grafted[r] = grafts->take(int(r));
        Grafted& got = grafted[r];
        const std::uint32_t from = std::uint32_t(grafts->bounds[r]);
        if (got.sizes.size() != foreign[r].size()) throw Error("the points' tree: another process's nodes are not those asked");
        std::size_t at = 0;
        for (std::size_t g = 0; g < got.sizes.size(); ++g) {
            const Node& asked = nodes[foreign[r][g].slot];
            if (got.sizes[g] == 0 || got.sizes[g] > got.nodes.size() - at || got.nodes[at].begin + from != asked.begin ||
                got.nodes[at].end + from != asked.end)
                throw Error("the points' tree: another process's nodes are not those asked");
            tasks.push_back(foreign[r][g]);
            parts.push_back({got.nodes.data() + at, std::size_t(got.sizes[g]), from});
            at += got.sizes[g];
        }
        if (at != got.nodes.size()) throw Error("the points' tree: another process's nodes are not whole");
    }
    // Task node j >= 1 goes to offset + j - 1; the task's root to its slot. The places
    // first, then the copies in parallel (appended one task at a time, the growing array
    // was a third of the tree's build).
    std::vector<std::size_t> offset(tasks.size() + 1, nodes.size());
    for (std::size_t t = 0; t < tasks.size(); ++t) offset[t + 1] = offset[t] + parts[t].size - 1;
    nodes.resize(offset[tasks.size()]);
    const std::ptrdiff_t all = std::ptrdiff_t(tasks.size());
#pragma omp parallel for schedule(dynamic, 1) if (parallel)
    for (std::ptrdiff_t t = 0; t < all; ++t) {
        const Part& part = parts[std::size_t(t)];
        const std::uint32_t shift = std::uint32_t(offset[std::size_t(t)]) - 1;
        for (std::size_t j = 0; j < part.size; ++j) {
            Node node = part.first[j];
            if (node.children) node.child += shift;
            node.begin += part.moved;
            node.end += part.moved;
            nodes[j ? offset[std::size_t(t)] + j - 1 : tasks[std::size_t(t)].slot] = node;
        }
        if (t < nt) PointArray<Node>().swap(local[std::size_t(t)]);
    }
    if (all == nt) {
        tighten_boxes(parallel);
        return;
    }
    // The grafts came with their boxes.
    std::vector<std::uint8_t> unboxed(nodes.size(), 1);
    for (std::size_t t = std::size_t(nt); t < tasks.size(); ++t) {
        unboxed[tasks[t].slot] = 0;
        std::fill(unboxed.begin() + std::ptrdiff_t(offset[t]), unboxed.begin() + std::ptrdiff_t(offset[t + 1]), 0);
    }
    tighten_boxes(parallel, &unboxed);
}

PointTree::Grafted PointTree::subtrees(const std::uint64_t* keys, const PointArray<Vec3f>& xyz,
                                      const std::vector<Asked>& asked) {
    // Built one after another into one array sized first (children counted from its start
    // while the boxes are made, then from their subtree's).
    Grafted out;
    NodeBuilder sub{keys, out.nodes};
    std::size_t total = 0;
    for (const auto& [begin, end, level] : asked) {
        if (begin >= end || end > xyz.size() || level > std::uint32_t(kBits))
            throw Error("the first process asked for nodes this process's range does not have");
        out.sizes.push_back(1 + sub.below(begin, end, int(level)));
        total += out.sizes.back();
    }
    out.nodes.reserve(total);
    for (const auto& [begin, end, level] : asked) {
        Node root{};
        root.begin = begin;
        root.end = end;
        out.nodes.push_back(root);
        sub.fill(std::uint32_t(out.nodes.size() - 1), int(level));
    }
    if (out.nodes.size() != total) throw Error("the points' tree: the nodes asked came out other than counted");
    tighten(out.nodes, xyz, false, nullptr);
    std::size_t first = 0;
    for (const std::uint64_t size : out.sizes) {
        for (std::size_t i = first; i < first + size; ++i)
            if (out.nodes[i].children) out.nodes[i].child -= std::uint32_t(first);
        first += size;
    }
    return out;
}

// Each leaf's box from its points, then each inner node's from its children (which
// always come after it).
void PointTree::tighten_boxes(bool parallel, const std::vector<std::uint8_t>* only) {
    tighten(nodes, xyz, parallel, only);
}

void PointTree::tighten(PointArray<Node>& nodes, const PointArray<Vec3f>& xyz, bool parallel,
                        const std::vector<std::uint8_t>* only) {
    const std::ptrdiff_t nn = std::ptrdiff_t(nodes.size());
#pragma omp parallel for schedule(dynamic, 1024) if (parallel)
    for (std::ptrdiff_t i = 0; i < nn; ++i) {
        Node& node = nodes[i];
        if (!node.leaf() || (only && !(*only)[i])) continue;
        node.lo = node.hi = xyz[node.begin];
        for (std::uint32_t k = node.begin + 1; k < node.end; ++k)
            for (int a = 0; a < 3; ++a) {
                node.lo[a] = std::min(node.lo[a], xyz[k][a]);
                node.hi[a] = std::max(node.hi[a], xyz[k][a]);
            }
    }
    for (std::ptrdiff_t i = nn; i-- > 0;) {
        Node& node = nodes[i];
        if (node.leaf() || (only && !(*only)[i])) continue;
        node.lo = nodes[node.child].lo;
        node.hi = nodes[node.child].hi;
        for (std::uint32_t c = 1; c < node.children; ++c)
            for (int a = 0; a < 3; ++a) {
                node.lo[a] = std::min(node.lo[a], nodes[node.child + c].lo[a]);
                node.hi[a] = std::max(node.hi[a], nodes[node.child + c].hi[a]);
            }
    }
}

void PointTree::scale(double factor) {
    if (!shared_ranges.empty()) scaled_since.push_back(factor);
    origin = {origin[0] * factor, origin[1] * factor, origin[2] * factor};
    const float f = float(factor);
    // Rounding is monotone: the scaled boxes are still the tight boxes of the scaled points.
    for (Vec3f& p : xyz)
        for (float& x : p) x *= f;
    for (Node& node : nodes)
        for (int a = 0; a < 3; ++a) {
            node.lo[a] *= f;
            node.hi[a] *= f;
        }
    for (double& x : frame_.lo) x *= double(f);
    frame_.scale /= double(f);
}

// ---- queries ----

PointTree::Hit PointTree::nearest(const Vec3& q, double bound_sq) const {
    Hit best{bound_sq, npos};
    if (nodes.empty()) return best;
    Pending stack[kMaxDepth * 8];
    int top = 0;
    stack[top++] = {0, box_dist_sq(q, nodes[0])};
    while (top > 0) {
        const Pending at = stack[--top];
        if (!(at.dist_sq < best.dist_sq)) continue;
        const Node& n = nodes[at.node];
        if (n.leaf()) {
            // Points all at one place are as near as the first of them.
            const std::uint32_t end = n.lo == n.hi ? n.begin + 1 : n.end;
            for (std::uint32_t k = n.begin; k < end; ++k) {
                const double d = dist_sq(q, point(k));
                if (d < best.dist_sq) best = {d, k};
            }
            continue;
        }
        Pending* kids = stack + top;
        int m = 0;
        for (std::uint32_t c = 0; c < n.children; ++c) {
            const double d = box_dist_sq(q, nodes[n.child + c]);
            if (d < best.dist_sq) kids[m++] = {n.child + c, d};
        }
        sort_far_first(kids, m);
        top += m;
    }
    return best;
}

double PointTree::nearest_other(std::size_t k) const {
    const Vec3 q = point(k);
    double best = std::numeric_limits<double>::infinity();
    Pending stack[kMaxDepth * 8];
    int top = 0;
    stack[top++] = {0, box_dist_sq(q, nodes[0])};
    while (top > 0) {
        const Pending at = stack[--top];
        if (!(at.dist_sq < best)) continue;
        const Node& n = nodes[at.node];
        if (n.leaf()) {
            const std::uint32_t end = n.lo == n.hi ? n.begin + 1 : n.end;
            for (std::uint32_t j = n.begin; j < end; ++j) {
                const double d = dist_sq(q, point(j));
                if (d > 0 && d < best) best = d;
            }
            continue;
        }
        Pending* kids = stack + top;
        int m = 0;
        for (std::uint32_t c = 0; c < n.children; ++c) {
            const double d = box_dist_sq(q, nodes[n.child + c]);
            if (d < best) kids[m++] = {n.child + c, d};
        }
        sort_far_first(kids, m);
        top += m;
    }
    return best < std::numeric_limits<double>::infinity() ? std::sqrt(best) : 0.0;
}

// Visits the leaves nearer q than bound() (read again before each node), nearest first:
// leaf(node) takes the leaf's points.
template <class Bound, class Leaf>
void nearest_first(const PointTree& t, const Vec3& q, Bound&& bound, Leaf&& leaf) {
    if (t.nodes.empty()) return;
    Pending stack[PointTree::kMaxDepth * 8];
    int top = 0;
    stack[top++] = {0, t.box_dist_sq(q, t.nodes[0])};
    while (top > 0) {
        const Pending at = stack[--top];
        if (!(at.dist_sq < bound())) continue;
        const PointTree::Node& n = t.nodes[at.node];
        if (n.leaf()) {
            leaf(n);
            continue;
        }
        Pending* kids = stack + top;
        int m = 0;
        for (std::uint32_t c = 0; c < n.children; ++c) {
            const double d = t.box_dist_sq(q, t.nodes[n.child + c]);
            if (d < bound()) kids[m++] = {n.child + c, d};
        }
        sort_far_first(kids, m);
        top += m;
    }
}

double PointTree::kth_nearest(std::size_t k, std::size_t kth, std::vector<Neighbour>* within) const {
    // The kth + 1 smallest squared distances to all points, the point itself (0) included.
    const std::size_t want = std::min(kth + 1, size());
    std::vector<double> best;  // ascending, at most `want`
    best.reserve(want + 1);
    const auto worst = [&] { return best.size() < want ? std::numeric_limits<double>::infinity() : best.back(); };
    // Those asked for `within` are kept while no farther than the worst so far (a hair
    // more: the caller's bound is the distance squared again), and so are the leaves.
    constexpr double kHair = 1 + 1e-12;
    const auto bound = [&] {
        return within ? std::nextafter(worst() * kHair, std::numeric_limits<double>::infinity()) : worst();
    };
    if (within) within->clear();
    const auto add = [&](double d, std::uint32_t first, std::uint32_t copies) {
        if (within && d <= worst() * kHair)
            for (std::uint32_t c = 0; c < copies; ++c) within->push_back({d, first + c});
        for (std::uint32_t c = 0; c < copies && d < worst(); ++c) {
            best.insert(std::upper_bound(best.begin(), best.end(), d), d);
            if (best.size() > want) best.pop_back();
        }
    };
    const Vec3 q = point(k);
    nearest_first(*this, q, bound, [&](const Node& n) {
        if (n.lo == n.hi) add(dist_sq(q, point(n.begin)), n.begin, n.count());
        else
            for (std::uint32_t j = n.begin; j < n.end; ++j) add(dist_sq(q, point(j)), j, 1);
    });
    if (within) {
        const double last = best.back() * kHair;
        within->erase(std::remove_if(within->begin(), within->end(), [&](const Neighbour& a) { return a.dist_sq > last; }),
                      within->end());
        std::sort(within->begin(), within->end(), [](const Neighbour& a, const Neighbour& b) { return a.index < b.index; });
    }
    return std::sqrt(best.back());
}

std::vector<PointTree::Neighbour> PointTree::nearest_points(const Vec3& q, std::size_t count) const {
    std::vector<Neighbour> best;  // nearest first, at most `count`
    best.reserve(count + 1);
    const auto worst = [&] {
        return best.size() < count ? std::numeric_limits<double>::infinity() : best.back().dist_sq;
    };
    const auto nearer = [](const Neighbour& a, const Neighbour& b) { return a.dist_sq < b.dist_sq; };
    nearest_first(*this, q, worst, [&](const Node& n) {
        for (std::uint32_t j = n.begin; j < n.end; ++j) {
            const Neighbour at{dist_sq(q, point(j)), j};
            if (!(at.dist_sq < worst())) continue;
            best.insert(std::upper_bound(best.begin(), best.end(), at, nearer), at);
            if (best.size() > count) best.pop_back();
        }
    });
    return best;
}

std::size_t PointTree::count_within(const Vec3& q, double r_sq, std::size_t enough) const {
    std::size_t found = 0;
    if (nodes.empty()) return 0;
    std::uint32_t stack[kMaxDepth * 8];
    int top = 0;
    stack[top++] = 0;
    while (top > 0 && found < enough) {
        const Node& n = nodes[stack[--top]];
        const Vec3 lo = this->lo(n), hi = this->hi(n);
        if (box_dist_sq(q, lo, hi) > r_sq) continue;
        // The far corner, rounded, is no nearer than any point in the box.
        Vec3 far;
        for (int a = 0; a < 3; ++a) far[a] = q[a] - lo[a] > hi[a] - q[a] ? lo[a] : hi[a];
        if (dist_sq(q, far) <= r_sq) {
            found += n.count();
            continue;
        }
        if (n.leaf()) {
            for (std::uint32_t j = n.begin; j < n.end; ++j) found += dist_sq(q, point(j)) <= r_sq;
            continue;
        }
        for (std::uint32_t c = n.children; c-- > 0;) stack[top++] = n.child + c;
    }
    return found;
}

}  // namespace snvr::detail
