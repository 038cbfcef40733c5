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
#include "check/slab_queries.hpp"
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

void detail::measure_groups(detail::PointDepths& depths) {
    // Chunks of neighbouring groups (they share bounds and working space), a few per
    // thread; the second pass once the first has found the shallowest measured depth.
    const std::size_t groups = depths.groups(), chunk = std::max<std::size_t>(16, groups / 64);
    const auto chunks = std::ptrdiff_t((groups + chunk - 1) / chunk);
#pragma omp parallel for schedule(dynamic, 1) if (chunks > 1)
    for (std::ptrdiff_t c = 0; c < chunks; ++c)
        depths.bound(std::size_t(c) * chunk, std::min(groups, std::size_t(c + 1) * chunk));
    const double shallowest = depths.shallowest();
#pragma omp parallel for schedule(dynamic, 1) if (chunks > 1)
    for (std::ptrdiff_t c = 0; c < chunks; ++c)
        depths.settle(std::size_t(c) * chunk, std::min(groups, std::size_t(c + 1) * chunk), shallowest);
}

namespace {

// What a share leaves to the slabs (slab_queries.hpp): its walls' rays (and where each goes
// among its walls), the points whose nearest triangle lies beyond it, those whose side
// alone a ray tells (with their distances); whether each point's depth goes to the
// percentile.
struct Undecided {
    detail::FarQuestions asked;
    std::vector<std::size_t> wall_at;
    std::vector<double> side_distance;
    std::vector<std::uint8_t> point_sampled, side_sampled;

    void add_points(const detail::PointDepths::Figures& f, const detail::PointTree& tree) {
        for (std::size_t i = 0; i < f.unresolved.size(); ++i) {
            asked.points.push_back(tree.point(f.unresolved[i]));
            point_sampled.push_back(f.unresolved_sampled[i]);
        }
        for (std::size_t i = 0; i < f.undecided.size(); ++i) {
            asked.sides.push_back(tree.point(f.undecided[i]));
            side_distance.push_back(f.undecided_distance[i]);
            side_sampled.push_back(f.undecided_sampled[i]);
        }
    }
    // The slabs' answers into a share's figures: its walls, the points inside and the least
    // depth of one, and the depths for the percentile (where taken).
    void settle(const detail::FarAnswers& a, std::vector<double>& walls, std::uint64_t& inside, double& depth_min,
                std::vector<double>* percentile) const {
        for (std::size_t i = 0; i < a.hits.size(); ++i) walls[wall_at[i]] = a.hits[i];
        const auto add = [&](double d, bool in, bool sampled) {
            if (in) {
                ++inside;
                depth_min = std::min(depth_min, d);
            }
            if (sampled && percentile) percentile->push_back(in ? d : -d);
        };
        for (std::size_t i = 0; i < a.depths.size(); ++i) add(a.depths[i].distance, a.depths[i].inside, point_sampled[i]);
        for (std::size_t i = 0; i < a.inside.size(); ++i) add(side_distance[i], a.inside[i] != 0, side_sampled[i]);
    }
};

// Every group of `depths` measured, its figures added to out's, the points it could not
// decide named as name(k) (k: by `tree`'s order) and left to the slabs.
template <class Name>
void add_depths(detail::PointDepths& depths, const detail::PointTree& tree, CheckShareFigures& out, Undecided& far,
                const Name& name) {
    detail::measure_groups(depths);
    const detail::PointDepths::Figures f = depths.figures();
    out.points_inside += f.inside;
    out.depth_min = std::min(out.depth_min, f.depth_min);
    for (const std::vector<std::uint32_t>* each : {&f.unresolved, &f.undecided})
        for (std::uint32_t k : *each) out.unresolved.push_back(name(k));
    far.add_points(f, tree);
}

// The figures of the groups of a range kept by this process (its places named where
// undecided), once its points are where the root's are: scaled as they were since filed,
// about the root's origin now.
void measure_kept(const CheckShare& share, const Mesh& m, const TriangleGrid& grid, detail::KeptRange* kept,
                  CheckShareFigures& out, Undecided& far) {
    const detail::PointTree& tree = detail::kept_as_first(kept, share.range_size, share.range_scaled, share.origin);
    detail::PointDepths::Part part;
    part.complete_within = share.reach;
    detail::PointDepths depths(m, grid, tree, share.voxel, share.range_groups, part);
    add_depths(depths, tree, out, far, [](std::uint32_t k) { return k; });
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
void measure_points(CheckShare& share, const Mesh& m, const TriangleGrid& grid, CheckShareFigures& out,
                    Undecided& far) {
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
    add_depths(*depths, tree, out, far,
               [&](std::uint32_t k) { return std::uint32_t(share.range_size + cloud.input_index(k)); });
}


// The walls of `measured` (NaN beyond the reach), and their rays where NaN.
std::vector<double> share_walls(const Mesh& m, const TriangleGrid& grid, const std::vector<Vec3>& normals,
                                const std::vector<std::uint32_t>& measured, double eps, double reach, Undecided& far) {
    std::vector<double> walls(measured.size(), std::numeric_limits<double>::infinity());
#pragma omp parallel for schedule(dynamic, 256) if (std::ptrdiff_t(walls.size()) > detail::kParallelItems)
    for (std::ptrdiff_t k = 0; k < std::ptrdiff_t(walls.size()); ++k) {
        const std::uint32_t v = measured[std::size_t(k)];
        const Vec3& n = normals[v];
        if (dot(n, n) == 0) continue;
        const double t = grid.first_hit(m.vertices[v], {-n[0], -n[1], -n[2]}, eps, v).t;
        walls[std::size_t(k)] = t <= reach ? t : std::numeric_limits<double>::quiet_NaN();
    }
    for (std::size_t k = 0; k < walls.size(); ++k)
        if (std::isnan(walls[k])) {
            const std::uint32_t v = measured[k];
            far.asked.walls.push_back({m.vertices[v], {-normals[v][0], -normals[v][1], -normals[v][2]}, v});
            far.wall_at.push_back(k);
        }
    return walls;
}


// A share measured: its walls (NaN beyond the reach) and points' figures, and what it
// leaves to the slabs (its walls' rays by the share's vertex numbers).
struct MeasuredShare {
    CheckShareFigures figures;
    Undecided far;
};

MeasuredShare measure_share(CheckShare share, detail::KeptRange* kept) {
    Mesh m;  // the share's own: it was given by value
    m.vertices = std::move(share.vertices);
    m.triangles = std::move(share.triangles);
    for (const auto& t : m.triangles)
        for (std::uint32_t v : t)
            if (v >= m.vertices.size()) throw InputError("measure_check_share: a triangle uses a vertex the share lacks");
    for (std::uint32_t v : share.measured)
        if (v >= m.vertices.size()) throw InputError("measure_check_share: a measured vertex the share lacks");
    if (share.points.size() % 3 != 0) throw InputError("measure_check_share: the points are not x y z in turn");
    MeasuredShare got;
    CheckShareFigures& out = got.figures;
    out.walls.assign(share.measured.size(), std::numeric_limits<double>::infinity());
    out.depth_min = std::numeric_limits<double>::infinity();
    if (m.triangles.empty()) {  // nothing near: no wall met, and the points' nearest lie beyond
        if (!share.range_groups.empty()) {
            const detail::PointTree& range = detail::kept_as_first(kept, share.range_size, share.range_scaled, share.origin);
            for (const auto& g : share.range_groups)
                for (std::uint32_t k = g[0]; k < g[1]; ++k) {
                    out.unresolved.push_back(k);
                    got.far.asked.points.push_back(range.point(k));
                }
        }
        for (std::size_t k = 0; k < share.points.size() / 3; ++k) {  // as the points' tree has them
            out.unresolved.push_back(std::uint32_t(share.range_size + k));
            const float* x = &share.points[3 * k];
            got.far.asked.points.push_back({share.origin[0] + double(x[0]), share.origin[1] + double(x[1]),
                                            share.origin[2] + double(x[2])});
        }
        got.far.point_sampled.assign(got.far.asked.points.size(), 0);
        return got;
    }
    const TriangleGrid grid(m);
    const std::vector<Vec3> normals = detail::unit_normals(m);
    // Each measured vertex as the whole shell measures it; a hit beyond the reach (or none)
    // may lie among triangles this share lacks: NaN, for the slabs (or the root) to measure.
    out.walls = share_walls(m, grid, normals, share.measured, share.epsilon, share.reach, got.far);
    if (!share.range_groups.empty()) measure_kept(share, m, grid, kept, out, got.far);
    measure_points(share, m, grid, out, got.far);
    return got;
}

}  // namespace

CheckShareFigures measure_check_share(CheckShare share) { return measure_share(std::move(share), nullptr).figures; }


CheckShareFigures detail::measure_check_share(CheckShare share, KeptRange* kept, const std::vector<std::uint32_t>& measured_whole,
                                              const SlabMesh& slabs, TileScheduler& on, const SlabAnswers* ready) {
    const double eps = share.epsilon;
    if (measured_whole.size() != share.measured.size())
        throw InputError("measure_check_share: one number in the whole mesh a measured vertex");
    MeasuredShare got = measure_share(std::move(share), kept);
    // What the share could not decide, asked of the slabs.
    for (std::size_t i = 0; i < got.far.wall_at.size(); ++i) got.far.asked.walls[i].vertex = measured_whole[got.far.wall_at[i]];
    CheckShareFigures& out = got.figures;
    got.far.settle(ask_slabs(slabs, eps, got.far.asked, on, ready), out.walls, out.points_inside, out.depth_min, nullptr);
    out.unresolved.clear();
    return out;
}

detail::FirstShare detail::measure_first_share(ShareMesh share, const PointTree& points, double voxel,
                                               const std::vector<PointDepths::Span>& spans,
                                               const std::vector<std::uint8_t>& elsewhere, double eps, double reach,
                                               const SlabMesh& slabs, TileScheduler& on, const SlabAnswers* ready,
                                               const std::function<void()>& before_asking, const Told& told) {
    Mesh m;
    m.vertices = std::move(share.vertices);
    m.triangles = std::move(share.triangles);
    FirstShare got;
    Undecided far;
    {
        const TriangleGrid grid(m);
        const std::vector<Vec3> normals = unit_normals(m);
        PointDepths::Part part;
        part.complete_within = reach;
        part.sampled = true;
        PointDepths depths(m, grid, points, voxel, spans, false, false, elsewhere.empty() ? nullptr : &elsewhere, &part);
        // How far they have come: a wall a unit, a group two.
        const std::size_t all = share.measured.size() + 2 * depths.groups();
        if (told) told(0, all);
        got.walls = share_walls(m, grid, normals, share.measured, eps, reach, far);
        for (std::size_t i = 0; i < far.wall_at.size(); ++i) far.asked.walls[i].vertex = share.measured_whole[far.wall_at[i]];
        if (told) told(share.measured.size(), all);
        measure_groups(depths);
        got.points = depths.figures();
        if (told) told(all, all);
    }
    far.add_points(got.points, points);
    if (before_asking) before_asking();
    const FarAnswers answers = ask_slabs(slabs, eps, far.asked, on, ready);
    got.points_asked = answers.points_asked;
    PointDepths::Figures& f = got.points;
    std::uint64_t inside = f.inside;
    far.settle(answers, got.walls, inside, f.depth_min, &f.depths);
    f.inside = std::size_t(inside);
    f.unresolved.clear();
    f.undecided.clear();
    return got;
}

}  // namespace snvr
