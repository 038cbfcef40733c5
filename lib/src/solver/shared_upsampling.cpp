// The points between shared among processes (shared_upsampling.hpp).
#include "solver/shared_upsampling.hpp"

#include <algorithm>
#include <cstring>
#include <utility>
#include <vector>

#include "geometry/point_tree.hpp"
#include "geometry/surface_upsampling.hpp"
#include "snvr/error.hpp"

namespace snvr {

PointSet points_between_shared(TileScheduler& on, const PointCloud& so_far, double spacing, std::size_t& elsewhere) {
    const detail::PointTree& tree = detail::tree_of(so_far);
    // The runs count in this tree's order, which the others file again in its frame; where
    // scaling has left a point out of that frame's order (rare), this process makes them all.
    if (!tree.in_frame_order()) {
        no_points_between(on);
        return upsample_surface(tree, spacing);
    }
    const std::size_t n = tree.size(), processes = std::size_t(on.processes());
    const auto first = [&](std::size_t p) { return n * p / processes; };  // of process p's run
    {
        UpsampleShare share;
        share.origin = tree.origin;
        share.spacing = spacing;
        share.points_frame = tree.frame().figures();
        share.points.resize(3 * n);
        if (n) std::memcpy(share.points.data(), tree.xyz.data(), 3 * n * sizeof(float));
        for (std::size_t p = 1; p < processes; ++p) {
            share.begin = first(p);
            share.end = first(p + 1);
            on.give_upsampling(int(p), share);
        }
    }
    PointSet out = upsample_surface(tree, spacing, 0, first(1));
    for (std::size_t p = 1; p < processes; ++p) {
        const std::vector<double> xyz = on.take_upsampled(int(p));
        if (xyz.size() % 3) throw Error("the points added by process " + std::to_string(p) + " are not whole");
        out.reserve(out.size() + xyz.size() / 3);
        for (std::size_t k = 0; k < xyz.size(); k += 3) out.push_back({xyz[k], xyz[k + 1], xyz[k + 2]});
        elsewhere += xyz.size() / 3;
    }
    return out;
}

void no_points_between(TileScheduler& on) {
    const UpsampleShare none;
    for (int p = 1; p < on.processes(); ++p) on.give_upsampling(p, none);
}

void points_between_for_root(TileScheduler& on) {
    UpsampleShare share = on.upsampling();
    if (!(share.spacing > 0)) return;
    const auto frame = detail::PointTree::Frame::of(share.points_frame.data());
    const PointCloud cloud = detail::cloud_of_flat(std::move(share.points), share.origin, &frame);
    const PointSet made = upsample_surface(detail::tree_of(cloud), share.spacing, share.begin, share.end);
    std::vector<double> flat;
    flat.reserve(3 * made.size());
    for (const Vec3& p : made) flat.insert(flat.end(), {p[0], p[1], p[2]});
    on.send_upsampled(flat);
}

}  // namespace snvr
