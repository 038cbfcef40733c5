// The holes a sampling leaves in the surface. Where points fall at random (a scanner's
// returns, not a blue-noise spacing) gaps open far wider than the distances between
// nearest neighbours, and the shell gets holes through it wherever one is wider than the
// offset. A wider offset would close them but thicken every wall, and real scans hold a
// few holes as wide (missing patches): instead, where the holes are the sampling's own,
// a point is added at the centre of each hole wider than the offset.
#pragma once
#include <cstddef>
#include <functional>
#include <vector>

#include "geometry/point_tree.hpp"
#include "snvr/point_cloud.hpp"

namespace snvr {

// A hole at a point: an empty disc on the surface with the point on its rim, enclosed by
// points. The surface near a point is the plane of its nearest 16 others; its nearest 48
// (those within 49 degrees of that plane) are seen in it. The disc is empty of them,
// lies within their reach (its diameter at most the farthest one's distance), its centre
// inside their convex hull, the points within twice its radius of its centre surround
// it (no empty angle over 162 degrees), the points on its rim lie on one plane (within
// 10% of its radius), and its centre lies as far from its nearest point in space as in
// the plane (within 10%). A disc that is not enclosed so is the surface's boundary, a
// notch in a ragged one, a fold, an edge or a twist, or an opening wider than the
// neighbours can judge: not a hole in the sampling. The centre is placed on its rim's
// plane (on a sphere, inside the sphere by at most the rim's sagitta).
struct HoleRules {
    // A sampling is random where at least this share of its points border a hole wider
    // than the gap (the 99th percentile of nearest-neighbour distances): the sampler's
    // random sphere, torus, cube and helicoid of 1,500 to 5,000 points 4.9-21%, of 500
    // points 1.0-17% (the random cube of 500, seed 9, 3.8-4.0% as its coordinates are
    // rounded: at 4% its walls stayed open in one of the two), its blue-noise and noisy
    // shapes 0-1.4%, the bundled scans 0-1.55% (distcap 4.65%), its line scan 99%.
    static constexpr double random_share = 0.03;
    static constexpr std::size_t samples = 2000;  // points the share is measured on (strided)
    static constexpr int passes = 3;              // over the points and the centres added so far
    // A random sampling's holes are at most this many gaps wide (1.3-1.9 measured, 500
    // to 5,000 points): where the offset's holes to fill are wider, none is looked for.
    static constexpr double widest_gaps = 2.5;
};

// The share of up to HoleRules::samples points (evenly strided by input order) that
// border a hole wider than `gap`.
double share_bordering_holes(const detail::PointTree& tree, double gap);

// A pass's holes wider than `least` at the points [begin, end) of a tree's order (with
// `near`, only those within `reach` of one of its points), as radius, x, y, z in turn: a
// run another process finds (solver/shared_holes.hpp).
std::vector<double> holes_in_run(const detail::PointTree& tree, double least, std::size_t begin, std::size_t end,
                                 const PointSet& near = {}, double reach = 0);
// Where other processes find each pass's holes at runs of the points (each on the whole
// cloud): given the pass's tree, `least`, where it looks (`near`, `reach`: as
// holes_in_run's) and how many points that is in all, it gives them their runs (or none,
// where a pass looks at too few to be worth it) and returns the end of this process's own,
// [0, here_end), and what then takes theirs (as holes_in_run gives them; null where none
// was given).
struct HolesElsewhere {
    std::size_t here_end = 0;
    std::function<std::vector<double>()> collect;
};
using AskHoles = std::function<HolesElsewhere(const detail::PointTree& tree, double least, const PointSet& near,
                                              double reach, std::size_t looked_at)>;
// How far a pass (1 to HoleRules::passes) has looked: `done` of the `all` points it looks
// at here. Told at the pass's start (done 0), then between parts of the search, never from
// its threads, so that it may throw (a cancel).
using HolesTold = std::function<void(std::size_t done, std::size_t all, int pass)>;

// Points at the centres of the holes wider than `least` radius (on the surface their rim
// points describe), one per hole, in passes over the points and the
// centres added so far until no hole that wide is left (at most HoleRules::passes).
PointSet hole_centres(const PointCloud& points, double least, const AskHoles& elsewhere = nullptr,
                      const HolesTold& told = nullptr);

}  // namespace snvr
