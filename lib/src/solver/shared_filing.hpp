// The points' tree filed by every process of a run spread over processes (tiles.hpp),
// while the first holds the points as read: it gives each other process an equal part of
// the input in order; each sorts its part by coarse cell (PointTree::Filing), the parts
// go to the processes whose ranges of cells they fall in (ranges of equal points, from
// the counts summed over all), each sorts its range's cells by the full keys, and the
// first takes the ranges back in order and builds the nodes. A cell's points come
// together in input order and are sorted as one process would sort them: the tree is the
// one PointTree's constructor makes, bit for bit. This is how the points come to be
// spread by ranges of their Morton order, the tiles' runs.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "geometry/outliers.hpp"
#include "geometry/point_clusters.hpp"
#include "geometry/point_tree.hpp"
#include "io/point_readers.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/tiles.hpp"
#include "spilled_memory.hpp"

namespace snvr::detail {

// Fewer points than this are filed by the first alone (the messages would cost more).
constexpr std::size_t kSharedFilingPoints = std::size_t(1) << 16;

// At the first: its points as read (float coordinates about `origin`, checked finite),
// filed with the others' help (alone where they are few, the others told so).
PointCloud cloud_filed_with(TileScheduler& on, PointArray<Vec3f>&& coordinates, const Vec3& origin);
// At the first, where it files nothing with the others (a mesh read, points from elsewhere).
void no_shared_filing(TileScheduler& on);
// At another process: its range of the points filed by all, in the first's order and
// frame, kept from the filing to the check (which measures its points' depths where they
// are: check_share.cpp); `whole`: the points filed by all; `scaled`: how many of the
// first's scale factors (PointTree::scaled_since) it has applied. Once the outlier rules
// are done its tree has no input indices (the check names points by place).
struct KeptRange {
    std::unique_ptr<PointTree> tree;
    std::size_t whole = 0;
    std::size_t scaled = 0;
    std::uint64_t keys_lo = 0, keys_hi = 0;  // the filing keys of its cells: [lo, hi)
};
// At another process: its kept range where the first's points are now, for a question
// about them (the check's depths, the depth guard's search): scaled by each of the
// first's factors since the filing (`scaled`) that it has not taken, about the first's
// origin. Throws unless it holds `size` points (the first's count of its range).
PointTree& kept_as_first(KeptRange* kept, std::size_t size, const std::vector<double>& scaled, const Vec3& origin);
// At another process: its part of the first's filing, if any (null: none); it returns
// once the outlier rules' counts are done.
std::shared_ptr<KeptRange> file_for_root(TileScheduler& on);

// Where every process can read its own part of the input (io's points_in_parts), none
// is sent: each reads its part (read_my_part), the filing's box is agreed over the parts,
// and the filing goes on as above. parts_to_read, which every process calls at once:
// the input's points where every one of them can read it so (and they are several), else 0.
std::size_t parts_to_read(TileScheduler* on, const std::string& path);
FloatPoints read_my_part(TileScheduler& on, const std::string& path, std::size_t n, const std::string& temp_folder);
PointCloud cloud_read_with(TileScheduler& on, FloatPoints&& part, std::size_t n);  // at the first
std::shared_ptr<KeptRange> file_part_for_root(TileScheduler& on, FloatPoints&& part, std::size_t n);  // at the others

// The others keep their ranges after filing (file_for_root and file_part_for_root return
// once the rules' questions are done; the ranges then stay for the check): the first's
// outlier rules (the sparse rule, the strays' lonely points) ask each which of its
// range's points have too few neighbours within it, count the rest of their own, and
// decide the points named over the whole cloud: the rules' answers, the same (their
// questions a point outside this process's range stood at the cost of the whole tree's
// search before). The clusters' rule asks each for its range's own clusters and links
// the rest (every pair but those within one other's range: cluster_roots). The others
// drop the points the first drops (told as it drops them: PointTree::tell_dropped), so
// that their ranges stay its. At the first, for points filed with the others (else
// inert): short_of() and roots_of() for the rules, asked as often as they like; going
// out of scope, it tells the others there is no more. The ranges stay
// (PointTree::shared_ranges) while no point is dropped.
class NeighbourCountsShared {
public:
    NeighbourCountsShared(TileScheduler* on, PointCloud& points);
    ~NeighbourCountsShared();
    NeighbourCountsShared(const NeighbourCountsShared&) = delete;
    NeighbourCountsShared& operator=(const NeighbourCountsShared&) = delete;
    ShortOf short_of();  // null where inert
    RootsOf roots_of();  // the clusters' roots: the others link their ranges' own
    AskStrays strays_of();  // the stray rule: the others test their ranges' lonely points

private:
    TileScheduler* on_;
    PointTree* tree_;
};

}  // namespace snvr::detail
