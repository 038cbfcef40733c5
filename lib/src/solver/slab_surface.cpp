// The surface in slabs of planes (slab_surface.hpp).
#include "solver/slab_surface.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <utility>

#include "mesh/dual_pieces.hpp"
#include "mesh/guard_search.hpp"
#include "mesh/vertex_lists.hpp"
#include "snvr/error.hpp"

namespace snvr {

int slab_ghost_planes(const MeshFairing& fairing, const detail::KeepDeep* deep) {
    // The fairing's steps, then the guard's reach on the faired vertices, then those checked.
    const int faired = 2 * fairing.passes;
    return deep ? faired + detail::guard_reach_planes(deep->depth, deep->voxel) + guard_checked_planes(*deep)
                : std::max(1, faired);
}

int guard_checked_planes(const detail::KeepDeep& deep) {
    return (detail::guard_reach_planes(deep.depth, deep.voxel) + 1) / 2;
}

detail::Planes SlabPlan::welded(int s) const {
    const int lo = std::max(0, cuts[std::size_t(s)] - ghost), hi = std::min(cuts.back(), cuts[std::size_t(s) + 1] + ghost);
    // The triangles of the lowest plane would use the plane below it: not there but at the grid's floor.
    return {lo, std::max(lo, hi), lo > 0 ? lo + 1 : 0};
}

void count_by_plane(const detail::MeshPiece& piece, std::vector<std::uint64_t>& by_plane) {
    const std::array<int, 3>& n = piece.region.whole;
    const std::uint64_t plane = detail::first_vertex_key(1, n);
    for (std::size_t v = 0; v < piece.vertex_keys.size(); ++v)
        if (piece.vertex_owned[v]) ++by_plane[std::size_t(piece.vertex_keys[v] / plane)];
}

SlabPlan plan_slabs(const std::vector<std::uint64_t>& by_plane, int slabs, int ghost) {
    if (slabs < 1) throw ParameterError("plan_slabs: no slab");
    SlabPlan plan;
    plan.ghost = ghost;
    const int nz = int(by_plane.size());
    std::uint64_t all = 0;
    for (std::uint64_t c : by_plane) all += c;
    plan.cuts.push_back(0);
    std::uint64_t below = 0;  // the vertices of planes [0, z)
    int z = 0;
    for (int s = 1; s < slabs; ++s) {
        if (all == 0) {
            plan.cuts.push_back(int(std::int64_t(nz) * s / slabs));
            continue;
        }
        // The first plane at which the slabs before hold their share.
        const double share = double(all) * s / slabs;
        while (z < nz && double(below) + 0.5 * double(by_plane[std::size_t(z)]) < share)
            below += by_plane[std::size_t(z++)];
        plan.cuts.push_back(z);
    }
    plan.cuts.push_back(nz);
    return plan;
}

SlabWeld weld_slab(std::vector<detail::MeshPiece>& pieces, const FacesPart& faces, const Domain& whole, int core_cells,
                   const SlabPlan& plan, int s, const MeshFairing& fairing, const detail::KeepDeep* deep,
                   const detail::PointTree* points) {
    const detail::Planes planes = plan.welded(s);
    for (detail::MeshPiece& p : seam_pieces(faces, whole, core_cells, planes)) pieces.push_back(std::move(p));
    SlabWeld w;
    if (plan.slabs() == 1) {  // the whole mesh, no ghosts
        w.mesh = detail::weld_pieces(pieces, nullptr, &planes);
        w.vertices = w.mesh.vertices.size();
        w.triangles = w.mesh.triangles.size();
    } else {
        // The slab's own: the runs of the whole order from its first plane to the next slab's.
        detail::WeldedKeys keys;
        w.mesh = detail::weld_pieces(pieces, &keys, &planes);
        const std::array<int, 3> n{whole.nx, whole.ny, whole.nz};
        const int lo = plan.cuts[std::size_t(s)], hi = plan.cuts[std::size_t(s) + 1];
        const bool last = s + 1 == plan.slabs();
        const auto run = [](const std::vector<std::uint64_t>& k, std::uint64_t from, std::uint64_t to) {
            const auto b = std::lower_bound(k.begin(), k.end(), from), e = std::lower_bound(k.begin(), k.end(), to);
            return std::make_pair(std::size_t(b - k.begin()), std::size_t(e - b));
        };
        std::tie(w.below, w.vertices) = run(keys.vertices, detail::first_vertex_key(lo, n),
                                            last ? ~std::uint64_t(0) : detail::first_vertex_key(hi, n));
        std::tie(w.first_triangle, w.triangles) = run(keys.triangles, detail::first_triangle_key(lo, n),
                                                      last ? ~std::uint64_t(0) : detail::first_triangle_key(hi, n));
        const auto vertex_at = [&keys](std::uint64_t key) {
            return std::size_t(std::lower_bound(keys.vertices.begin(), keys.vertices.end(), key) - keys.vertices.begin());
        };
        const int band = plan.checked;
        w.band_below = vertex_at(detail::first_vertex_key(std::max(0, lo - band), n));
        w.band_above = hi + band >= whole.nz ? w.mesh.vertices.size() : vertex_at(detail::first_vertex_key(hi + band, n));
    }
    const bool guard = deep && points && points->size() > 0 && !w.mesh.triangles.empty();
    detail::VertexLists rings, fans;
    if (fairing.passes > 0 || guard) detail::rings_and_fans(w.mesh, rings, guard ? &fans : nullptr);
    if (fairing.passes > 0 && !w.mesh.triangles.empty()) detail::fair_mesh(w.mesh, fairing, rings);
    if (deep) {
        const auto own = w.mesh.vertices.begin() + std::ptrdiff_t(w.below);
        w.unguarded.assign(own, own + std::ptrdiff_t(w.vertices));
    }
    if (guard) {
        // Its points are those of its own planes (the first slab's and the last's reach beyond).
        const int lo = plan.cuts[std::size_t(s)], hi = plan.cuts[std::size_t(s) + 1];
        const bool first = s == 0, last = s + 1 == plan.slabs();
        detail::GuardCounted counted;
        counted.vertex_begin = w.below;
        counted.vertex_end = w.below + w.vertices;
        counted.point = [&](std::uint32_t p) {
            const double plane = std::floor((points->point(p)[2] - whole.origin[2]) / whole.h);
            return (first || plane >= lo) && (last || plane < hi);
        };
        w.guard = detail::keep_points_deep(w.mesh, *points, deep->depth, deep->voxel, deep->lone, std::move(rings), fans,
                                           nullptr, nullptr, &counted);
    }
    return w;
}

SlabBands slab_bands(const SlabWeld& w) {
    const auto& v = w.mesh.vertices;
    const auto at = [&v](std::size_t i) { return v.begin() + std::ptrdiff_t(i); };
    return {{at(w.band_below), at(w.below)}, {at(w.below + w.vertices), at(w.band_above)}};
}

std::size_t bands_differing(const SlabBands& b, const std::vector<Vec3>& whole, std::size_t first, std::size_t own) {
    if (b.below.size() > first || first + own + b.above.size() > whole.size())
        throw Error("a slab's ghosts reach beyond the whole surface");
    std::size_t differ = 0;
    for (std::size_t i = 0; i < b.below.size(); ++i) differ += b.below[i] != whole[first - b.below.size() + i];
    for (std::size_t i = 0; i < b.above.size(); ++i) differ += b.above[i] != whole[first + own + i];
    return differ;
}

Mesh slab_own(SlabWeld weld, std::size_t first) {
    Mesh& m = weld.mesh;
    if (first < weld.below) throw Error("slab_own: the slabs before hold fewer vertices than its ghosts below");
    const std::size_t shift = first - weld.below;  // local vertex v is the whole mesh's v + shift
    if (weld.first_triangle) m.triangles.erase(m.triangles.begin(), m.triangles.begin() + std::ptrdiff_t(weld.first_triangle));
    m.triangles.resize(weld.triangles);
    if (shift)
        for (auto& t : m.triangles)
            for (std::uint32_t& v : t) v = std::uint32_t(v + shift);
    if (weld.below) m.vertices.erase(m.vertices.begin(), m.vertices.begin() + std::ptrdiff_t(weld.below));
    m.vertices.resize(weld.vertices);
    return std::move(m);
}

}  // namespace snvr
