// The points of a PointCloud in Morton order, filed into an octree of tight boxes: one
// pass puts them into cells (a counting sort by a coarse cell, then each cell sorted by
// its points' full keys), and every stage searches the same tree. Every query returns
// exactly what a test of all points would (the squared distance summed as
// (dx^2 + dy^2) + dz^2 in double, dx = q - p with p = origin + coordinate), since a
// box's distance, rounded, is never above a point's in it.
#pragma once
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

#include "spilled_memory.hpp"
#include "snvr/point_cloud.hpp"

namespace snvr::detail {

class PointTree {
public:
    // A node holds at most this many points unless they all share one finest cell.
    static constexpr std::uint32_t kLeafSize = 32;
    static constexpr std::uint32_t npos = std::uint32_t(-1);

    struct Node {
        Vec3f lo, hi;              // the tight box of its points, about the origin
        std::uint32_t begin, end;  // its points
        std::uint32_t child;       // its first child; the others follow it
        std::uint32_t children;    // 0 for a leaf
        std::uint32_t count() const { return end - begin; }
        bool leaf() const { return children == 0; }
    };

    struct Hit {
        double dist_sq;      // the bound when nothing nearer was found
        std::uint32_t index; // npos when nothing nearer was found
    };

    // Cubic cells over the points' first box, 2^21 a side: a point's cell, bit-interleaved.
    struct Frame {
        double lo[3];
        double scale;
        std::uint64_t key(const Vec3f& p) const;
        // The same for any place about the origin: every point in a box has a key from
        // its low corner's to its high corner's (each axis's cell grows with it).
        std::uint64_t key(const Vec3& p) const;
        // As sent between processes: lo x y z, then scale.
        std::array<double, 4> figures() const { return {lo[0], lo[1], lo[2], scale}; }
        static Frame of(const double* f) { return {{f[0], f[1], f[2]}, f[3]}; }
    };

    // How points are filed: a counting sort by a coarse cell (the top `bits` digits of
    // their keys), then each cell by the full keys (ties in input order). The constructor
    // does both; a filing shared among processes (shared_filing.hpp) does them by parts of
    // the input and ranges of cells, which give the same tree.
    struct Filing {
        Frame frame;
        int bits = 1;
        int shift() const;  // a point's coarse cell: its key >> shift()
        std::size_t cells() const { return std::size_t(1) << (3 * bits); }
        std::uint32_t cell(const Vec3f& p) const;
        // p[0..n) by coarse cell into xyz and input (each point's input index: order[i], or
        // first_input + i where order is null), stable; cell_start (cells() + 1 of them):
        // where each cell's points begin.
        void by_cell(const Vec3f* p, std::size_t n, std::uint32_t first_input, const std::uint32_t* order, Vec3f* xyz,
                     std::uint32_t* input, std::uint32_t* cell_start) const;
        // Sorts each of `cells` cells (cell c: [cell_start[c], cell_start[c + 1]) of the
        // arrays) by the points' keys, and puts the keys in `keys`.
        void sort_cells(const std::uint32_t* cell_start, std::size_t cells, Vec3f* xyz, std::uint32_t* input,
                        std::uint64_t* keys) const;
    };
    // The frame from the points' box (or the one given), the cells from their number.
    static Filing filing_of(const PointArray<Vec3f>& coordinates, const Frame* frame = nullptr);
    // The same from the box of n points (the finest cells fewer where they are in files).
    static Filing filing_for(const Vec3f& lo, const Vec3f& hi, std::size_t n, bool in_files);
    static void box_of(const PointArray<Vec3f>& coordinates, Vec3f& lo, Vec3f& hi);  // the float box

    PointTree() = default;
    // Takes the coordinates (about origin) and each one's input index; sorts and files them.
    // In `frame` when given (another tree's, whose box holds these points): points taken
    // from that tree in its order then come already sorted, and filing them sorts nothing.
    PointTree(PointArray<Vec3f> coordinates, PointArray<std::uint32_t> input, const Vec3& origin,
              const Frame* frame = nullptr);
    // Filed with other processes (shared_filing.cpp), the nodes whose points all lie in
    // another's range are that one's to build: asked for by their points [begin, end) in
    // that range and the level of their keys' digits they split at (ask, before this
    // process builds its own part), then taken in the order asked (take). A node's children
    // follow from its points alone, so its nodes below are the whole tree's.
    using Asked = std::array<std::uint32_t, 3>;  // begin, end, level
    struct Grafted {
        std::vector<std::uint64_t> sizes;  // each subtree's nodes, in the order asked
        PointArray<Node> nodes;            // the subtrees one after another (Node::child
                                           // counted within its own), with their boxes
    };
    struct Grafts {
        std::vector<std::size_t> bounds;  // where each process's range begins, then the end
        std::function<void(int range, const std::vector<Asked>& asked)> ask;
        std::function<Grafted(int range)> take;
    };
    // Points filed already (by Filing's steps): in key order, their input indices and keys.
    PointTree(PointArray<Vec3f> sorted, PointArray<std::uint32_t> input, const Vec3& origin, const Frame& frame,
              const std::uint64_t* keys, const Grafts* grafts = nullptr);
    // At the process whose range it is: the subtrees asked, from its range's sorted keys and
    // points (before it builds its own tree, so that the first waits the least).
    static Grafted subtrees(const std::uint64_t* keys, const PointArray<Vec3f>& xyz, const std::vector<Asked>& asked);

    Vec3 origin{0, 0, 0};
    PointArray<Vec3f> xyz;            // by tree order
    PointArray<std::uint32_t> input;  // input index of each
    PointArray<Node> nodes;           // nodes[0] is the root (none when there are no points)
    // Filed with other processes (shared_filing.hpp), which keep their ranges of the order
    // for the outlier rules' counts and the check's depths: where each process's range
    // begins, and the end (empty where filed alone), kept as points are dropped
    // (keep_only); the factors the points were scaled by since; and whom to tell the input
    // indices of the points keep_only drops, before it drops them (so that the others drop
    // them meanwhile; where no one is told, the ranges are given up: filed_alone).
    std::vector<std::size_t> shared_ranges;
    std::vector<double> scaled_since;
    std::function<void(const std::vector<std::uint32_t>&)> tell_dropped;
    std::size_t shared_end() const { return shared_ranges.size() > 1 ? shared_ranges[1] : 0; }
    // Where the input indices are 0 .. numbered - 1 but those dropped since (ascending), so
    // that a sample by input rank needs no pass over them (point_samples.hpp): set where the
    // points were filed numbered so (the constructors, without an order; a filing by all
    // whose parts number them so: numbered_whole), kept by keep_only; 0 where unknown.
    std::size_t numbered = 0;
    std::vector<std::uint32_t> inputs_dropped;
    void numbered_whole() {
        numbered = size();
        inputs_dropped.clear();
    }
    bool numbering_known() const { return numbered > 0 && numbered - inputs_dropped.size() == size(); }
    void filed_alone() {
        shared_ranges.clear();
        scaled_since.clear();
        tell_dropped = nullptr;
    }

    std::size_t size() const { return xyz.size(); }
    Vec3 point(std::size_t k) const {
        return {origin[0] + double(xyz[k][0]), origin[1] + double(xyz[k][1]), origin[2] + double(xyz[k][2])};
    }
    // A node's box in world units (rounding is monotone: it still holds its points).
    Vec3 lo(const Node& n) const { return {origin[0] + double(n.lo[0]), origin[1] + double(n.lo[1]), origin[2] + double(n.lo[2])}; }
    Vec3 hi(const Node& n) const { return {origin[0] + double(n.hi[0]), origin[1] + double(n.hi[1]), origin[2] + double(n.hi[2])}; }

    // Squared distance from q to a point, and a lower bound of it for every point in a box.
    static double dist_sq(const Vec3& q, const Vec3& p) {
        const double x = q[0] - p[0], y = q[1] - p[1], z = q[2] - p[2];
        return (x * x + y * y) + z * z;
    }
    static double box_dist_sq(const Vec3& q, const Vec3& lo, const Vec3& hi) {
        const double x = std::max({0.0, lo[0] - q[0], q[0] - hi[0]});
        const double y = std::max({0.0, lo[1] - q[1], q[1] - hi[1]});
        const double z = std::max({0.0, lo[2] - q[2], q[2] - hi[2]});
        return (x * x + y * y) + z * z;
    }
    double box_dist_sq(const Vec3& q, const Node& n) const { return box_dist_sq(q, lo(n), hi(n)); }

    // The nearest point nearer than sqrt(bound_sq) (the first in tree order of equally near ones).
    Hit nearest(const Vec3& q, double bound_sq = std::numeric_limits<double>::infinity()) const;
    // Eight queries at once, lane by lane (a 2x2x2 block of cells: their searches visit
    // nearly the same leaves, so one walk serves all eight, and each point is measured
    // against the eight in SIMD). A lane's point nearer than sqrt(best[lane]) replaces
    // best[lane] and index[lane]; lanes that find none keep theirs. The distances are the
    // ones nearest() gives (a tie may pick another point).
    static constexpr int kLanes = 8;
    void nearest_lanes(const double (&q)[3][kLanes], double (&best)[kLanes], std::uint32_t (&index)[kLanes]) const;
    // The distance from point k to its nearest point at a distance above 0 (0 when there is none).
    double nearest_other(std::size_t k) const;
    // The `count` points nearest q (all when there are fewer), nearest first; index: the
    // point's position in the tree.
    struct Neighbour {
        double dist_sq;
        std::uint32_t index;
    };
    // The distance from point k to its k-th nearest other point, duplicates counted (the
    // farthest there is when there are fewer others). With `within`, the same search also
    // gives, in tree order, every point no farther than that (and a few a hair beyond: a
    // caller's bound in squared distance may round up), itself included: for_each_within
    // for that distance without a second search.
    double kth_nearest(std::size_t k, std::size_t kth, std::vector<Neighbour>* within = nullptr) const;
    std::vector<Neighbour> nearest_points(const Vec3& q, std::size_t count) const;
    // How many points lie at squared distance <= r_sq from q, counting up to `enough`.
    std::size_t count_within(const Vec3& q, double r_sq, std::size_t enough) const;

    // Calls leaf(node) for each leaf in tree order whose ancestors and itself `enter(node)`
    // accepts; a bound that rejects a node rejects everything below it.
    template <class Enter, class Leaf>
    void for_each_leaf(Enter&& enter, Leaf&& leaf) const {
        if (!nodes.empty()) for_each_leaf_below(nodes[0], enter, leaf);
    }
    // The same from `below` (a node of this tree) down.
    template <class Enter, class Leaf>
    void for_each_leaf_below(const Node& below, Enter&& enter, Leaf&& leaf) const {
        std::uint32_t stack[kMaxDepth * 8];
        int top = 0;
        stack[top++] = std::uint32_t(&below - nodes.data());
        while (top > 0) {
            const Node& n = nodes[stack[--top]];
            if (!enter(n)) continue;
            if (n.leaf()) {
                leaf(n);
                continue;
            }
            for (std::uint32_t c = n.children; c-- > 0;) stack[top++] = n.child + c;
        }
    }
    // Calls f(k) for every point k with dist_sq(q, point(k)) < r_sq.
    template <class F>
    void for_each_within(const Vec3& q, double r_sq, F&& f) const {
        for_each_leaf([&](const Node& n) { return box_dist_sq(q, n) < r_sq; },
                      [&](const Node& n) {
                          for (std::uint32_t k = n.begin; k < n.end; ++k)
                              if (dist_sq(q, point(k)) < r_sq) f(k);
                      });
    }

    // Keeps the points whose flag (by tree order) is set, the rest in order, and prunes
    // the nodes to them: each node's range moved onto the points kept, those left empty
    // dropped, the boxes made tight again. No keys are made again (filing anew took 8 bytes
    // a point and the builder's copies of the nodes: 2 GB at 200 M points). A node may then
    // hold fewer than kLeafSize points and not be a leaf, or have one child; no query's
    // answer depends on the shape.
    void keep_only(const std::vector<std::uint8_t>& flags);
    // Multiplies every point by factor > 0; the boxes stay tight (rounding is monotone).
    void scale(double factor);

    static constexpr int kMaxDepth = 22;  // levels of 21-bit Morton keys, and the root

    const Frame& frame() const { return frame_; }
    // Whether the points' keys in the frame still ascend (scaling may round a few across
    // a cell's edge): points taken in this order and filed in this frame keep it.
    bool in_frame_order() const;

private:
    // Files points already in key order (ties in input order), as the sort would leave
    // them; false, and nothing filed, when they are not.
    bool file_in_order(PointArray<Vec3f>& coordinates, PointArray<std::uint32_t>& order);
    void build_nodes(const std::uint64_t* keys, const Grafts* grafts = nullptr);  // n sorted keys
    // Each node's box made tight again; only those flagged in `only` (by place) when given.
    void tighten_boxes(bool parallel, const std::vector<std::uint8_t>* only = nullptr);
    static void tighten(PointArray<Node>& nodes, const PointArray<Vec3f>& xyz, bool parallel,
                        const std::vector<std::uint8_t>* only);

    Frame frame_{{0, 0, 0}, 1};
};

// The tree a cloud keeps its points in, for the library's stages.
struct CloudAccess {
    static const PointTree& tree(const PointCloud& cloud) { return *cloud.tree_; }
    static std::unique_ptr<PointTree>& tree_of(PointCloud& cloud) { return cloud.tree_; }
};
inline const PointTree& tree_of(const PointCloud& cloud) { return CloudAccess::tree(cloud); }

// The bytes a cloud holds on the heap (PointCloud::bytes but its arrays in files).
std::size_t heap_bytes(const PointCloud& cloud);

// Float coordinates about `origin`, as the readers make them, filed (the same errors as
// the PointCloud constructor's); in `frame` as PointTree's constructor says.
PointCloud cloud_of(PointArray<Vec3f>&& coordinates, const Vec3& origin, const PointTree::Frame* frame = nullptr);

// Throws ResourceError where n points are more than a cloud holds (its indices are 32-bit).
void require_point_count(std::size_t n);

// The same, the tree filed by `file` (the coordinates checked first).
using TreeFiler = std::function<std::unique_ptr<PointTree>(PointArray<Vec3f>&&, const Vec3& origin)>;
PointCloud cloud_filed(PointArray<Vec3f>&& coordinates, const Vec3& origin, const TreeFiler& file);

// PointCloud(points.to_point_set() followed by `more`), the same tree to the last bit: where
// the points keep their order in it (its origin and frame leave their keys and ranks in
// order: the points' box holds `more`), it is the points' order merged with `more`'s,
// none of them sorted again; else filed afresh (the points added at a sparse scan's
// holes, three times a run: 12 M points each).
PointCloud cloud_with(const PointCloud& points, const PointSet& more);

// Points sent from one process to another (x y z in turn, float coordinates about
// `origin`) as a cloud; the flat copy is freed first (InputError if not whole points).
// `frame`: the sender's tree's, when they were taken from it in its order (PointTree).
PointCloud cloud_of_flat(std::vector<float>&& xyz, const Vec3& origin, const PointTree::Frame* frame = nullptr);

}  // namespace snvr::detail
