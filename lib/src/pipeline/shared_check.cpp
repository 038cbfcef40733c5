// The check shared among a tiled run's processes (shared_check.hpp).
#include "pipeline/shared_check.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "check/point_depths.hpp"
#include "check/slab_mesh.hpp"
#include "check/slab_queries.hpp"
#include "check/slab_shares.hpp"
#include "check/slab_topology.hpp"
#include "check/walls.hpp"
#include "geometry/point_tree.hpp"
#include "geometry/vec3_math.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh_io.hpp"
#include "solver/sent_arrays.hpp"
#include "solver/tile_plan.hpp"

namespace snvr::detail {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The check's work in walls (one vertex's wall: 0.47-0.9 us on one thread, the city block's
// and the bunny's; writing the mesh meanwhile is reckoned at 0.8 us a wall). The first
// process's own part, done while the others measure: the grid and the edges and topology
// 1.0 a vertex (0.46 us on the bunny at 512, 0.68 on the city block, and its sampled
// groups' frames on a dense scan: at 0.7 the 50 M-point city block's first finished 1.9-
// 2.6 s after the other, at 1.0 0.8-1.9 s; at 0.6 with no cost for the others' filing of
// their shares, the bunny's 0.1-0.2 s before the other). Another process first files its
// share's triangles: an eighth of a wall more for each wall it measures (the bunny: 0.3 s
// for 1.4 M walls, 1.0 s for 3.3 M on the city block). The points' depths go by groups of
// neighbours, about 7.5 us a group whatever its points (9 walls; the 50 M-point city block
// at 1024, 30 points a group at 250 ns, and the 200 M-point one, 91 at 90 ns). A point
// given to another process costs the first 25 ns (gathered and sent) and the other about
// 64 ns more than measuring it here (filed in the first's order and frame, each key made
// once), so that a dense scan's depths mostly stay and a sparse one's go: the 200 M-point
// block's other process is given 84 M points and ends with the first (before each key was
// made once, at 0.08 it was given 91 M and its check took 24.3 s where 18.9; at 0.13, 68 M).
constexpr double kWallSeconds = 0.8e-6;
// The first's own part of the check, beside its share: its slab's topology (counted as the
// others begin: 0.83 s for the 50 M-point city block's first slab of 2.2 M vertices), its
// share's merging, and its slab's grid for the questions no share decides (0.5-0.7 s). At
// 1.0 a vertex (when it measured on the whole mesh) the first ended 2.5-3 s after the
// other; at 0.3 the other waited for it 1-2 s (the check 15.1-16.5 s); at 0.6, 13.8-14.8 s.
constexpr double kFirstWorkAVertex = 0.6;
constexpr double kShareAWall = 0.12;
constexpr double kWorkAGroup = 9;
constexpr double kGiveAPoint = 0.03;
constexpr double kSendAPoint = 0.08;
// A group another process measures in its own range of the points (kept since the
// filing: neither sent nor filed again) costs it this much of kWorkAGroup (the 50 M-point
// city block at 1024 on two processes: 6.5 us a group there, 9.4 at the first, when 0.7
// was set; 7.3-7.6 us once the slabs counted the topology, the other then ending 2-2.7 s
// after the first, its mesh written).
constexpr double kRangeGroupShare = 1.0;
// Another process's answers for its slab (a grid over its triangles), made before it
// measures, a vertex of its slab: 0.5 (0.6 s for the first slab of the 50 M-point city
// block at 1024 cells, 2.2 M vertices; the other's, made after its share, 1.2 s).
constexpr double kAnswersAVertex = 0.5;

// What a tile holds of the check's work: its vertices' walls, and its points' groups.
struct TileWork {
    double walls = 0;
    std::size_t groups = 0, points = 0;
    double walls_measured(bool elsewhere) const { return walls * (elsewhere ? 1 + kShareAWall : 1); }
    double depths(bool sent) const { return kWorkAGroup * double(groups) + (sent ? kSendAPoint * double(points) : 0); }
};

// Who measures the walls and the depths in each tile: the walls of the tiles another
// process is near (`near`: it ran them, or holds most of their points), that process
// (their triangles are in its share already); the rest, the most work first, whoever
// would be done first with it (the depths costing more where their points must be sent),
// each process's work so far (`work`: the first's own part of the check; the points'
// depths each measures in its own range) counted. (The first's tiles' walls dealt in turn
// instead, the others waited for it: the bunny at 512 on two processes, its check 1.75 s;
// a tile's depths always with its runner, the dense city block's took longer than the
// first measuring them all.)
struct Measurers {
    std::vector<int> walls, depths;
};
Measurers check_measurers(const std::vector<int>& near, const std::vector<TileWork>& in, std::vector<double> work) {
    Measurers by{std::vector<int>(in.size(), 0), std::vector<int>(in.size(), 0)};
    const int processes = int(work.size());
    struct Item {
        std::size_t tile;
        bool depths;
        double cost;  // here
    };
    std::vector<Item> dealt;
    for (std::size_t t = 0; t < in.size(); ++t) {
        const int p = t < near.size() ? near[t] : 0;
        if (p > 0 && p < processes) {
            by.walls[t] = p;
            work[std::size_t(p)] += in[t].walls_measured(true);
        } else if (in[t].walls > 0) {
            dealt.push_back({t, false, in[t].walls});
        }
        if (in[t].groups > 0) dealt.push_back({t, true, in[t].depths(false)});
    }
    std::stable_sort(dealt.begin(), dealt.end(), [](const Item& a, const Item& b) { return a.cost > b.cost; });
    for (const Item& item : dealt) {
        std::size_t best = 0;
        double done = kInf;
        for (std::size_t p = 0; p < work.size(); ++p) {
            const double cost = item.depths ? in[item.tile].depths(p != 0) : in[item.tile].walls_measured(p != 0);
            if (work[p] + cost < done) done = work[p] + cost, best = p;
        }
        work[best] = done;
        if (item.depths && best != 0) work[0] += kGiveAPoint * double(in[item.tile].points);
        (item.depths ? by.depths : by.walls)[item.tile] = int(best);
    }
    return by;
}

// The points of the groups given to one process: runs [begin, end) of the cloud's order.
struct PointsGiven {
    std::vector<std::array<std::uint32_t, 2>> runs;
    std::size_t points = 0;
    void add(std::uint32_t begin, std::uint32_t end) {
        runs.push_back({begin, end});
        points += end - begin;
    }
    std::size_t count() const { return points; }
    // Their coordinates about the tree's origin, x y z in turn.
    PointArray<float> coordinates(const PointTree& tree) const {
        PointArray<float> xyz(3 * count());
        float* to = xyz.data();
        for (const auto& run : runs)
            for (std::uint32_t k = run[0]; k < run[1]; ++k, to += 3) std::memcpy(to, tree.xyz[k].data(), 3 * sizeof(float));
        return xyz;
    }
};

// The first's word on the check by slabs: what they are, whether the slabs measure the
// check whole (not with the surface's figures), whether they are the shell's only copy,
// then the path whose format holds the coordinates (empty: as they are); where the slabs'
// vertices moved, each's own.
void tell_slab_check(TileScheduler& on, SlabsAre are, bool by_slabs, bool kept, const SlabsForCheck& slabs,
                     const Mesh& mesh, const std::vector<std::size_t>& starts) {
    const std::string word = std::string(1, char(are)) + char(by_slabs) + char(kept) + slabs.written_as;
    for (int q = 1; q < on.processes(); ++q) {
        send_array(on, q, word.data(), word.size());
        if (are == SlabsAre::Moved)
            send_array(on, q, mesh.vertices.data() + starts[std::size_t(q)], starts[std::size_t(q) + 1] - starts[std::size_t(q)]);
    }
}

// Where the slabs are the shell's only copy: the format's rule on the moves of every slab's
// vertices rounded as written (the largest of each figure over the processes), which the
// first tells.
void require_slabs_written(TileScheduler& on, const WrittenMoves& mine, const std::string& written_as, double voxel) {
    std::vector<double> most{-mine.largest, -mine.farthest};
    on.least(most);
    if (on.rank() == 0) require_written_moves({-most[0], -most[1]}, written_as, voxel);
}

}  // namespace

void serve_check(TileScheduler& on, Mesh slab, KeptRange* kept) {
    std::string word;
    receive_array(on, 0, word);
    if (word.size() < 3) throw Error("the first process's word on the check is not whole");
    const auto are = SlabsAre(word[0]);
    const bool by_slabs = word[1] != 0, slabs_kept = word[2] != 0;
    const std::string written_as = word.substr(3);
    if (are == SlabsAre::Other) slab = Mesh();  // the first's slab is the whole shell
    else if (are == SlabsAre::Moved) receive_into(on, 0, slab.vertices.data(), slab.vertices.size());
    else if (!written_as.empty()) {
        if (slabs_kept) require_slabs_written(on, written_moves(slab.vertices.data(), slab.vertices.size(), written_as), written_as, 0);
        slab = as_written(std::move(slab), written_as);
    }
    SlabMesh slabs(SlabPart::of(slab), on);  // kept for the questions no share decides
    CheckDeal deal = take_check_grid(on);
    count_by_tiles(slabs, deal, on);
    if (by_slabs) {
        SlabTopology topology(slabs, on);
        topology.count();
        topology.send_to_first();
    }
    take_check_deal(on, deal);
    std::uint64_t bytes = 0;
    ShareMesh mine = share_from_slabs(slabs, deal, on, bytes);
    // Its slab's answers to what no share decides, made before it measures (which the deal
    // reckons: kAnswersAVertex): made before the deal, they held the first in the shares'
    // exchange (0.7 s on the 50 M-point city block); made when asked, the first waited for
    // them at the end (0.7 s at 1024 cells, 2.7 s at 2048, where they took 1.2 and 6 s).
    std::optional<SlabAnswers> answers;
    if (by_slabs) answers.emplace(slabs);
    CheckShare share = on.check_share();
    share.vertices = std::move(mine.vertices);
    share.triangles = std::move(mine.triangles);
    share.measured = std::move(mine.measured);
    on.send_check(measure_check_share(std::move(share), kept, mine.measured_whole, slabs, on, answers ? &*answers : nullptr));
    // Which of the whole mesh's vertices its walls are.
    send_array(on, 0, mine.measured_whole.data(), mine.measured_whole.size());
    if (slabs_kept) give_slab(slabs, on);
}

MeshQuality check_sharing(const Mesh& mesh, const PointCloud& points, const Result& run, bool surface,
                          TileScheduler& on, TileFacts& facts, const SlabsForCheck& slabs,
                          const std::function<void()>& meanwhile, double meanwhile_seconds, const Told& told) {
    // The topology by the slabs: the ghosts exchanged first; the others count theirs while
    // this one deals the shares, and send them before they take theirs.
    const std::vector<std::size_t>& starts = facts.slab_starts;
    const bool kept = facts.slabs_kept;  // `mesh` is this process's slab, the others hold theirs
    const bool whole = starts.size() == std::size_t(on.processes()) + 1 &&
                       (kept ? starts[1] == mesh.vertices.size() && facts.slab_triangles == mesh.triangles.size()
                             : starts.back() == mesh.vertices.size() && facts.slab_triangles <= mesh.triangles.size());
    const SlabsAre are = surface || !whole ? SlabsAre::Other : slabs.are;
    if (kept && (are != SlabsAre::Kept || !slabs.handover))
        throw Error("the check: the slabs are the shell's only copy, but not as they were kept, or not handed on");
    // Without the surface's figures the slabs measure the whole check: the topology, every
    // wall and depth, and what no share decides; this process's slab is the shell's first
    // vertices and triangles, or all of it where the others' are not its parts.
    const bool by_slabs = !surface;
    tell_slab_check(on, are, by_slabs, kept, slabs, mesh, starts);
    if (kept && !slabs.written_as.empty()) require_slabs_written(on, slabs.moves, slabs.written_as, run.domain.h);
    facts.check_topology_slabs = are != SlabsAre::Other;
    const int processes = on.processes();
    if (processes > 64) throw ParameterError("the check is shared among at most 64 processes");
    SlabMesh held(are != SlabsAre::Other ? SlabPart::of(mesh, starts[1], facts.slab_triangles) : SlabPart::of(mesh), on);
    // What the deal goes by, counted by the slabs: each tile's vertices, the longest edge.
    const Domain& d = run.domain;
    CheckDeal deal;
    deal.grid = d;
    deal.core = run.tiles.core_cells;
    send_check_grid(on, deal);
    const SlabTiles counted = count_by_tiles(held, deal, on);
    std::optional<SlabTopology> topology;
    if (by_slabs) topology.emplace(held, on);
    const std::size_t tiles = deal.tiles();
    const auto tile_at = [&deal](const Vec3& x) { return deal.tile_at(x); };
    const std::size_t nv = held.starts().back();
    std::vector<TileWork> work_in(tiles);
    for (std::size_t t = 0; t < tiles; ++t) work_in[t].walls = double(counted.vertices[t]);
    // The points' depths go by their groups (PointDepths'), each to its centre's tile; the
    // groups sampled for the percentile stay here, so that it is taken over the same points
    // as alone. Those wider than a voxel (a sparse scan's lone leaves) are cut narrower
    // first: whole, their points may lie beyond where a share holds every triangle near
    // (they stayed here: the 12.5 M-point block at 2048 cells on two processes, the first
    // measured 12 s after the other was done). The surface's figures (every point by
    // rays) stay here too.
    const PointTree& tree = tree_of(points);
    std::vector<PointDepths::Span> spans;  // kept for this process's own measuring
    if (!surface) spans = PointDepths::narrowed(tree, d.h, d.h, PointDepths::group_spans(tree, d.h, false));
    constexpr std::uint32_t kHere = std::numeric_limits<std::uint32_t>::max();  // measured here
    std::vector<std::uint32_t> group_tile(spans.size());  // freed once dealt
    std::vector<std::uint32_t> sampled_tiles;             // where the groups sampled lie
    std::vector<double> work(std::size_t(processes), 0);
    work[0] = kFirstWorkAVertex * double(nv) + meanwhile_seconds / kWallSeconds;
    if (by_slabs && are != SlabsAre::Other)
        for (int p = 1; p < processes; ++p)
            work[std::size_t(p)] += kAnswersAVertex * double(starts[std::size_t(p) + 1] - starts[std::size_t(p)]);
    // Where the others kept their ranges of the points filed by all, each measures the
    // groups within its range where they are (none sent, none filed again); the rest (the
    // first's range's, and all where there are no ranges) are dealt by tile, their points
    // sent to whoever measures them elsewhere.
    const std::vector<std::size_t>& bounds = tree.shared_ranges;
    const bool by_ranges = bounds.size() == std::size_t(processes) + 1;
    std::vector<std::uint8_t> group_range(by_ranges ? spans.size() : 0);  // its range's process (0: dealt)
    std::vector<std::uint32_t> range_groups(by_ranges ? tiles * std::size_t(processes) : 0);  // a tile's, by range
    for (std::size_t g = 0; g < spans.size(); ++g) {
        const PointDepths::Span& s = spans[g];
        Vec3 centre;
        for (std::size_t a = 0; a < 3; ++a) centre[a] = 0.5 * (s.lo[a] + s.hi[a]);
        if (s.sampled) {
            work[0] += kWorkAGroup;
            group_tile[g] = kHere;
            sampled_tiles.push_back(tile_at(centre));
            continue;
        }
        group_tile[g] = tile_at(centre);
        if (by_ranges) {  // the process whose range holds the whole group (the first where it spans a bound)
            const std::size_t p = std::size_t(std::upper_bound(bounds.begin(), bounds.end(), std::size_t(s.begin)) -
                                              bounds.begin()) - 1;
            const std::size_t q = p < std::size_t(processes) && s.end <= bounds[p + 1] ? p : 0;
            ++range_groups[group_tile[g] * std::size_t(processes) + q];
            if (q > 0) {
                group_range[g] = std::uint8_t(q);
                work[q] += kRangeGroupShare * kWorkAGroup;
                continue;
            }
        }
        ++work_in[group_tile[g]].groups;
        work_in[group_tile[g]].points += s.end - s.begin;
    }
    // A tile's walls are nearest the process that ran it, or that holds most of its points.
    std::vector<int> walls_near = run.tiles.owners;
    if (by_ranges) {
        walls_near.assign(tiles, 0);
        for (std::size_t t = 0; t < tiles; ++t)
            for (int p = 1; p < processes; ++p)
                if (range_groups[t * std::size_t(processes) + std::size_t(p)] >
                    range_groups[t * std::size_t(processes) + std::size_t(walls_near[t])])
                    walls_near[t] = p;
    }
    const Measurers measurer = check_measurers(walls_near, work_in, work);
    // A wall thicker than this, or a point's nearest triangle farther, the first process
    // measures: the shells' walls are about twice the offset, a point inside lies within it.
    const double reach = 4 * run.offset + 2 * d.h;
    CheckElsewhere elsewhere;
    if (surface) {  // measured on the whole mesh here: the vertices whose walls are the others'
        elsewhere.vertex.assign(nv, 0);
        for (std::size_t v = 0; v < nv; ++v) elsewhere.vertex[v] = measurer.walls[tile_at(mesh.vertices[v])] != 0;
    }
    const auto depths_by = [&](std::size_t g) -> std::size_t {
        if (group_tile[g] == kHere) return 0;
        return by_ranges && group_range[g] ? group_range[g] : std::size_t(measurer.depths[group_tile[g]]);
    };
    if (!spans.empty()) {
        elsewhere.groups.assign(spans.size(), 0);
        for (std::size_t g = 0; g < spans.size(); ++g) elsewhere.groups[g] = depths_by(g) != 0;
    }
    // What each other process measures: its range's groups and the groups' points given
    // it; and the tiles where it measures something.
    std::vector<PointsGiven> given(static_cast<std::size_t>(processes)), ranged(static_cast<std::size_t>(processes));
    deal.measures_in.resize(tiles);
    deal.walls_by.resize(tiles);
    for (std::size_t t = 0; t < tiles; ++t) {
        deal.measures_in[t] = std::uint64_t(1) << measurer.walls[t] | std::uint64_t(1) << measurer.depths[t];
        deal.walls_by[t] = std::uint8_t(measurer.walls[t]);
    }
    for (std::size_t g = 0; g < spans.size(); ++g)
        if (elsewhere.groups[g]) {
            (by_ranges && group_range[g] ? ranged : given)[depths_by(g)].add(spans[g].begin, spans[g].end);
            deal.measures_in[group_tile[g]] |= std::uint64_t(1) << depths_by(g);
        }
    for (std::uint32_t t : sampled_tiles) deal.measures_in[t] |= 1;
    elsewhere.spans = std::move(spans);  // made once
    std::vector<std::uint32_t>().swap(group_tile);
    std::vector<std::uint8_t>().swap(group_range);
    const double eps = wall_epsilon(held.box()[0], held.box()[1]);  // the whole shell's
    std::optional<SlabShares> shares;
    std::optional<SlabAnswers> answers;
    {
        // A triangle within the reach of a point or vertex in a tile has a corner within the
        // reach and its longest edge of the tile; a point's group and its run reach 3 voxels
        // beyond its tile.
        deal.widened = reach + counted.longest_edge + 3 * d.h;
        // Its slab's answers to what no share decides, made while the others count their
        // topology (it waited 0.4 s for them on the 50 M-point city block; made when asked,
        // 0.6 s at the end, which the others waited for).
        if (by_slabs) answers.emplace(held);
        if (topology) topology->take_others();  // sent before they take the deal
        send_check_deal(on, deal);
        // Each slab gives the others their triangles: the share's mesh, from this one's too
        // (merged once the others have their points).
        shares.emplace(held, deal, on);
        facts.check_bytes += shares->bytes();
        for (int p = 1; p < processes; ++p) {
            facts.check_points += given[std::size_t(p)].count() + ranged[std::size_t(p)].count();
            {  // its points first, freed before the rest is made
                const PointArray<float> xyz = given[std::size_t(p)].coordinates(tree);
                facts.check_bytes += xyz.size() * sizeof(float);
                on.give_check_points(p, tree.origin, xyz.data(), xyz.size());
            }
            CheckShare share;
            // Its points in the groups dealt (its own tree's leaves could join them wider).
            share.point_groups.reserve(given[std::size_t(p)].runs.size());
            for (const auto& r : given[std::size_t(p)].runs) share.point_groups.push_back(r[1] - r[0]);
            facts.check_bytes += share.point_groups.size() * sizeof(share.point_groups[0]);
            if (by_ranges) {  // the points of its range's groups are its own already, where the first's are
                const std::size_t b = bounds[std::size_t(p)];
                share.range_groups.reserve(ranged[std::size_t(p)].runs.size());
                for (const auto& r : ranged[std::size_t(p)].runs)
                    share.range_groups.push_back({std::uint32_t(r[0] - b), std::uint32_t(r[1] - b)});
                share.range_size = bounds[std::size_t(p) + 1] - b;
                share.range_scaled = tree.scaled_since;
                facts.check_bytes += share.range_groups.size() * sizeof(share.range_groups[0]);
            }
            share.epsilon = eps;
            share.reach = reach;
            share.voxel = d.h;
            share.points_frame = tree.frame().figures();  // the points given follow its order
            on.give_check(p, share);
        }
    }
    if (by_slabs) {
        // Its own slab counted as the others begin measuring their shares (within measure_
        // sharing's topology task it ran late in the check: 1.5-1.9 s on the 50 M-point city
        // block's first slab, 0.83-0.85 s here); its own share measured, then `meanwhile`.
        const auto started = std::chrono::steady_clock::now();
        ShareMesh first_share = shares->mine();
        shares.reset();
        topology->count();
        std::vector<std::uint8_t> measured(nv, 0);  // each vertex's wall once
        const auto mark = [&](const std::vector<std::uint32_t>& ids, const std::string& from) {
            for (std::uint32_t v : ids) {
                if (v >= nv || measured[v]) throw Error("the walls from " + from + " name a vertex twice or none");
                measured[v] = 1;
            }
        };
        mark(first_share.measured_whole, "this process");
        // Where the slabs are kept, this one's goes to the sink first, while the others measure.
        const std::function<void()> then = [&] {
            if (kept) slabs.handover->own(held);
            if (meanwhile) meanwhile();
        };
        FirstShare own = measure_first_share(std::move(first_share), tree, d.h, elsewhere.spans, elsewhere.groups, eps,
                                             reach, held, on, &*answers, then, told);
        facts.check_points_far = own.points_asked;
        std::vector<double>& walls = own.walls;
        PointDepths::Figures& depths = own.points;
        for (int p = 1; p < processes; ++p) {
            const CheckShareFigures got = on.take_check(p);
            std::vector<std::uint32_t> ids;  // the vertices whose walls these are
            receive_array(on, p, ids);
            const std::string from = "process " + std::to_string(p);
            if (got.walls.size() != ids.size() || !got.unresolved.empty())
                throw Error("the check's figures from " + from + " are not whole");
            mark(ids, from);
            walls.insert(walls.end(), got.walls.begin(), got.walls.end());
            facts.check_walls += ids.size();
            depths.inside += got.points_inside;
            depths.depth_min = std::min(depths.depth_min, got.depth_min);
        }
        // Vertices in no triangle: no wall anywhere (infinity, as alone).
        walls.resize(nv, std::numeric_limits<double>::infinity());
        MeshQuality q = shell_figures(topology->joined(), points.size(), run.offset, d.h, walls, depths);
        q.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        if (kept) slabs.handover->rest(held);
        return q;
    }
    // Vertices of another's tiles in no triangle: no wall anywhere (infinity, as alone).
    // `meanwhile` runs first, once this process has measured its own part: while the others
    // finish theirs, or, where this one has the most to do, with their cores free for what
    // the system does on its behalf (writing a file takes twice as long with both cores
    // busy: the city block's 440 MB of STL 0.25 s after the check, 0.77 s beside it).
    elsewhere.fill = [&](std::vector<double>& wall, PointDepths::Figures& depths) {
        if (meanwhile) meanwhile();
        // The others ask the slabs (this one's the whole shell) what their shares cannot decide.
        facts.check_points_far = ask_slabs(held, eps, FarQuestions(), on).points_asked;
        for (std::size_t v = 0; v < wall.size(); ++v)
            if (elsewhere.vertex[v]) wall[v] = std::numeric_limits<double>::infinity();
        for (int p = 1; p < processes; ++p) {
            const CheckShareFigures got = on.take_check(p);
            std::vector<std::uint32_t> ids;  // the vertices whose walls these are
            receive_array(on, p, ids);
            const std::string from = "process " + std::to_string(p);
            if (got.walls.size() != ids.size()) throw Error("the walls from " + from + " are not whole");
            for (std::size_t k = 0; k < ids.size(); ++k) {
                if (ids[k] >= wall.size() || !elsewhere.vertex[ids[k]])
                    throw Error("the walls from " + from + " name a vertex it does not measure");
                wall[ids[k]] = got.walls[k];
            }
            facts.check_walls += ids.size();
            depths.inside += got.points_inside;
            depths.depth_min = std::min(depths.depth_min, got.depth_min);
            if (!got.unresolved.empty()) throw Error("the points from " + from + " are not all decided");
        }
    };
    return measure_sharing(mesh, points, run.offset, d.h, surface, elsewhere, told);
}

}  // namespace snvr::detail
