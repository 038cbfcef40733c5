// The holes found by all processes (shared_holes.hpp).
#include "solver/shared_holes.hpp"

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "geometry/point_tree.hpp"
#include "snvr/error.hpp"
#include "solver/sent_arrays.hpp"

namespace snvr {
namespace {

// What the root sends each other for a pass: least (0: the holes are done), its run, the
// cloud's origin and frame, the reach and count of the points it looks near; then the
// cloud's coordinates and those points.
constexpr std::size_t kHeader = 12;
// A pass sends each other process the whole cloud, which it files (about 0.15 us a point)
// before it seeks the holes at its share of the points looked at (7.5 us a point on the
// whole, most ruled out by a count; 15-30 us near the last centres, all in sparse parts):
// a later pass is shared where that share, reckoned at the lower cost, outweighs the
// filing (the 12.5 M-point city block at 2048 cells: its later passes look at 256 k and
// 178 k of 12.3 M points and stay here, about 3-4 s each on one thread, where the other's
// filing alone takes 1.5-2 s: about even; a random sampling's look at a fifth of its points).
constexpr double kSeekingOverFiling = 50;

}  // namespace

AskHoles holes_shared(TileScheduler& on, std::size_t& elsewhere) {
    if (on.processes() < 2) return nullptr;
    return [&on, &elsewhere](const detail::PointTree& tree, double least, const PointSet& near, double reach,
                             std::size_t looked_at) {
        const std::size_t n = tree.size(), processes = std::size_t(on.processes());
        const double theirs_share = double(processes - 1) / double(processes);
        if (!near.empty() && !(double(looked_at) * theirs_share * kSeekingOverFiling > double(n)))
            return HolesElsewhere{n, nullptr};
        // The runs count in this tree's order, which the others file again in its frame;
        // where scaling has left a point out of that frame's order (rare), all are found here.
        if (!tree.in_frame_order()) return HolesElsewhere{n, nullptr};
        const auto first = [n, processes](std::size_t p) { return n * p / processes; };  // of process p's run
        const std::array<double, 4> frame = tree.frame().figures();
        std::vector<double> near_xyz;
        for (const Vec3& p : near) near_xyz.insert(near_xyz.end(), {p[0], p[1], p[2]});
        for (std::size_t p = 1; p < processes; ++p) {
            const std::vector<double> header{least,          double(first(p)), double(first(p + 1)), tree.origin[0],
                                             tree.origin[1], tree.origin[2],   frame[0],             frame[1],
                                             frame[2],       frame[3],         reach,                double(near.size())};
            detail::send_array(on, int(p), header.data(), header.size());
            detail::send_array(on, int(p), &tree.xyz[0][0], 3 * n);
            if (!near.empty()) detail::send_array(on, int(p), near_xyz.data(), near_xyz.size());
        }
        if (near.empty()) elsewhere += n - first(1);
        HolesElsewhere theirs{first(1), nullptr};
        theirs.collect = [&on, processes] {
            std::vector<double> all;
            for (std::size_t p = 1; p < processes; ++p) {
                std::vector<double> got;
                detail::receive_array(on, int(p), got);
                all.insert(all.end(), got.begin(), got.end());
            }
            return all;
        };
        return theirs;
    };
}

void holes_done(TileScheduler& on) {
    const std::vector<double> done(kHeader, 0.0);
    for (int p = 1; p < on.processes(); ++p) detail::send_array(on, p, done.data(), done.size());
}

void holes_for_root(TileScheduler& on) {
    for (;;) {
        std::vector<double> header;
        detail::receive_array(on, 0, header);
        if (header.size() != kHeader) throw Error("the first process's question of the holes is not whole");
        if (!(header[0] > 0)) return;
        std::vector<float> xyz;
        detail::receive_array(on, 0, xyz);
        PointSet near(static_cast<std::size_t>(header[11]));
        if (!near.empty()) {
            std::vector<double> flat;
            detail::receive_array(on, 0, flat);
            if (flat.size() != 3 * near.size()) throw Error("the points the first process looks near are not whole");
            for (std::size_t k = 0; k < near.size(); ++k) near[k] = {flat[3 * k], flat[3 * k + 1], flat[3 * k + 2]};
        }
        const auto frame = detail::PointTree::Frame::of(header.data() + 6);
        const PointCloud cloud = detail::cloud_of_flat(std::move(xyz), {header[3], header[4], header[5]}, &frame);
        const std::vector<double> found = holes_in_run(detail::tree_of(cloud), header[0], std::size_t(header[1]),
                                                       std::size_t(header[2]), near, header[10]);
        detail::send_array(on, 0, found.data(), found.size());
    }
}

}  // namespace snvr
