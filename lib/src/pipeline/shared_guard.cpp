// The depth guard's first search shared among a tiled run's processes (shared_guard.hpp).
// What the first sends each other process: the question (the aim, the depth, its points'
// origin, its count of the other's range, then every scale factor since the filing; the
// question alone, empty, where there is no search), then the mesh's vertices and
// triangles; what comes back: the vertices near its points, then the close pairs, its
// points named by their places in its range.
#include "pipeline/shared_guard.hpp"

#include <cstdint>
#include <string>
#include <vector>

#include "geometry/point_tree.hpp"
#include "snvr/error.hpp"
#include "solver/sent_arrays.hpp"
#include "solver/shared_filing.hpp"

namespace snvr::detail {

namespace {

constexpr std::size_t kQuestionHead = 6;  // aim, depth, origin x y z, the range's size; then the scale factors

}  // namespace

GuardSearchShared::GuardSearchShared(TileScheduler* on, const PointCloud& points, TileFacts& facts)
    : on_(on && on->processes() > 1 ? on : nullptr) {
    if (!on_) return;
    const PointTree& tree = tree_of(points);
    const std::size_t processes = std::size_t(on_->processes());
    if (tree.shared_ranges.size() != processes + 1) return;  // the others' ranges are not these points
    hook_.here_end = tree.shared_ranges[1];
    hook_.ask = [this, &tree, &facts](const Mesh& mesh, double aim, double depth) {
        asked_ = true;
        for (int p = 1; p < on_->processes(); ++p) {
            const std::size_t b = tree.shared_ranges[std::size_t(p)], e = tree.shared_ranges[std::size_t(p) + 1];
            std::vector<double> question{aim, depth, tree.origin[0], tree.origin[1], tree.origin[2], double(e - b)};
            question.insert(question.end(), tree.scaled_since.begin(), tree.scaled_since.end());
            send_array(*on_, p, question.data(), question.size());
            send_array(*on_, p, mesh.vertices.data(), mesh.vertices.size());
            send_array(*on_, p, mesh.triangles.data(), mesh.triangles.size());
            facts.guard_points += e - b;
            facts.guard_bytes += mesh.vertices.size() * sizeof(mesh.vertices[0]) +
                                 mesh.triangles.size() * sizeof(mesh.triangles[0]);
        }
    };
    hook_.collect = [this, &tree] {
        GuardFound all;
        for (int p = 1; p < on_->processes(); ++p) {
            const std::size_t b = tree.shared_ranges[std::size_t(p)], e = tree.shared_ranges[std::size_t(p) + 1];
            GuardFound theirs;
            receive_array(*on_, p, theirs.near_vertices);
            receive_array(*on_, p, theirs.close);
            all.near_vertices.insert(all.near_vertices.end(), theirs.near_vertices.begin(), theirs.near_vertices.end());
            for (PointTriangle c : theirs.close) {
                if (c.point >= e - b)
                    throw Error("process " + std::to_string(p) + " named a point its range does not have");
                c.point += std::uint32_t(b);
                all.close.push_back(c);
            }
        }
        return all;
    };
}

void GuardSearchShared::done() {
    if (!on_ || asked_) return;
    for (int p = 1; p < on_->processes(); ++p) send_array(*on_, p, static_cast<const double*>(nullptr), 0);
}

void answer_guard_search(TileScheduler& on, KeptRange* kept) {
    std::vector<double> question;
    receive_array(on, 0, question);
    if (question.empty()) return;  // no search
    if (question.size() < kQuestionHead) throw Error("the depth guard's question from the first process is not whole");
    const std::vector<double> scaled(question.begin() + std::ptrdiff_t(kQuestionHead), question.end());
    const PointTree& tree =
        kept_as_first(kept, std::size_t(question[5]), scaled, Vec3{question[2], question[3], question[4]});
    Mesh mesh;
    receive_array(on, 0, mesh.vertices);
    receive_array(on, 0, mesh.triangles);
    for (const auto& t : mesh.triangles)
        for (std::uint32_t v : t)
            if (v >= mesh.vertices.size()) throw Error("the depth guard's mesh from the first process uses a missing vertex");
    const GuardFound found = guard_search(mesh, tree, question[0], question[1]);
    send_array(on, 0, found.near_vertices.data(), found.near_vertices.size());
    send_array(on, 0, found.close.data(), found.close.size());
}

}  // namespace snvr::detail
