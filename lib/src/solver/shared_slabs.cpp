// The surface in slabs over the processes (shared_slabs.hpp).
#include "solver/shared_slabs.hpp"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <limits>
#include <numeric>
#include <optional>
#include <utility>

#include "snvr/error.hpp"
#include "solver/sent_arrays.hpp"
#include "solver/slab_surface.hpp"
#include "solver/tile_needs.hpp"
#include "geometry/point_tree.hpp"
#include "mesh/guard_search.hpp"
#include "mesh/vertex_lists.hpp"

namespace snvr {
namespace {

template <class T>
std::uint64_t bytes_of(const std::vector<T>& v) {
    return v.size() * sizeof(T);
}

// The faces' bricks over a slab's planes: the field's shape, where it lies, its table and bricks.
std::uint64_t give_faces(TileScheduler& on, int to, const FacesPart& part) {
    const Field& f = part.field;
    const bool single = f.precision == Precision::Single;
    const std::vector<std::int64_t> head{f.nx, f.ny, f.nz, part.z, single ? 1 : 0};
    detail::send_array(on, to, head.data(), head.size());
    detail::send_array(on, to, f.brick_table().data(), f.brick_table().size());
    if (single) detail::send_array(on, to, f.stored_f32().data(), f.stored_f32().size());
    else detail::send_array(on, to, f.stored_f64().data(), f.stored_f64().size());
    return bytes_of(head) + bytes_of(f.brick_table()) + (single ? bytes_of(f.stored_f32()) : bytes_of(f.stored_f64()));
}
FacesPart take_faces(TileScheduler& on, int from) {
    std::vector<std::int64_t> head;
    detail::receive_array(on, from, head);
    if (head.size() != 5) throw Error("the faces' bricks from the first process are not whole");
    std::vector<std::uint32_t> table;
    detail::receive_array(on, from, table);
    FacesPart part;
    part.z = int(head[3]);
    const int nx = int(head[0]), ny = int(head[1]), nz = int(head[2]);
    if (head[4]) {
        std::vector<float> stored;
        detail::receive_array(on, from, stored);
        part.field = Field::from_bricks(nx, ny, nz, std::move(table), std::move(stored));
    } else {
        std::vector<double> stored;
        detail::receive_array(on, from, stored);
        part.field = Field::from_bricks(nx, ny, nz, std::move(table), std::move(stored));
    }
    return part;
}

// Whether a piece owns any of the planes a slab is welded from.
bool meets(const detail::MeshPiece& p, const detail::Planes& planes) {
    const int lo = p.region.own_lo[2] + p.region.offset[2], hi = p.region.own_hi[2] + p.region.offset[2];
    return lo < planes.hi && hi > planes.lo;
}

// How many pieces, then each's region and arrays.
std::uint64_t give_pieces(TileScheduler& on, int to, const std::vector<detail::MeshPiece>& pieces,
                          const detail::Planes& planes) {
    std::vector<const detail::MeshPiece*> given;
    for (const detail::MeshPiece& p : pieces)
        if (meets(p, planes)) given.push_back(&p);
    const std::uint64_t count = given.size();
    detail::send_array(on, to, &count, 1);
    std::uint64_t bytes = sizeof count;
    for (const detail::MeshPiece* p : given) {
        detail::send_array(on, to, &p->region, 1);
        detail::send_array(on, to, p->mesh.vertices.data(), p->mesh.vertices.size());
        detail::send_array(on, to, p->vertex_keys.data(), p->vertex_keys.size());
        detail::send_array(on, to, p->vertex_owned.data(), p->vertex_owned.size());
        detail::send_array(on, to, p->mesh.triangles.data(), p->mesh.triangles.size());
        detail::send_array(on, to, p->triangle_keys.data(), p->triangle_keys.size());
        bytes += sizeof p->region + bytes_of(p->mesh.vertices) + bytes_of(p->vertex_keys) + bytes_of(p->vertex_owned) +
                 bytes_of(p->mesh.triangles) + bytes_of(p->triangle_keys);
    }
    return bytes;
}
void take_pieces(TileScheduler& on, int from, std::vector<detail::MeshPiece>& into) {
    std::uint64_t count = 0;
    detail::receive_into(on, from, &count, 1);
    for (std::uint64_t i = 0; i < count; ++i) {
        into.emplace_back();
        detail::MeshPiece& p = into.back();
        detail::receive_into(on, from, &p.region, 1);
        detail::receive_array(on, from, p.mesh.vertices);
        detail::receive_array(on, from, p.vertex_keys);
        detail::receive_array(on, from, p.vertex_owned);
        detail::receive_array(on, from, p.mesh.triangles);
        detail::receive_array(on, from, p.triangle_keys);
        if (p.vertex_keys.size() != p.mesh.vertices.size() || p.vertex_owned.size() != p.mesh.vertices.size() ||
            p.triangle_keys.size() != p.mesh.triangles.size())
            throw Error("a tile's piece of the surface from another process is not whole");
    }
}

// The points within the guard's reach of each other process's welded planes, as runs of
// the first's tree's order (none for the first).
std::vector<PointRuns> slab_point_runs(const detail::PointTree& tree, const SlabPlan& plan, const Domain& whole,
                                       double reach) {
    std::vector<std::array<double, 2>> windows(std::size_t(plan.slabs()), {1, 0});
    for (int q = 1; q < plan.slabs(); ++q) {
        const detail::Planes planes = plan.welded(q);
        windows[std::size_t(q)] = {whole.origin[2] + planes.lo * whole.h - reach, whole.origin[2] + planes.hi * whole.h + reach};
    }
    return z_window_runs(tree, windows);
}
std::uint64_t count_of(const PointRuns& runs) {
    std::uint64_t n = 0;
    for (const auto& r : runs) n += r[1] - r[0];
    return n;
}

// Those points to each other process, with the tree's origin and frame (so that the
// other's tree keeps its order: the guard's ties go by it). Frees the runs.
void give_slab_points(TileScheduler& on, const detail::PointTree& tree, std::vector<PointRuns>& runs) {
    for (std::size_t q = 1; q < runs.size(); ++q) {
        const detail::PointArray<float> xyz = points_in(tree, runs[q]);
        runs[q] = PointRuns();
        std::vector<double> head{tree.origin[0], tree.origin[1], tree.origin[2]};
        const std::array<double, 4> frame = tree.frame().figures();
        head.insert(head.end(), frame.begin(), frame.end());
        detail::send_array(on, int(q), head.data(), head.size());
        detail::send_array(on, int(q), xyz.data(), xyz.size());
    }
}
PointCloud take_slab_points(TileScheduler& on) {
    std::vector<double> head;
    detail::receive_array(on, 0, head);
    if (head.size() != 7) throw Error("the points for a slab's depth guard from the first process are not whole");
    // Straight into the cloud's own array, not copied there again.
    detail::PointArray<Vec3f> xyz;
    on.receive_bytes(0, [&xyz](std::size_t bytes) -> void* {
        if (bytes % sizeof(Vec3f)) throw Error("the points for a slab's depth guard are not whole");
        xyz.resize(bytes / sizeof(Vec3f));
        return xyz.empty() ? nullptr : xyz.front().data();
    });
    const auto frame = detail::PointTree::Frame::of(head.data() + 3);
    return detail::cloud_of(std::move(xyz), {head[0], head[1], head[2]}, &frame);
}


// Whether the slabs keep their points deep, or the first the whole surface's (the others
// searching their ranges of the points for it, where they are already: pipeline/
// shared_guard.hpp): where the points the first would give the others for their slabs are
// no more than the vertices those slabs own. A point given costs its process its copy, its
// filing and its search; the slabs save the first its serial lift and repairs, which go
// with the vertices. Measured on two processes against the first guarding: the 12.5 M-point
// city block at 2048 cells (3.3 M points given for 8.0 M vertices, 3 repair rounds) 8.2 and
// 11.5 s in the mesh stage where 17.0 and 15.7, the bunny at 512 0.85 and 0.79 where 1.09
// and 1.02; the 50 M-point block at 1024 (13 M points for 2.2 M
// vertices) 3.4-5.7 s where 3.9-5.0; the 200 M-point block at 1024 (54 M points) 9.9 s where
// 6.5, its other process 0.8 GB more.
//
// Where the surface is to stay in its slabs (Parameters::surface_in_parts), they guard
// whatever their points: the first guarding would gather the whole surface (and send it
// the others for their search, 211 MB on the 50 M-point block), which then no process
// need hold. On two processes against the first guarding, the same bytes: the 50 M-point
// block at 1024 55.4 s where 56.3, its first's peak 2.10 GB where 2.16, the other's 1.89
// where 1.48; the 200 M-point block under --max-memory 4G 137.8 s where 134.4 (the mesh
// stage 10.8 s where 7.0), its peaks 2.93 and 2.82 GB where 3.08 and 2.82.
bool slabs_guard(std::uint64_t points_given, std::uint64_t their_vertices, bool in_parts) {
    return in_parts || points_given <= their_vertices;
}

// For tests only: SNVR_TEST_GUARD_GHOSTS=N has the slabs guard, welded with N planes of
// ghosts, half of them checked, so that too few fail the check (every process alike).
std::optional<int> guard_test_ghosts(const detail::KeepDeep* deep) {
    const char* text = deep ? std::getenv("SNVR_TEST_GUARD_GHOSTS") : nullptr;
    if (!text) return std::nullopt;
    const int ghosts = std::atoi(text);
    if (ghosts < 1) throw ParameterError("SNVR_TEST_GUARD_GHOSTS: not a count of planes");
    return ghosts;
}

// A slab's guard figures in the counts the processes sum (each its rounds in its own place).
constexpr std::size_t kGuardFigures = 4;
void put_guard(const DepthGuardReport& g, int me, std::uint64_t* at) {
    at[0] = g.near_vertices;
    at[1] = g.moved_vertices;
    at[2] = g.shallow_points;
    at[3] = g.lone_points;
    at[kGuardFigures + std::size_t(me)] = std::uint64_t(g.repair_rounds);
}
DepthGuardReport summed_guard(const std::uint64_t* at, std::size_t processes) {
    DepthGuardReport g;
    g.near_vertices = at[0];
    g.moved_vertices = at[1];
    g.shallow_points = at[2];
    g.lone_points = at[3];
    g.repair_rounds = int(*std::max_element(at + kGuardFigures, at + kGuardFigures + processes));
    return g;
}

// The whole mesh's vertices each slab's checked ghosts copy: the runs just below and above
// its own, two a slab in turn.
using VertexRun = std::array<std::uint64_t, 2>;
std::vector<VertexRun> band_runs(const std::vector<SlabBands>& bands, const std::vector<std::size_t>& starts) {
    std::vector<VertexRun> runs;
    for (std::size_t q = 0; q < bands.size(); ++q) {
        if (bands[q].below.size() > starts[q] || starts[q + 1] + bands[q].above.size() > starts.back())
            throw Error("a slab's ghosts reach beyond the whole surface");
        runs.push_back({starts[q] - bands[q].below.size(), starts[q]});
        runs.push_back({starts[q + 1], starts[q + 1] + bands[q].above.size()});
    }
    return runs;
}
// Of `runs`, the vertices a slab owns (its own from the whole mesh's `first`), in turn.
std::vector<Vec3> owned_in(const std::vector<VertexRun>& runs, const std::vector<Vec3>& own, std::size_t first) {
    std::vector<Vec3> out;
    for (const VertexRun& r : runs)
        for (std::uint64_t v = std::max<std::uint64_t>(r[0], first); v < std::min<std::uint64_t>(r[1], first + own.size()); ++v)
            out.push_back(own[v - first]);
    return out;
}
// The slabs kept where they are: the runs of `bands` against their owners' vertices, which
// each other process gives from its own (the first's side of give_band_owners).
std::size_t bands_differing_by_owners(TileScheduler& on, const std::vector<SlabBands>& bands,
                                      const std::vector<std::size_t>& starts, const std::vector<Vec3>& own) {
    const std::vector<VertexRun> runs = band_runs(bands, starts);
    const std::size_t P = bands.size();
    std::vector<std::vector<Vec3>> owned(P);
    owned[0] = owned_in(runs, own, 0);
    for (std::size_t q = 1; q < P; ++q) {
        detail::send_array(on, int(q), runs.data(), runs.size());
        detail::receive_array(on, int(q), owned[q]);
    }
    // Each run's vertices come from the slabs in turn; each owner's reply holds its part of every run.
    std::vector<std::size_t> read(P, 0);
    std::size_t differ = 0;
    for (std::size_t r = 0; r < runs.size(); ++r) {
        const SlabBands& b = bands[r / 2];
        const std::vector<Vec3>& ghosts = r % 2 ? b.above : b.below;
        std::size_t k = 0;
        for (std::size_t q = 0; q < P; ++q) {
            const std::uint64_t lo = std::max<std::uint64_t>(runs[r][0], starts[q]), hi = std::min<std::uint64_t>(runs[r][1], starts[q + 1]);
            for (std::uint64_t v = lo; v < hi; ++v, ++k) {
                if (read[q] >= owned[q].size()) throw Error("the vertices at a slab's ghosts from another process are not whole");
                differ += ghosts[k] != owned[q][read[q]++];
            }
        }
    }
    return differ;
}
void give_band_owners(TileScheduler& on, const std::vector<Vec3>& own, std::size_t first) {
    std::vector<VertexRun> runs;
    detail::receive_array(on, 0, runs);
    const std::vector<Vec3> owned = owned_in(runs, own, first);
    detail::send_array(on, 0, owned.data(), owned.size());
}

// At the first: each slab's checked ghosts against their owners' vertices (the whole
// surface's, gathered, or where the slabs are kept, each owner's). Where any differs, the
// slabs' vertices before their guard come back (with their triangles, where they were
// kept) and the guard runs here on the whole surface. Each other process's side:
// slab_guard_checked.
DepthGuardReport check_slab_guards(TileScheduler& on, Mesh& surface, const std::vector<std::size_t>& starts,
                                   const SlabBands& bands, const std::vector<Vec3>& unguarded, const SlabsGuard& guard,
                                   DepthGuardReport summed, TileFacts& facts) {
    const std::size_t P = starts.size() - 1;
    std::vector<SlabBands> all(P);
    all[0] = bands;
    for (std::size_t q = 1; q < P; ++q) {
        detail::receive_array(on, int(q), all[q].below);
        detail::receive_array(on, int(q), all[q].above);
    }
    std::size_t differ = 0;
    if (facts.slabs_kept) {
        differ = bands_differing_by_owners(on, all, starts, surface.vertices);
    } else {
        for (std::size_t q = 0; q < P; ++q)
            differ += bands_differing(all[q], surface.vertices, starts[q], starts[q + 1] - starts[q]);
    }
    all.clear();
    facts.guard_ghosts_differing = differ;
    const std::uint8_t again = differ > 0;
    for (std::size_t q = 1; q < P; ++q) detail::send_array(on, int(q), &again, 1);
    facts.guard_rerun = again;
    if (!again) return summed;
    const bool kept = facts.slabs_kept;
    facts.slabs_kept = false;
    surface.vertices.resize(starts.back());
    std::copy(unguarded.begin(), unguarded.end(), surface.vertices.begin());
    for (std::size_t q = 1; q < P; ++q) {
        detail::receive_into(on, int(q), surface.vertices.data() + starts[q], starts[q + 1] - starts[q]);
        if (kept) {
            std::vector<std::array<std::uint32_t, 3>> theirs;
            detail::receive_array(on, int(q), theirs);
            surface.triangles.insert(surface.triangles.end(), theirs.begin(), theirs.end());
        }
    }
    if (surface.triangles.size() != facts.surface_triangles)
        throw Error("the slabs' triangles from the other processes are not whole");
    detail::VertexLists rings, fans;
    detail::rings_and_fans(surface, rings, &fans);
    const detail::KeepDeep& d = guard.deep;
    return detail::keep_points_deep(surface, detail::tree_of(*guard.points), d.depth, d.voxel, d.lone, std::move(rings),
                                    fans);
}
void slab_guard_checked(TileScheduler& on, const SlabBands& bands, const std::vector<Vec3>& unguarded, const Mesh& own,
                        std::size_t first, bool kept) {
    detail::send_array(on, 0, bands.below.data(), bands.below.size());
    detail::send_array(on, 0, bands.above.data(), bands.above.size());
    if (kept) give_band_owners(on, own.vertices, first);
    std::uint8_t again = 0;
    detail::receive_into(on, 0, &again, 1);
    if (!again) return;
    detail::send_array(on, 0, unguarded.data(), unguarded.size());
    if (kept) detail::send_array(on, 0, own.triangles.data(), own.triangles.size());
}

}  // namespace

Mesh surface_in_slabs(std::vector<detail::MeshPiece>& pieces, Field faces, const Domain& whole, int core_cells,
                      const MeshFairing& fairing, const SlabsGuard* guard, bool in_parts, TileScheduler* on,
                      TileFacts& facts, DepthGuardReport* report) {
    const int processes = on ? on->processes() : 1, me = on ? on->rank() : 0;
    if (processes == 1) guard = nullptr;
    const bool guard_asked = guard != nullptr;
    if (guard && me == 0 && !guard->points) throw Error("surface_in_slabs: the guard's points are not given");
    const detail::KeepDeep* deep = guard ? &guard->deep : nullptr;
    std::vector<std::uint64_t> by_plane(std::size_t(whole.nz), 0);
    for (const detail::MeshPiece& p : pieces) count_by_plane(p, by_plane);
    if (processes > 1) on->sum(by_plane);
    SlabPlan plan = plan_slabs(by_plane, processes, guard_test_ghosts(deep).value_or(slab_ghost_planes(fairing, deep)));
    // Whether the slabs guard: the first's word (it holds the points), the same everywhere.
    std::vector<PointRuns> guard_runs;
    if (guard) {
        std::vector<std::uint64_t> word{0, 0};
        if (me == 0) {
            guard_runs = slab_point_runs(detail::tree_of(*guard->points), plan, whole,
                                         detail::guard_point_reach(deep->depth, deep->voxel, deep->lone));
            for (const PointRuns& r : guard_runs) word[1] += count_of(r);
            const std::uint64_t theirs = std::accumulate(by_plane.begin() + plan.cuts[1], by_plane.end(), std::uint64_t(0));
            word[0] = slabs_guard(word[1], theirs, in_parts) || guard_test_ghosts(deep);
        }
        on->sum(word);
        facts.guard_slab_points = word[1];
        if (!word[0]) {
            guard = nullptr, deep = nullptr;
            guard_runs.clear();
            plan.ghost = slab_ghost_planes(fairing);
        }
    }
    if (deep) plan.checked = guard_test_ghosts(deep) ? plan.ghost / 2 : guard_checked_planes(*deep);
    // This slab's pieces: its own tiles' and those the others send.
    std::vector<detail::MeshPiece> here;
    FacesPart faces_here;
    std::uint64_t sent = 0;
    if (processes > 1)
        detail::exchange_pairwise(
            *on,
            [&](int q) {
                if (me == 0) sent += give_faces(*on, q, faces_for(faces, plan.welded(q)));
                sent += give_pieces(*on, q, pieces, plan.welded(q));
            },
            [&](int q) {
                if (q == 0) faces_here = take_faces(*on, q);
                take_pieces(*on, q, here);
            });
    // The guard's points: the first's own, and the others' from it.
    PointCloud near_slab;
    const detail::PointTree* guard_points = nullptr;
    if (guard && me == 0) {
        guard_points = &detail::tree_of(*guard->points);
        give_slab_points(*on, *guard_points, guard_runs);
    } else if (guard) {
        near_slab = take_slab_points(*on);
        guard_points = &detail::tree_of(near_slab);
    }
    if (me == 0) faces_here = {std::move(faces), 0};
    for (detail::MeshPiece& p : pieces)
        if (meets(p, plan.welded(me))) here.push_back(std::move(p));
    pieces.clear();
    SlabWeld weld = weld_slab(here, faces_here, whole, core_cells, plan, me, fairing, deep, guard_points);
    faces_here = FacesPart();
    near_slab = PointCloud();
    // Where each slab begins in the whole mesh (the slabs' counts), the bytes sent, and
    // the guard's figures over the slabs' own (summed; its rounds the most of any).
    const std::size_t P = std::size_t(processes);
    std::vector<std::uint64_t> counts(2 * P + 1 + kGuardFigures + P, 0);
    counts[std::size_t(me)] = weld.vertices;
    counts[P + std::size_t(me)] = weld.triangles;
    counts[2 * P] = sent;
    put_guard(weld.guard, me, &counts[2 * P + 1]);
    if (processes > 1) on->sum(counts);
    std::vector<std::size_t> starts(P + 1, 0);
    std::uint64_t all_triangles = 0;
    for (std::size_t q = 0; q < P; ++q) {
        starts[q + 1] = starts[q] + std::size_t(counts[q]);
        all_triangles += counts[P + q];
    }
    const std::size_t all_vertices = starts[P];
    if (all_vertices >= std::numeric_limits<std::uint32_t>::max())
        throw ResourceError("the tiles' surface: more than 2^32 vertices");
    const SlabBands bands = guard ? slab_bands(weld) : SlabBands();
    const std::vector<Vec3> unguarded = std::move(weld.unguarded);
    Mesh own = slab_own(std::move(weld), starts[std::size_t(me)]);
    facts.slabs = processes;
    facts.slab_ghost = plan.ghost;
    facts.slab_starts = starts;
    facts.slab_triangles = own.triangles.size();
    facts.guard_slabs = guard != nullptr;
    facts.surface_triangles = all_triangles;
    // The slabs stay where they are where the surface is asked for in parts, and its
    // points, where they are kept deep, were so on the slabs (else the first gathers them
    // to guard the whole surface); else they come to the first as well.
    facts.slabs_kept = processes > 1 && in_parts && (guard || !guard_asked);
    facts.slab_bytes = counts[2 * P];
    if (!facts.slabs_kept)
        facts.slab_bytes += (all_vertices - counts[0]) * sizeof(Vec3) +
                            (all_triangles - counts[P]) * sizeof(std::array<std::uint32_t, 3>);
    if (processes == 1) return own;
    if (me != 0) {
        if (!facts.slabs_kept) {
            detail::send_array(*on, 0, own.vertices.data(), own.vertices.size());
            detail::send_array(*on, 0, own.triangles.data(), own.triangles.size());
        }
        if (guard) slab_guard_checked(*on, bands, unguarded, own, starts[std::size_t(me)], facts.slabs_kept);
        return own;  // kept for the check (pipeline/shared_check.hpp)
    }
    if (!facts.slabs_kept) {
        own.vertices.resize(all_vertices);
        own.triangles.resize(std::size_t(all_triangles));
        std::size_t t = counts[P];
        for (std::size_t q = 1; q < P; ++q) {
            detail::receive_into(*on, int(q), own.vertices.data() + starts[q], std::size_t(counts[q]));
            detail::receive_into(*on, int(q), own.triangles.data() + t, std::size_t(counts[P + q]));
            t += counts[P + q];
        }
    }
    if (guard) {
        const DepthGuardReport g =
            check_slab_guards(*on, own, starts, bands, unguarded, *guard, summed_guard(&counts[2 * P + 1], P), facts);
        if (report) *report = g;
    }
    return own;
}

}  // namespace snvr
