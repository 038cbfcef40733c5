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

// What the root sends each other first: least (0: none asked), its run, the cloud's
// origin and frame; then the cloud's coordinates.
constexpr std::size_t kHeader = 10;

}  // namespace

AskHoles holes_shared(TileScheduler& on, bool& asked, std::size_t& elsewhere) {
    asked = false;
    if (on.processes() < 2) return nullptr;
    return [&on, &asked, &elsewhere](const detail::PointTree& tree, double least) {
        asked = true;
        // The runs count in this tree's order, which the others file again in its frame;
        // where scaling has left a point out of that frame's order (rare), all are found here.
        if (!tree.in_frame_order()) {
            no_holes_asked(on);
            return HolesElsewhere{tree.size(), nullptr};
        }
        const std::size_t n = tree.size(), processes = std::size_t(on.processes());
        const auto first = [n, processes](std::size_t p) { return n * p / processes; };  // of process p's run
        const std::array<double, 4> frame = tree.frame().figures();
        for (std::size_t p = 1; p < processes; ++p) {
            const std::vector<double> header{least,         double(first(p)), double(first(p + 1)), tree.origin[0],
                                             tree.origin[1], tree.origin[2],  frame[0],             frame[1],
                                             frame[2],       frame[3]};
            detail::send_array(on, int(p), header.data(), header.size());
            detail::send_array(on, int(p), &tree.xyz[0][0], 3 * n);
        }
        elsewhere = n - first(1);
        HolesElsewhere theirs{first(1), nullptr};
        theirs.collect = [&on, processes] {
            std::vector<double> all;
            for (std::size_t p = 1; p < processes; ++p) {
                std::vector<double> theirs;
                detail::receive_array(on, int(p), theirs);
                all.insert(all.end(), theirs.begin(), theirs.end());
            }
            return all;
        };
        return theirs;
    };
}

void no_holes_asked(TileScheduler& on) {
    const std::vector<double> none(kHeader, 0.0);
    for (int p = 1; p < on.processes(); ++p) detail::send_array(on, p, none.data(), none.size());
}

void holes_for_root(TileScheduler& on) {
    std::vector<double> header;
    detail::receive_array(on, 0, header);
    if (header.size() != kHeader) throw Error("the first process's question of the holes is not whole");
    if (!(header[0] > 0)) return;
    std::vector<float> xyz;
    detail::receive_array(on, 0, xyz);
    const auto frame = detail::PointTree::Frame::of(header.data() + 6);
    const PointCloud cloud = detail::cloud_of_flat(std::move(xyz), {header[3], header[4], header[5]}, &frame);
    const std::vector<double> found =
        holes_in_run(detail::tree_of(cloud), header[0], std::size_t(header[1]), std::size_t(header[2]));
    detail::send_array(on, 0, found.data(), found.size());
}

}  // namespace snvr
