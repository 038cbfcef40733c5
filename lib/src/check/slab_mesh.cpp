// A mesh in slabs over processes (slab_mesh.hpp).
#include "check/slab_mesh.hpp"

#include <algorithm>
#include <limits>
#include <string>

#include "snvr/error.hpp"
#include "solver/sent_arrays.hpp"

namespace snvr::detail {

SlabMesh::SlabMesh(SlabPart part, TileScheduler& on) : part_(part), rank_(std::size_t(on.rank())) {
    const std::size_t P = std::size_t(on.processes()), p = rank_;
    // Where each slab's vertices and triangles begin in the whole mesh.
    std::vector<std::uint64_t> sizes(2 * P, 0);
    sizes[p] = part.vertex_count;
    sizes[P + p] = part.triangle_count;
    on.sum(sizes);
    starts_.assign(P + 1, 0);
    triangle_starts_.assign(P + 1, 0);
    for (std::size_t q = 0; q < P; ++q) {
        starts_[q + 1] = starts_[q] + sizes[q];
        triangle_starts_[q + 1] = triangle_starts_[q] + sizes[P + q];
    }
    constexpr std::uint64_t kMost = std::numeric_limits<std::uint32_t>::max();
    if (starts_[P] >= kMost || triangle_starts_[P] >= kMost)
        throw ResourceError("a mesh in slabs: more than 2^32 vertices or triangles");
    const auto lo = std::uint32_t(starts_[p]), hi = std::uint32_t(starts_[p + 1]);
    // The whole mesh's box: the least of each slab's low corner and of its negated high one.
    std::vector<double> box(6, std::numeric_limits<double>::infinity());
    for (std::size_t v = 0; v < part.vertex_count; ++v)
        for (std::size_t a = 0; a < 3; ++a) {
            box[a] = std::min(box[a], part.vertices[v][a]);
            box[3 + a] = std::min(box[3 + a], -part.vertices[v][a]);
        }
    on.least(box);
    box_ = {Vec3{box[0], box[1], box[2]}, Vec3{-box[3], -box[4], -box[5]}};

    // Its own triangles that use another's vertices, to that one (every one it uses).
    std::vector<std::vector<SlabGhost>> give(P);
    given_.assign(part.triangle_count, 0);
    for (std::size_t t = 0; t < part.triangle_count; ++t) {
        const std::array<std::uint32_t, 3>& T = part.triangles[t];
        std::size_t to[3];
        int n = 0;
        for (std::uint32_t v : T) {
            if (v >= starts_[P])
                throw InputError("a mesh in slabs: triangle " + std::to_string(triangle_starts_[p] + t) + " uses vertex " +
                                 std::to_string(v) + " of " + std::to_string(starts_[P]));
            if (v >= lo && v < hi) continue;
            const std::size_t q = owner(v);
            if (std::find(to, to + n, q) == to + n) to[n++] = q;
        }
        for (int k = 0; k < n; ++k) give[to[k]].push_back({std::uint32_t(triangle_starts_[p] + t), T[0], T[1], T[2]});
        given_[t] = n > 0;
    }
    // The vertices of one process that some triangles use, in order (both sides make it alike).
    const auto used_of = [&](const std::vector<SlabGhost>& triangles, std::size_t q) {
        std::vector<std::uint32_t> used;
        for (const SlabGhost& g : triangles)
            for (int c = 1; c < 4; ++c)
                if (owner(g[std::size_t(c)]) == q) used.push_back(g[std::size_t(c)]);
        std::sort(used.begin(), used.end());
        used.erase(std::unique(used.begin(), used.end()), used.end());
        return used;
    };
    // Each other's ghosts here, then the positions of the vertices of its own that those use.
    std::vector<std::vector<SlabGhost>> ghosts(P);
    exchange_pairwise(
        on, [&](int q) { send_array(on, q, give[std::size_t(q)].data(), give[std::size_t(q)].size()); },
        [&](int q) { receive_array(on, q, ghosts[std::size_t(q)]); });
    std::vector<std::vector<std::uint32_t>> wanted(P);
    std::vector<std::vector<Vec3>> positions(P);
    for (std::size_t q = 0; q < P; ++q)
        if (q != p) wanted[q] = used_of(give[q], q);
    exchange_pairwise(
        on,
        [&](int q) {
            std::vector<Vec3> theirs;
            for (std::uint32_t v : used_of(ghosts[std::size_t(q)], p)) theirs.push_back(part.vertices[v - lo]);
            send_array(on, q, theirs.data(), theirs.size());
        },
        [&](int q) {
            receive_array(on, q, positions[std::size_t(q)]);
            if (positions[std::size_t(q)].size() != wanted[std::size_t(q)].size())
                throw Error("the vertices of a slab from process " + std::to_string(q) + " are not those asked for");
        });
    // The ghosts, and the others' vertices by number (ascending: the processes hold
    // ascending runs), with their positions.
    for (std::size_t q = 0; q < P; ++q) {
        ghosts_.insert(ghosts_.end(), ghosts[q].begin(), ghosts[q].end());
        foreign_.insert(foreign_.end(), wanted[q].begin(), wanted[q].end());
        foreign_at_.insert(foreign_at_.end(), positions[q].begin(), positions[q].end());
    }
}

std::size_t SlabMesh::owner(std::uint32_t v) const {
    return std::size_t(std::upper_bound(starts_.begin(), starts_.end(), std::uint64_t(v)) - starts_.begin()) - 1;
}

std::size_t SlabMesh::slot(std::uint32_t v) const {
    if (v >= starts_[rank_] && v < starts_[rank_ + 1]) return std::size_t(v - starts_[rank_]);
    const auto at = std::lower_bound(foreign_.begin(), foreign_.end(), v);
    return at != foreign_.end() && *at == v ? part_.vertex_count + std::size_t(at - foreign_.begin()) : npos;
}

const Vec3& SlabMesh::position(std::uint32_t v) const {
    const std::size_t s = slot(v);
    if (s == npos) throw Error("a mesh in slabs: vertex " + std::to_string(v) + " is neither this slab's nor used by it");
    return s < part_.vertex_count ? part_.vertices[s] : foreign_at_[s - part_.vertex_count];
}

}  // namespace snvr::detail
