// PointTree::nearest_lanes: one walk of the tree for eight nearby queries, in float.
//
// The tree holds the points as floats about its origin, so the walk measures them as
// they are, eight lanes to an AVX register, with no conversion: d_f, the float sum of
// squares. Each of those is within `err` of the double one nearest() evaluates, D. For
// the point p* of least D, d_f(p*) <= D(p*) + err <= D(p) + err <= d_f(p) + 2 err for
// every p, and D(p*) < bound gives d_f(p*) < bound + err: so p* is among the points with
// d_f <= T = min(bound, least d_f so far) + 2 err. The walk keeps T per lane, skips
// boxes beyond it (a box's float distance is never above a point's in it: rounding is
// monotone), and files every point at or below it; the filed few are then measured in
// double. The answer is nearest()'s, to the bit.
#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/point_tree.hpp"

namespace snvr::detail {

namespace {

constexpr int kLanes = PointTree::kLanes;
// Eight floats, and the masks their comparisons give (GCC and Clang vector extensions).
typedef float F8 __attribute__((vector_size(4 * kLanes)));
typedef std::int32_t I8 __attribute__((vector_size(4 * kLanes)));

// A node with this few points is measured whole rather than walked (its points are
// contiguous): a box test costs about as much as a few points in the lanes.
constexpr std::uint32_t kWholeNode = 128;
// Points filed at once before they are measured in double (there are usually a few).
constexpr int kFiled = 128;

struct Lanes {
    F8 q[3];    // the queries about the tree's origin, rounded to float
    F8 least;   // the least d_f so far, or the bound
    float err2; // 2 err
    std::uint32_t filed[kFiled];
    int count = 0;
};

// (Inlined into each clone of walk: out of line they would be built without AVX.)
// By halves folded with OR (three shuffles), not lane by lane: GCC takes a loop over the
// lanes one extraction at a time, and `any` runs once for each point the walk files.
typedef std::int32_t I4 __attribute__((vector_size(16)));
[[gnu::always_inline]] inline bool any(const I8& m) {
    I4 o = __builtin_shufflevector(m, m, 0, 1, 2, 3) | __builtin_shufflevector(m, m, 4, 5, 6, 7);
    o |= __builtin_shufflevector(o, o, 2, 3, 0, 1);
    o |= __builtin_shufflevector(o, o, 1, 0, 3, 2);
    return o[0] != 0;
}
[[gnu::always_inline]] inline float least_of(const F8& v) {
    float m = v[0];
    for (int i = 1; i < kLanes; ++i) m = v[i] < m ? v[i] : m;
    return m;
}
// The lanes' float squared distances to a node's box, in the points' expression.
[[gnu::always_inline]] inline F8 box_dist_sq(const Lanes& s, const PointTree::Node& n) {
    const F8 zero = {};
    F8 g[3];
    for (int a = 0; a < 3; ++a) {
        const F8 below = n.lo[a] - s.q[a], above = s.q[a] - n.hi[a];
        g[a] = below > zero ? below : zero;
        g[a] = above > g[a] ? above : g[a];
    }
    return (g[0] * g[0] + g[1] * g[1]) + g[2] * g[2];
}
[[gnu::always_inline]] inline F8 point_dist_sq(const Lanes& s, const Vec3f& p) {
    const F8 x = s.q[0] - p[0], y = s.q[1] - p[1], z = s.q[2] - p[2];
    return (x * x + y * y) + z * z;
}

// A node to visit, with the lanes' distances to its box.
struct Pending {
    F8 dist;
    std::uint32_t node;
};

// Files the points [begin, end) at or below T, measuring the filed in double when full.
template <class Settle>
[[gnu::always_inline]] inline void file_points(const PointTree& tree, Lanes& s, std::uint32_t begin,
                                               std::uint32_t end, const Settle& settle) {
    const F8 limit = s.least + s.err2;
    const auto file = [&](std::uint32_t k) {
        if (s.count == kFiled) settle(s);
        s.filed[s.count++] = k;
    };
    std::uint32_t k = begin;
    // Four points' masks at once: few points are filed, so most quadruples need one test.
    for (; k + 4 <= end; k += 4) {
        const I8 m0 = point_dist_sq(s, tree.xyz[k]) <= limit, m1 = point_dist_sq(s, tree.xyz[k + 1]) <= limit;
        const I8 m2 = point_dist_sq(s, tree.xyz[k + 2]) <= limit, m3 = point_dist_sq(s, tree.xyz[k + 3]) <= limit;
        if (!any((m0 | m1) | (m2 | m3))) continue;
        const I8 m[4] = {m0, m1, m2, m3};
        for (std::uint32_t j = 0; j < 4; ++j)
            if (any(m[j])) file(k + j);
    }
    for (; k < end; ++k)
        if (any(point_dist_sq(s, tree.xyz[k]) <= limit)) file(k);
}

template <class Settle>
[[gnu::always_inline]] inline void walk_lanes(const PointTree& tree, Lanes& s, const Settle& settle) {
    const auto& nodes = tree.nodes;
    Pending stack[24 * 8];
    stack[0] = {box_dist_sq(s, nodes[0]), 0};
    int top = 1;
    float order[8];
    while (top > 0) {
        const Pending& at = stack[--top];
        if (!any(at.dist <= s.least + s.err2)) continue;
        const PointTree::Node& n = nodes[at.node];
        if (n.leaf() || n.count() <= kWholeNode) {
            // Points all at one place are as near as the first of them.
            const std::uint32_t end = n.lo == n.hi ? n.begin + 1 : n.end;
            F8 own = {};  // the leaf's least
            own += std::numeric_limits<float>::infinity();
            for (std::uint32_t k = n.begin; k < end; ++k) {
                const F8 d = point_dist_sq(s, tree.xyz[k]);
                own = d < own ? d : own;
            }
            s.least = own < s.least ? own : s.least;
            // Then, seldom, a second look to file those within reach.
            if (any(own <= s.least + s.err2)) file_points(tree, s, n.begin, end, settle);
            continue;
        }
        // The children that may help some lane, the nearest popped first.
        Pending* kids = stack + top;
        int m = 0;
        const F8 limit = s.least + s.err2;
        for (std::uint32_t c = 0; c < n.children; ++c) {
            Pending& kid = kids[m];
            kid.dist = box_dist_sq(s, nodes[n.child + c]);
            if (!any(kid.dist <= limit)) continue;
            kid.node = n.child + c;
            order[m] = least_of(kid.dist);
            int j = m++;
            for (; j > 0 && order[j - 1] < order[j]; --j) {
                std::swap(order[j - 1], order[j]);
                std::swap(kids[j - 1], kids[j]);
            }
        }
        top += m;
    }
}

}  // namespace

namespace {

// The exact state per lane, which the filed points update.
struct Exact {
    const PointTree& tree;
    const double (&q)[3][kLanes];
    double (&best)[kLanes];
    std::uint32_t (&index)[kLanes];

    void operator()(Lanes& s) const {
        for (int f = 0; f < s.count; ++f) {
            const std::uint32_t k = s.filed[f];
            const Vec3 p = tree.point(k);
            for (int lane = 0; lane < kLanes; ++lane) {
                const double d = PointTree::dist_sq({q[0][lane], q[1][lane], q[2][lane]}, p);
                if (d < best[lane] || (d == best[lane] && index[lane] != PointTree::npos && k < index[lane]))
                    best[lane] = d, index[lane] = k;
            }
        }
        s.count = 0;
    }
};

__attribute__((target_clones("avx2", "default"))) void walk(const PointTree& tree, Lanes& s, const Exact& exact) {
    walk_lanes(tree, s, exact);
}

}  // namespace

void PointTree::nearest_lanes(const double (&q)[3][kLanes], double (&best)[kLanes],
                              std::uint32_t (&index)[kLanes]) const {
    if (nodes.empty()) return;
    Lanes s;
    // M bounds every coordinate about the origin, of points and queries alike.
    double m = 0, reach = 0;
    for (int a = 0; a < 3; ++a) m = std::max({m, std::abs(double(nodes[0].lo[a])), std::abs(double(nodes[0].hi[a]))});
    for (int lane = 0; lane < kLanes; ++lane)
        for (int a = 0; a < 3; ++a) {
            const double rel = q[a][lane] - origin[a];
            s.q[a][lane] = float(rel);
            m = std::max(m, std::abs(rel));
        }
    double far = 0;  // the largest bound, at most the widest possible distance
    for (int lane = 0; lane < kLanes; ++lane) far = std::max(far, best[lane]);
    reach = std::min(std::sqrt(far), 4 * m);
    // e0 bounds each axis's error in the float difference's inputs: the query's rounding
    // to float (2^-24 M) and the double point's own (2^-53 of |origin| + M), with room.
    double o = 0;
    for (int a = 0; a < 3; ++a) o = std::max(o, std::abs(origin[a]));
    const double e0 = 0x1p-22 * m + 0x1p-50 * (o + m);
    // With each axis off by at most e0 + 2^-24 |x|, and three roundings in the sum:
    // |d_f - D| <= 2 sqrt3 reach e0 + 3 e0^2 + 6 2^-24 reach^2, doubled for room.
    const double err = 8 * reach * e0 + 8 * e0 * e0 + 0x1p-19 * reach * reach;
    s.err2 = float(2 * err) * (1 + 0x1p-20f) + std::numeric_limits<float>::min();
    for (int lane = 0; lane < kLanes; ++lane) {
        // The bound rounded up to float: no filed point may be missed for rounding it.
        float b = float(best[lane]);
        if (double(b) < best[lane]) b = std::nextafter(b, std::numeric_limits<float>::infinity());
        s.least[lane] = b;
    }
    const Exact exact{*this, q, best, index};
    walk(*this, s, exact);
    exact(s);
}

}  // namespace snvr::detail
