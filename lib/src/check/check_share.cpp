// measure_check_share (quality.hpp): another process's share of a tiled run's check,
// measured on the triangles the root gave it, as the whole shell would measure it where
// those triangles decide.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "check/point_depths.hpp"
#include "check/walls.hpp"
#include "geometry/point_tree.hpp"
#include "geometry/vec3_math.hpp"
#include "mesh/triangle_grid.hpp"
#include "parallel_sizes.hpp"
#include "snvr/error.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/quality.hpp"
#include "solver/shared_filing.hpp"

namespace snvr {

namespace {

// Every group of `depths` measured, its figures added to out's, the points it could not
// decide named as name(k) (k: by its tree's order).
template <class Name>
void add_depths(detail::PointDepths& depths, CheckShareFigures& out, const Name& name) {
    depths.bound(0, depths.groups());
    depths.settle(0, depths.groups(), depths.shallowest());
    const detail::PointDepths::Figures f = depths.figures();
    out.points_inside += f.inside;
    out.depth_min = std::min(out.depth_min, f.depth_min);
    for (std::uint32_t k : f.unresolved) out.unresolved.push_back(name(k));
}

// The figures of the groups of a range kept by this process (its places named where
// undecided), once its points are where the root's are: scaled as they were since filed,
// about the root's origin now.
void measure_kept(const CheckShare& share, const Mesh& m, const TriangleGrid& grid, detail::KeptRange* kept,
                  CheckShareFigures& out) {
    const detail::PointTree& tree = detail::kept_as_first(kept, share.range_size, share.range_scaled, share.origin);
    detail::PointDepths::Part part;
    part.complete_within = share.reach;
    detail::PointDepths depths(m, grid, tree, share.voxel, share.range_groups, part);
    add_depths(depths, out, [](std::uint32_t k) { return k; });
}

// The root's groups of the points given (counts of consecutive points) as runs of the
// tree's order, where the points kept the order they came in (filed in the root's frame
// they do); else none (the tree's own leaves group them).
std::vector<std::array<std::uint32_t, 2>> root_groups(const std::vector<std::uint32_t>& counts,
                                                      const detail::PointTree& tree) {
    std::vector<std::array<std::uint32_t, 2>> runs;
    if (counts.empty()) return runs;
    std::uint64_t all = 0;
    for (std::uint32_t c : counts) {
        if (c == 0) throw InputError("measure_check_share: an empty group of points");
        all += c;
    }
    if (all != tree.size()) throw InputError("measure_check_share: the groups do not count the points given");
    for (std::size_t k = 0; k < tree.size(); ++k)
        if (tree.input[k] != k) return runs;
    runs.reserve(counts.size());
    std::uint32_t at = 0;
    for (std::uint32_t c : counts) {
        runs.push_back({at, at + c});
        at += c;
    }
    return runs;
}

// The share's points' figures; those whose search or side would leave its triangles
// (a ray's crossings, a nearest triangle beyond the reach) are named instead (after its
// range's places).
void measure_points(CheckShare& share, const Mesh& m, const TriangleGrid& grid, CheckShareFigures& out) {
    if (share.points.empty()) return;
    const auto frame = detail::PointTree::Frame::of(share.points_frame.data());
    const PointCloud cloud =
        detail::cloud_of_flat(std::move(share.points), share.origin, frame.scale > 0 ? &frame : nullptr);
    const detail::PointTree& tree = detail::tree_of(cloud);
    detail::PointDepths::Part part;
    part.complete_within = share.reach;
    const std::vector<std::array<std::uint32_t, 2>> runs = root_groups(share.point_groups, tree);
    std::optional<detail::PointDepths> depths;
    if (!runs.empty())
        depths.emplace(m, grid, tree, share.voxel, runs, part);
    else
        depths.emplace(m, grid, tree, share.voxel, false, false, nullptr, &part);
    add_depths(*depths, out, [&](std::uint32_t k) { return std::uint32_t(share.range_size + cloud.input_index(k)); });
}

}  // namespace

CheckShareFigures measure_check_share(CheckShare share) { return detail::measure_check_share(std::move(share), nullptr); }

CheckShareFigures detail::measure_check_share(CheckShare share, KeptRange* kept) {
    Mesh m;  // the share's own: it was given by value
    m.vertices = std::move(share.vertices);
    m.triangles = std::move(share.triangles);
    for (const auto& t : m.triangles)
        for (std::uint32_t v : t)
            if (v >= m.vertices.size()) throw InputError("measure_check_share: a triangle uses a vertex the share lacks");
    for (std::uint32_t v : share.measured)
        if (v >= m.vertices.size()) throw InputError("measure_check_share: a measured vertex the share lacks");
    if (share.points.size() % 3 != 0) throw InputError("measure_check_share: the points are not x y z in turn");
    CheckShareFigures out;
    out.walls.assign(share.measured.size(), std::numeric_limits<double>::infinity());
    out.depth_min = std::numeric_limits<double>::infinity();
    if (m.triangles.empty()) {  // nothing near: no wall met, and the points' nearest lie beyond
        for (const auto& g : share.range_groups)
            for (std::uint32_t k = g[0]; k < g[1]; ++k) out.unresolved.push_back(k);
        for (std::size_t k = 0; k < share.points.size() / 3; ++k) out.unresolved.push_back(std::uint32_t(share.range_size + k));
        return out;
    }
    const TriangleGrid grid(m);
    const std::vector<Vec3> normals = detail::unit_normals(m);
    // Each measured vertex as the whole shell measures it; a hit beyond the reach (or none)
    // may lie among triangles this share lacks: NaN, for the root to measure.
#pragma omp parallel for schedule(dynamic, 256) if (std::ptrdiff_t(out.walls.size()) > detail::kParallelItems)
    for (std::ptrdiff_t k = 0; k < std::ptrdiff_t(out.walls.size()); ++k) {
        const std::uint32_t v = share.measured[std::size_t(k)];
        const Vec3& n = normals[v];
        if (dot(n, n) == 0) continue;
        const double t = grid.first_hit(m.vertices[v], {-n[0], -n[1], -n[2]}, share.epsilon, v).t;
        out.walls[std::size_t(k)] = t <= share.reach ? t : std::numeric_limits<double>::quiet_NaN();
    }
    if (!share.range_groups.empty()) measure_kept(share, m, grid, kept, out);
    measure_points(share, m, grid, out);
    return out;
}

}  // namespace snvr
