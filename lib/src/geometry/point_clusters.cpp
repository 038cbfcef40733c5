// How many pieces the points themselves suggest: a shell of offset l joins points
// closer than 2l, so clusters linked at that distance bound the pieces a correct
// result can have (two sheets per closed piece, one per open piece).
#include "geometry/point_clusters.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

#include "parallel_sizes.hpp"
#include "snvr/error.hpp"
#include "snvr/point_cloud.hpp"

namespace snvr::detail {
namespace {

using Node = PointTree::Node;

// Union-find shared by the team's threads, on a plain array through atomic built-ins: a
// parent is never above its child, and a union hangs the larger root under the smaller,
// so every cluster's root is its least index whatever order the unions came in.
class Forest {
public:
    explicit Forest(PointArray<std::uint32_t>& parent) : parent_(parent) {}
    std::uint32_t find(std::uint32_t n) const {
        for (;;) {
            std::uint32_t p = load(n);
            if (p == n) return n;
            const std::uint32_t g = load(p);
            // Halving the path: any ancestor is a valid parent, a stale one too.
            if (g != p) __atomic_compare_exchange_n(&parent_[n], &p, g, false, __ATOMIC_RELAXED, __ATOMIC_RELAXED);
            n = g;
        }
    }
    void unite(std::uint32_t a, std::uint32_t b) const {
        for (;;) {
            a = find(a);
            b = find(b);
            if (a == b) return;
            if (a < b) std::swap(a, b);
            std::uint32_t root = a;  // still a root, or another thread hung it first: again
            if (__atomic_compare_exchange_n(&parent_[a], &root, b, false, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) return;
        }
    }
    void set(std::uint32_t n, std::uint32_t p) const { __atomic_store_n(&parent_[n], p, __ATOMIC_RELAXED); }
    std::uint32_t parent(std::uint32_t n) const { return load(n); }

private:
    std::uint32_t load(std::uint32_t n) const { return __atomic_load_n(&parent_[n], __ATOMIC_RELAXED); }
    PointArray<std::uint32_t>& parent_;
};

// The squared gap between two boxes (world units); below every pair's squared distance
// (rounding is monotone).
double gap_sq(const Vec3& alo, const Vec3& ahi, const Vec3& blo, const Vec3& bhi) {
    const double x = std::max({0.0, alo[0] - bhi[0], blo[0] - ahi[0]});
    const double y = std::max({0.0, alo[1] - bhi[1], blo[1] - ahi[1]});
    const double z = std::max({0.0, alo[2] - bhi[2], blo[2] - ahi[2]});
    return (x * x + y * y) + z * z;
}

// Union-find over the points. Nodes whose box's diagonal is below the link hold one
// cluster each ("whole": every pair in them is linked) and join as a block; a pair of
// units is looked at only while they are apart, and two whole nodes only until one link
// between them is found, by a dual descent of the tree that drops the pairs of boxes a
// link apart. Dense scans have thousands of points within a link: this looks at a
// handful of pairs for each pair of neighbouring whole nodes.
class Linker {
public:
    // bounds: where other processes link their own ranges of the tree (cluster_roots'),
    // or null.
    Linker(const PointTree& tree, double link, const std::vector<std::size_t>* bounds = nullptr)
        : t_(tree), link_sq_(link * link), parent_(tree.size()), forest_(parent_), bounds_(bounds) {
        const std::ptrdiff_t n = std::ptrdiff_t(parent_.size());
#pragma omp parallel for schedule(static) if (n > kParallelCheapItems)
        for (std::ptrdiff_t k = 0; k < n; ++k) parent_[std::size_t(k)] = std::uint32_t(k);
    }

    // Each point's cluster as its least index. Both threads link the units: the unions
    // commute, so the roots are the same. With other processes' ranges, `theirs` is asked
    // for each one's own roots once this process has linked the rest.
    PointArray<std::uint32_t> roots(const std::function<PointArray<std::uint32_t>(int)>& theirs = nullptr) {
        if (t_.nodes.empty() || !(link_sq_ > 0)) {
            if (bounds_) take_theirs(theirs);  // each other's answer is taken, whatever it is
            return parent_;
        }
        collect(0);
        const std::ptrdiff_t nu = std::ptrdiff_t(units_.size()), n = std::ptrdiff_t(parent_.size());
#pragma omp parallel if (n > kParallelCheapItems)
        {
#pragma omp for schedule(dynamic, 64)
            for (std::ptrdiff_t i = 0; i < nu; ++i) {
                const Unit& u = units_[std::size_t(i)];
                if (u.whole && !others_range(t_.nodes[u.node]))
                    for (std::uint32_t k = t_.nodes[u.node].begin + 1; k < t_.nodes[u.node].end; ++k)
                        parent_[k] = t_.nodes[u.node].begin;
            }
#pragma omp for schedule(dynamic, 16)
            for (std::ptrdiff_t i = 0; i < nu; ++i) link_unit(units_[std::size_t(i)]);
        }
        if (bounds_) take_theirs(theirs);
        // Each point's root, runs of points in turn, each run in ascending order: a parent
        // is never above its child, so a parent within the run has its root already and a
        // look finds it (a walk of the forest for every point took 0.36 s of the 50 M-point
        // city block's 0.99); one below the run is walked.
        constexpr std::ptrdiff_t kRun = 1 << 16;
#pragma omp parallel if (n > kParallelCheapItems)
        {
#pragma omp for schedule(static)
            for (std::ptrdiff_t run = 0; run < (n + kRun - 1) / kRun; ++run) {
                const std::uint32_t first = std::uint32_t(run * kRun);
                for (std::uint32_t k = first; k < std::uint32_t(std::min(n, (run + 1) * kRun)); ++k) {
                    const std::uint32_t p = forest_.parent(k);
                    forest_.set(k, p == k ? p : p >= first ? forest_.parent(p) : forest_.find(p));
                }
            }
        }
        return std::move(parent_);
    }

private:
    struct Unit {
        std::uint32_t node;
        bool whole;  // else a leaf of points apart
    };

    bool is_whole(const Node& n) const { return PointTree::dist_sq(t_.lo(n), t_.hi(n)) < link_sq_; }
    double gap(const Node& a, const Node& b) const { return gap_sq(t_.lo(a), t_.hi(a), t_.lo(b), t_.hi(b)); }

    void collect(std::uint32_t i) {
        const Node& n = t_.nodes[i];
        // The last other's range has no pair after it but its own, which that process
        // links: none of its units is looked at here (units are never nested, so a unit
        // across its bound cannot follow one within it).
        if (bounds_ && bounds_->size() > 2 && others_range(n) == int(bounds_->size()) - 2) return;
        if (is_whole(n)) {
            units_.push_back({i, true});
            return;
        }
        if (n.leaf()) {
            units_.push_back({i, false});
            return;
        }
        for (std::uint32_t c = 0; c < n.children; ++c) collect(n.child + c);
    }

    void unite(std::uint32_t a, std::uint32_t b) { forest_.unite(a, b); }
    std::uint32_t find_root(std::uint32_t n) const { return forest_.find(n); }
    bool linked(std::uint32_t a, std::uint32_t b) const {
        return PointTree::dist_sq(t_.point(a), t_.point(b)) < link_sq_;
    }

    // The other process whose own range holds node n whole (0: none, or no others).
    int others_range(const Node& n) const {
        if (!bounds_) return 0;
        const std::vector<std::size_t>& b = *bounds_;
        const std::size_t p = std::size_t(std::upper_bound(b.begin(), b.end(), std::size_t(n.begin)) - b.begin()) - 1;
        return p > 0 && p + 1 < b.size() && n.end <= b[p + 1] ? int(p) : 0;
    }

    // Each other process's range linked there: each point hangs under its range's root
    // (its least linked place there, below it) where nothing here has hung it under
    // another (a pair across ranges), else joins it; in ascending order, so that a root
    // below is where it goes by then.
    void take_theirs(const std::function<PointArray<std::uint32_t>(int)>& theirs) {
        const std::vector<std::size_t>& b = *bounds_;
        for (std::size_t p = 1; p + 1 < b.size(); ++p) {
            const PointArray<std::uint32_t> local = theirs(int(p));
            if (local.size() != b[p + 1] - b[p]) throw Error("a process's clusters are not its range's");
            for (std::size_t i = 0; i < local.size(); ++i) {
                if (local[i] >= i) {  // its range's root (anything else is no least place)
                    if (local[i] > i) throw Error("a process's cluster root lies above its point");
                    continue;
                }
                const std::uint32_t k = std::uint32_t(b[p] + i), r = std::uint32_t(b[p] + local[i]);
                if (forest_.parent(k) == k) forest_.set(k, forest_.find(r));
                else unite(k, r);
            }
        }
    }

    // Links the points of a leaf unit among themselves, then unit u with every unit after it
    // (but those of the same other process's range, which it links).
    void link_unit(const Unit& u) {
        const Node& a = t_.nodes[u.node];
        const int range = others_range(a);
        if (!u.whole && !range)
            for (std::uint32_t i = a.begin; i < a.end; ++i)
                for (std::uint32_t j = i + 1; j < a.end; ++j)
                    if (linked(i, j)) unite(i, j);
        neighbours(u, 0, range);
    }

    // Walks the tree from node i to the units after u within the link of it (a unit is the
    // first whole node or leaf on a path from the root), but within u's other process's
    // range (`range`, 0: none).
    void neighbours(const Unit& u, std::uint32_t i, int range) {
        const Node& a = t_.nodes[u.node];
        const Node& n = t_.nodes[i];
        if (n.end <= a.end || gap(a, n) >= link_sq_) return;  // nothing after u, or too far
        if (range && others_range(n) == range) return;
        if (is_whole(n) || n.leaf()) {
            join(u, {i, is_whole(n)});
            return;
        }
        for (std::uint32_t c = 0; c < n.children; ++c) neighbours(u, n.child + c, range);
    }

    // Links unit u with unit v.
    void join(const Unit& u, const Unit& v) {
        const Node& a = t_.nodes[u.node];
        const Node& b = t_.nodes[v.node];
        if (u.whole && v.whole) {
            if (find_root(a.begin) != find_root(b.begin) && any_link(u.node, v.node))
                unite(a.begin, b.begin);
        } else if (u.whole || v.whole) {
            // Each point of the leaf with the whole unit, while they are apart.
            const Node& leaf = u.whole ? b : a;
            const std::uint32_t whole = u.whole ? u.node : v.node;
            for (std::uint32_t k = leaf.begin; k < leaf.end; ++k)
                if (find_root(k) != find_root(t_.nodes[whole].begin) && reaches(k, whole))
                    unite(k, t_.nodes[whole].begin);
        } else {
            for (std::uint32_t i = a.begin; i < a.end; ++i)
                for (std::uint32_t j = b.begin; j < b.end; ++j)
                    if (find_root(i) != find_root(j) && linked(i, j)) unite(i, j);
        }
    }

    // Whether point k is linked with some point of node x.
    bool reaches(std::uint32_t k, std::uint32_t x) const {
        const Node& n = t_.nodes[x];
        const Vec3 p = t_.point(k);
        if (PointTree::box_dist_sq(p, t_.lo(n), t_.hi(n)) >= link_sq_) return false;
        if (n.leaf()) {
            for (std::uint32_t j = n.begin; j < n.end; ++j)
                if (linked(k, j)) return true;
            return false;
        }
        for (std::uint32_t c = 0; c < n.children; ++c)
            if (reaches(k, n.child + c)) return true;
        return false;
    }

    // Whether some point of node x and some point of node y are linked.
    bool any_link(std::uint32_t x, std::uint32_t y) const {
        const Node& a = t_.nodes[x];
        const Node& b = t_.nodes[y];
        if (gap(a, b) >= link_sq_) return false;
        if (a.leaf() && b.leaf()) {
            for (std::uint32_t i = a.begin; i < a.end; ++i)
                for (std::uint32_t j = b.begin; j < b.end; ++j)
                    if (linked(i, j)) return true;
            return false;
        }
        // Split the node with more points (a leaf cannot be split).
        if (!a.leaf() && (b.leaf() || a.count() >= b.count())) {
            for (std::uint32_t c = 0; c < a.children; ++c)
                if (any_link(a.child + c, y)) return true;
            return false;
        }
        for (std::uint32_t c = 0; c < b.children; ++c)
            if (any_link(x, b.child + c)) return true;
        return false;
    }

    const PointTree& t_;
    double link_sq_;
    PointArray<std::uint32_t> parent_;
    Forest forest_;
    const std::vector<std::size_t>* bounds_;
    std::vector<Unit> units_;
};

}  // namespace

PointArray<std::uint32_t> cluster_roots(const PointTree& tree, double link_distance) {
    return Linker(tree, link_distance).roots();
}

PointArray<std::uint32_t> cluster_roots(const PointTree& tree, double link_distance, const std::vector<std::size_t>& bounds,
                                        const std::function<PointArray<std::uint32_t>(int)>& theirs) {
    if (bounds.empty() || bounds.back() != tree.size()) throw Error("cluster_roots: the ranges are not the tree's");
    if (bounds.size() < 3) return cluster_roots(tree, link_distance);  // no others
    return Linker(tree, link_distance, &bounds).roots(theirs);
}

}  // namespace snvr::detail

namespace snvr {

std::size_t count_point_clusters(const PointCloud& points, double link_distance) {
    const detail::PointArray<std::uint32_t> root = detail::cluster_roots(detail::tree_of(points), link_distance);
    std::size_t roots = 0;
    for (std::uint32_t k = 0; k < root.size(); ++k) roots += root[k] == k;
    return roots;
}

std::size_t count_point_clusters(const PointSet& points, double link_distance) {
    // A point with a coordinate that is not finite is linked to nothing: a cluster of its own.
    PointSet finite;
    for (const Vec3& p : points)
        if (std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])) finite.push_back(p);
    return points.size() - finite.size() + count_point_clusters(PointCloud(finite), link_distance);
}

}  // namespace snvr
