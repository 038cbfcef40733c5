// The outlier rules (geometry/outliers.hpp): uniform random outliers sit far from the
// surface and from each other, so they fall out of the surface's clusters as singletons
// or small groups; a sparse but real part of a scan is still linked at a few spacings.
// Both rules look at the cloud's leaves first: a leaf whose points have their neighbours
// among themselves clears them all, and only the rest ask the tree. The run's lengths
// come from the caller (pipeline/outlier_policy.cpp plans them).
#include "geometry/outliers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "geometry/neighbour_counts.hpp"
#include "geometry/point_clusters.hpp"
#include "geometry/point_samples.hpp"
#include "geometry/point_tree.hpp"
#include "geometry/stray_points.hpp"
#include "geometry/vec3_math.hpp"
#include "snvr/error.hpp"

namespace snvr {
namespace {

using detail::PointTree;

// The median of v (reordered).
double median(std::vector<double>& v) {
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
}

// The largest squared distance whose root is at most r: sqrt(d) <= r exactly when d is
// at most this (the rule compares roots; the tree compares squares).
double root_bound_sq(double r) {
    double r2 = r * r;
    while (r2 > 0 && std::sqrt(r2) > r) r2 = std::nextafter(r2, 0.0);
    while (std::sqrt(std::nextafter(r2, std::numeric_limits<double>::infinity())) <= r)
        r2 = std::nextafter(r2, std::numeric_limits<double>::infinity());
    return r2;
}

// Rule 1, by tree order: 1 for a point whose `neighbours`-th nearest other point is
// farther than reach_factor times the median of that distance (fewer than neighbours + 1
// points within that reach). Empty when the median is 0 (most points at one place:
// nothing stands out).
std::vector<std::uint8_t> sparse_points(const PointTree& t, const OutlierSettings& s, const detail::ShortOf& short_of) {
    const std::vector<std::uint32_t> sample = detail::strided_sample(t, s.median_sample);
    std::vector<double> reach(sample.size());
    const std::ptrdiff_t ns = std::ptrdiff_t(sample.size());
#pragma omp parallel for schedule(dynamic, 256)
    for (std::ptrdiff_t i = 0; i < ns; ++i) reach[i] = t.kth_nearest(sample[i], s.neighbours);
    const double typical = median(reach);
    if (!(typical > 0)) return {};
    // Within reach: at least `need` points (itself and duplicates included) at squared
    // distance r2 or less; with fewer points in all, every one of them.
    const double r2 = root_bound_sq(s.reach_factor * typical);
    const std::size_t need = std::min(s.neighbours + 1, t.size());
    return short_of ? short_of(t, r2, need) : detail::points_short_of(t, r2, need);
}

// Moves the flagged points (by cloud order) into `out` (input index, world point) and
// out of the cloud; returns whether there were any.
bool take(PointCloud& cloud, const std::vector<std::uint8_t>& flagged, std::vector<std::pair<std::size_t, Vec3>>& out) {
    std::vector<std::uint8_t> keep(flagged.size());
    bool any = false;
    for (std::size_t k = 0; k < flagged.size(); ++k) {
        keep[k] = !flagged[k];
        if (flagged[k]) {
            out.emplace_back(cloud.input_index(k), cloud[k]);
            any = true;
        }
    }
    if (any) cloud.keep(keep);
    return any;
}

// The clusters of `root` (by tree order: each point's cluster's least tree position):
// their roots ascending and each one's points. Counted by runs of points with one root (a
// scan's clusters are long runs): a count a point by its root's place was 4 bytes a point
// of fresh pages and a random add each (0.5 s of the 50 M-point city block's).
struct Clusters {
    std::vector<std::uint32_t> roots;
    std::vector<std::uint32_t> members;  // by roots' order
    std::size_t of(std::uint32_t root) const {
        return std::size_t(std::lower_bound(roots.begin(), roots.end(), root) - roots.begin());
    }
    // Calls f(k, cluster) for each point k, its cluster's place in roots.
    template <class F>
    void each_point(const detail::PointArray<std::uint32_t>& root, F&& f) const {
        std::uint32_t last = 0;
        std::size_t at = roots.size();
        for (std::size_t k = 0; k < root.size(); ++k) {
            if (at == roots.size() || root[k] != last) {
                last = root[k];
                at = of(last);
            }
            f(k, at);
        }
    }
};
Clusters clusters_of(const detail::PointArray<std::uint32_t>& root) {
    Clusters c;
    for (std::size_t k = 0; k < root.size(); ++k)
        if (root[k] == k) c.roots.push_back(std::uint32_t(k));
    c.members.assign(c.roots.size(), 0);
    c.each_point(root, [&c](std::size_t, std::size_t at) { ++c.members[at]; });
    return c;
}

// The cluster roots (tree positions, each cluster's least) of the points left after
// `dropped` (by tree order, whole clusters at a time), renumbered as the cloud's keep
// renumbers them: a point's new place is the number of points kept before it, counted on
// bits (once a run of points with one root). In place: the k-th point kept goes to a
// place at or before its old one.
void roots_of_kept(detail::PointArray<std::uint32_t>& root, const std::vector<std::uint8_t>& dropped) {
    const std::size_t n = root.size();
    std::vector<std::uint64_t> gone(n / 64 + 1, 0);
    for (std::size_t k = 0; k < n; ++k) gone[k / 64] |= std::uint64_t(dropped[k] != 0) << (k % 64);
    std::vector<std::uint32_t> before(gone.size(), 0);  // dropped below each word
    for (std::size_t w = 1; w < gone.size(); ++w) before[w] = before[w - 1] + std::uint32_t(__builtin_popcountll(gone[w - 1]));
    const auto place = [&](std::uint32_t k) {
        const std::uint64_t below = gone[k / 64] & ((std::uint64_t(1) << (k % 64)) - 1);
        return k - before[k / 64] - std::uint32_t(__builtin_popcountll(below));
    };
    std::size_t to = 0;
    std::uint32_t was = 0, now = place(0);
    for (std::size_t k = 0; k < n; ++k) {
        if (dropped[k]) continue;
        if (root[k] != was) {
            was = root[k];
            now = place(was);
        }
        root[to++] = now;
    }
    root.resize(to);
}

// The roots of the clusters far from the largest, each a tiny share of the points (stray
// returns in small far groups): one whose box lies farther from the largest cluster's box
// than far_cluster_distance times that box's longest side, with under far_cluster_share
// of all the points. Such groups would spread the grid over the whole box and leave the
// object a few cells across; a small object close beside the main one stays. None when
// they would be more than 5% of the points (`refused` then). Only the small clusters'
// boxes are kept (a box for every point's root took 1.2 GB at 25 M points).
std::vector<std::uint32_t> far_clusters(const PointCloud& cloud, const detail::PointArray<std::uint32_t>& root,
                                        const Clusters& clusters, std::size_t total, const OutlierSettings& s,
                                        bool& refused) {
    refused = false;
    struct Box {
        Bounds b;
        bool started = false;
        void add(const Vec3& p) {
            if (!started) b = {p, p};
            started = true;
            for (int a = 0; a < 3; ++a) {
                b.lo[a] = std::min(b.lo[a], p[a]);
                b.hi[a] = std::max(b.hi[a], p[a]);
            }
        }
    };
    if (root.empty()) return {};
    const std::vector<std::uint32_t>& members = clusters.members;
    const std::size_t most = std::size_t(std::max_element(members.begin(), members.end()) - members.begin());
    const std::uint32_t largest = clusters.roots[most];
    std::unordered_map<std::uint32_t, Box> small;  // by root
    for (std::size_t c = 0; c < members.size(); ++c)
        if (c != most && double(members[c]) < s.far_cluster_share * double(total)) small[clusters.roots[c]];
    if (small.empty()) return {};
    // The largest cluster's box by leaves where a leaf's points are all its (the leaf's
    // tight box is theirs: most of a scan's leaves), point by point elsewhere.
    Box main;
    const PointTree& tree = detail::tree_of(cloud);
    tree.for_each_leaf([](const PointTree::Node&) { return true; }, [&](const PointTree::Node& leaf) {
        std::uint32_t k = leaf.begin;
        while (k < leaf.end && root[k] == largest) ++k;
        if (k == leaf.end) {
            main.add(tree.lo(leaf));
            main.add(tree.hi(leaf));
            return;
        }
        for (k = leaf.begin; k < leaf.end; ++k) {
            if (root[k] == largest) {
                main.add(cloud[k]);
            } else {
                const auto at = small.find(root[k]);
                if (at != small.end()) at->second.add(cloud[k]);
            }
        }
    });
    const double reach = s.far_cluster_distance * main.b.longest();
    std::vector<std::uint32_t> far;
    std::size_t dropped = 0;
    for (const auto& [r, box] : small) {
        double gap_sq = 0;  // between the two boxes
        for (int a = 0; a < 3; ++a) {
            const double g = std::max({0.0, box.b.lo[a] - main.b.hi[a], main.b.lo[a] - box.b.hi[a]});
            gap_sq += g * g;
        }
        if (gap_sq > reach * reach) {
            far.push_back(r);
            dropped += members[clusters.of(r)];
        }
    }
    if (double(dropped) > 0.05 * double(total)) {
        refused = true;
        return {};
    }
    std::sort(far.begin(), far.end());
    return far;
}

}  // namespace

void OutlierSettings::validate() const {
    if (!(reach_factor > 0) || !std::isfinite(reach_factor) || neighbours < 1 || median_sample < 1)
        throw ParameterError("the outliers' reach factor must be a positive number, neighbours and the median's sample at least 1");
    if (!(far_cluster_distance > 0) || !std::isfinite(far_cluster_distance) || !(far_cluster_share >= 0 && far_cluster_share <= 1))
        throw ParameterError("the far clusters' distance must be a positive number and their share from 0 to 1");
}

std::vector<std::pair<std::size_t, Vec3>> detail::remove_outliers(PointCloud& cloud, const OutlierSettings& s,
                                                                  const RunLengthsOf& lengths_of, double& link,
                                                                  std::size_t& clusters, const RuleQuestions& asked,
                                                                  const Told& told) {
    s.validate();
    std::vector<std::pair<std::size_t, Vec3>> out;
    link = 0;
    clusters = 0;
    const std::size_t total = cloud.size();
    if (total < 2) return out;
    const std::vector<std::uint8_t> sparse = sparse_points(detail::tree_of(cloud), s, asked.short_of);
    if (sparse.empty()) return out;
    take(cloud, sparse, out);
    std::optional<RunLengths> plan;  // of the points kept, while none is dropped
    // Near the surface, what the density let through: points off their neighbours' plane.
    if (s.strays) {
        plan = lengths_of(cloud);
        detail::StraySettings strays;
        strays.least_lonely = 0.5 * plan->voxel;
        const std::vector<std::uint8_t> stray = detail::stray_points(detail::tree_of(cloud), strays, asked.short_of,
                                                                       asked.strays_of, told);
        if (!stray.empty() && take(cloud, stray, out)) plan.reset();
    }
    // Among the rest, what the shell would carry as loose beads: clusters that the
    // offset the run will use (planned on the points kept) leaves apart, if small.
    // Dropping them can lower the offset (they may set the sampling gap), which can
    // part more: again until nothing changes (two rounds in the cases tried, the second
    // seldom made: see below). A round
    // drops whole clusters, so the next one at the same link finds the others as they
    // were: their roots are carried over rather than linked again (1.1 s of the 50 M-point
    // city block's 10.4; the 4 bytes a point they take through the keep stay below the
    // linking's peak).
    detail::PointArray<std::uint32_t> root;  // by tree order, at `link`
    for (int round = 0; round < 8; ++round) {
        if (!plan) plan = lengths_of(cloud);
        const double next_link = 2 * plan->offset;
        plan.reset();
        if (root.empty() || next_link != link)
            root = asked.roots_of ? asked.roots_of(detail::tree_of(cloud), next_link)
                                  : detail::cluster_roots(detail::tree_of(cloud), next_link);
        link = next_link;
        std::vector<std::uint8_t> small(cloud.size());
        std::size_t roots = 0, dropped_roots = 0;
        bool refused = false;
        {
            const Clusters found = clusters_of(root);
            const std::vector<std::uint32_t> far = far_clusters(cloud, root, found, total, s, refused);
            // Whether each cluster goes: small, or far.
            std::vector<std::uint8_t> goes(found.roots.size());
            for (std::size_t c = 0; c < goes.size(); ++c) {
                const std::uint32_t m = found.members[c];
                goes[c] = (m < s.min_cluster && double(m) < 0.01 * double(total)) ||
                          std::binary_search(far.begin(), far.end(), found.roots[c]);
                dropped_roots += goes[c];
            }
            roots = found.roots.size();
            found.each_point(root, [&](std::size_t k, std::size_t c) { small[k] = goes[c]; });
        }
        if (!take(cloud, small, out)) {
            clusters = roots;  // nothing dropped: these are the kept points' clusters
            break;
        }
        roots_of_kept(root, small);
        // The clusters kept are as they were, so at the same link the next round would
        // drop none (none small, none far from the same largest) unless the far ones were
        // refused for their share, which the drops may have lowered: it is not made (0.6 s
        // of the 50 M-point city block's 8.4).
        plan = lengths_of(cloud);
        if (!refused && 2 * plan->offset == link) {
            clusters = roots - dropped_roots;
            break;
        }
    }
    std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    return out;
}

}  // namespace snvr
