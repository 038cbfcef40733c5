// The check's topology of a mesh in slabs over processes (slab_topology.hpp).
#include "check/slab_topology.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "snvr/error.hpp"
#include "solver/sent_arrays.hpp"

namespace snvr::detail {
namespace {

using Tri = std::array<std::uint32_t, 3>;
// A triangle given to another process: its number in the whole mesh, then its corners.
using Ghost = std::array<std::uint32_t, 4>;

// What MeshReport counts a part owns, in a row to send (part_counts).
constexpr std::size_t kCounts = 6;
std::array<std::uint64_t, kCounts> counts_row(const MeshReport& r) {
    return {r.boundary_edges,          r.nonmanifold_edges,   r.misoriented_edges,
            r.nonmanifold_vertices,    r.degenerate_triangles, r.zero_area_triangles};
}
void add_row(MeshReport& r, const std::uint64_t* row) {
    r.boundary_edges += row[0];
    r.nonmanifold_edges += row[1];
    r.misoriented_edges += row[2];
    r.nonmanifold_vertices += row[3];
    r.degenerate_triangles += row[4];
    r.zero_area_triangles += row[5];
}

// A part's pieces to the first, and back (PartPieces less its triangles' labels).
void send_pieces(TileScheduler& on, const PartPieces& p) {
    send_array(on, 0, p.faces.data(), p.faces.size());
    send_array(on, 0, p.edges.data(), p.edges.size());
    send_array(on, 0, p.vertices.data(), p.vertices.size());
    send_array(on, 0, p.open.data(), p.open.size());
    send_array(on, 0, p.volume.data(), p.volume.size());
    send_array(on, 0, p.shared_vertices.data(), p.shared_vertices.size());
    const std::array<ExactSum, 2> total{p.total, ExactSum(p.finite)};
    send_array(on, 0, total.data(), total.size());
}
PartPieces take_pieces(TileScheduler& on, int from) {
    PartPieces p;
    receive_array(on, from, p.faces);
    receive_array(on, from, p.edges);
    receive_array(on, from, p.vertices);
    receive_array(on, from, p.open);
    receive_array(on, from, p.volume);
    receive_array(on, from, p.shared_vertices);
    std::array<ExactSum, 2> total{};
    receive_into(on, from, total.data(), total.size());
    p.total = total[0];
    p.finite = total[1] != 0;
    const std::size_t n = p.faces.size();
    if (p.edges.size() != n || p.vertices.size() != n || p.open.size() != n || p.volume.size() != n)
        throw Error("the pieces of a slab from process " + std::to_string(from) + " are not whole");
    for (std::size_t k = 0; k < p.shared_vertices.size(); k += p.shared_vertices[k] + 1) {
        const std::size_t m = p.shared_vertices[k];
        if (k + m >= p.shared_vertices.size()) throw Error("the shared vertices of a slab's pieces are not whole");
        for (std::size_t i = 1; i <= m; ++i)
            if (p.shared_vertices[k + i] >= n) throw Error("a slab's shared vertex names a piece it has not");
    }
    return p;
}

}  // namespace

SlabTopology::SlabTopology(SlabPart part, TileScheduler& on) : on_(on), part_(part) {
    const int processes = on.processes(), me = on.rank();
    const std::size_t P = std::size_t(processes), p = std::size_t(me);
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
        throw ResourceError("the check of a mesh in slabs: more than 2^32 vertices or triangles");
    const auto lo = std::uint32_t(starts_[p]), hi = std::uint32_t(starts_[p + 1]);
    const auto owner = [&](std::uint32_t v) {
        return std::size_t(std::upper_bound(starts_.begin(), starts_.end(), std::uint64_t(v)) - starts_.begin()) - 1;
    };
    // The whole mesh's box, for the volume's centre and quantum.
    std::vector<double> box(6, std::numeric_limits<double>::infinity());
    for (std::size_t v = 0; v < part.vertex_count; ++v)
        for (std::size_t a = 0; a < 3; ++a) {
            box[a] = std::min(box[a], part.vertices[v][a]);
            box[3 + a] = std::min(box[3 + a], -part.vertices[v][a]);
        }
    on.least(box);
    if (starts_[P]) sum_ = VolumeSum({box[0], box[1], box[2]}, {-box[3], -box[4], -box[5]});

    // Its own triangles that use another's vertices, to that one (every one it uses).
    std::vector<std::vector<Ghost>> give(P);
    given_.assign(part.triangle_count, 0);
    for (std::size_t t = 0; t < part.triangle_count; ++t) {
        const Tri& T = part.triangles[t];
        std::size_t to[3];
        int n = 0;
        for (std::uint32_t v : T) {
            if (v >= starts_[P])
                throw InputError("the check of a mesh in slabs: triangle " + std::to_string(triangle_starts_[p] + t) +
                                 " uses vertex " + std::to_string(v) + " of " + std::to_string(starts_[P]));
            if (v >= lo && v < hi) continue;
            const std::size_t q = owner(v);
            if (std::find(to, to + n, q) == to + n) to[n++] = q;
        }
        for (int k = 0; k < n; ++k)
            give[to[k]].push_back({std::uint32_t(triangle_starts_[p] + t), T[0], T[1], T[2]});
        given_[t] = n > 0;
    }
    // The vertices of one process that some triangles use, in order (both sides make it alike).
    const auto used_of = [&](const std::vector<Ghost>& triangles, std::size_t q) {
        std::vector<std::uint32_t> used;
        for (const Ghost& g : triangles)
            for (int c = 1; c < 4; ++c)
                if (owner(g[std::size_t(c)]) == q) used.push_back(g[std::size_t(c)]);
        std::sort(used.begin(), used.end());
        used.erase(std::unique(used.begin(), used.end()), used.end());
        return used;
    };
    // Each other's ghosts here, then the positions of the vertices of its own that those use.
    std::vector<std::vector<Ghost>> ghosts(P);
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
    // Kept until counted: the ghosts, and the others' vertices by number (ascending: the
    // processes hold ascending runs), with their positions.
    for (std::size_t q = 0; q < P; ++q) {
        ghosts_.insert(ghosts_.end(), ghosts[q].begin(), ghosts[q].end());
        foreign_.insert(foreign_.end(), wanted[q].begin(), wanted[q].end());
        foreign_at_.insert(foreign_at_.end(), positions[q].begin(), positions[q].end());
    }
}

void SlabTopology::count() {
    // The part as one mesh: the other slabs' vertices its triangles and ghosts use numbered
    // about its own in the whole mesh's order (so that each edge's smaller end is the whole
    // mesh's), its own triangles, then the ghosts.
    const std::size_t p = std::size_t(on_.rank());
    const auto lo = std::uint32_t(starts_[p]), hi = std::uint32_t(starts_[p + 1]);
    std::vector<std::uint32_t> foreign = foreign_;  // those of the ghosts (no position needed) too
    for (const Ghost& g : ghosts_)
        for (int c = 1; c < 4; ++c)
            if (g[std::size_t(c)] < lo || g[std::size_t(c)] >= hi) foreign.push_back(g[std::size_t(c)]);
    std::sort(foreign.begin(), foreign.end());
    foreign.erase(std::unique(foreign.begin(), foreign.end()), foreign.end());
    const std::size_t below = std::size_t(std::lower_bound(foreign.begin(), foreign.end(), lo) - foreign.begin());
    const std::size_t own = part_.vertex_count;
    const auto local = [&](std::uint32_t v) {
        if (v >= lo && v < hi) return std::uint32_t(below + (v - lo));
        const std::size_t i = std::size_t(std::lower_bound(foreign.begin(), foreign.end(), v) - foreign.begin());
        return std::uint32_t(i < below ? i : i + own);
    };
    Mesh held;
    held.vertices.assign(foreign.size() + own, Vec3{0, 0, 0});
    std::copy(part_.vertices, part_.vertices + own, held.vertices.begin() + std::ptrdiff_t(below));
    for (std::size_t k = 0; k < foreign_.size(); ++k) held.vertices[local(foreign_[k])] = foreign_at_[k];
    held.triangles.reserve(part_.triangle_count + ghosts_.size());
    for (std::size_t t = 0; t < part_.triangle_count; ++t) {
        const Tri& T = part_.triangles[t];
        held.triangles.push_back({local(T[0]), local(T[1]), local(T[2])});
    }
    for (const Ghost& g : ghosts_) held.triangles.push_back({local(g[1]), local(g[2]), local(g[3])});
    const std::size_t own_lo = below, own_hi = below + own, own_triangles = part_.triangle_count;
    {
        const MeshAdjacency adjacency = adjacency_of(held);
        counts_ = part_counts(held, adjacency, own_triangles, own_lo, own_hi);
        pieces_ = part_pieces(held, adjacency, own_triangles, own_lo, own_hi, sum_);
    }
    held = Mesh();
    // The pieces that share a triangle: (the triangle's number, its piece here) for each
    // ghost here and each own triangle given, the proper ones.
    for (std::size_t k = 0; k < ghosts_.size(); ++k)
        if (pieces_.label[own_triangles + k] != kNoPiece) ghost_pieces_.push_back({ghosts_[k][0], pieces_.label[own_triangles + k]});
    const std::uint64_t first = triangle_starts_[p];
    for (std::size_t t = 0; t < own_triangles; ++t)
        if (given_[t] && pieces_.label[t] != kNoPiece) given_pieces_.push_back({std::uint32_t(first + t), pieces_.label[t]});
    pieces_.label = {};
    ghosts_ = {};
    given_ = {};
}

void SlabTopology::send_to_first() {
    const std::array<std::uint64_t, kCounts> row = counts_row(counts_);
    send_array(on_, 0, row.data(), row.size());
    send_pieces(on_, pieces_);
    send_array(on_, 0, ghost_pieces_.data(), ghost_pieces_.size());
    send_array(on_, 0, given_pieces_.data(), given_pieces_.size());
}

void SlabTopology::take_others() {
    for (int q = 1; q < on_.processes(); ++q) {
        their_counts_.emplace_back();
        receive_into(on_, q, their_counts_.back().data(), their_counts_.back().size());
        their_pieces_.push_back(take_pieces(on_, q));
        their_ghosts_.emplace_back();
        their_given_.emplace_back();
        receive_array(on_, q, their_ghosts_.back());
        receive_array(on_, q, their_given_.back());
    }
}

Topology SlabTopology::joined() {
    // Every slab's pieces in turn (their labels offset by those before), and each ghost's
    // piece joined to its triangle's own.
    const std::size_t P = starts_.size() - 1;
    if (their_pieces_.size() + 1 != P) throw Error("the check of a mesh in slabs: not every slab's pieces came");
    MeshReport all_counts = counts_;
    all_counts.vertices = starts_[P];
    all_counts.triangles = triangle_starts_[P];
    PartPieces all = std::move(pieces_);
    std::vector<std::array<std::uint32_t, 2>> ghosts = std::move(ghost_pieces_), given = std::move(given_pieces_);
    for (std::size_t q = 0; q + 1 < P; ++q) {
        add_row(all_counts, their_counts_[q].data());
        const auto offset = std::uint32_t(all.pieces());
        const std::size_t n = their_pieces_[q].pieces();
        all.append(their_pieces_[q]);
        for (const auto& [from, into] : {std::pair{&their_ghosts_[q], &ghosts}, std::pair{&their_given_[q], &given}})
            for (const auto& pair : *from) {
                if (pair[1] >= n) throw Error("a slab's triangle names a piece it has not");
                into->push_back({pair[0], pair[1] + offset});
            }
    }
    std::sort(given.begin(), given.end());
    std::vector<std::array<std::uint32_t, 2>> joined;
    joined.reserve(ghosts.size());
    for (const auto& g : ghosts) {
        const auto at = std::lower_bound(given.begin(), given.end(), std::array<std::uint32_t, 2>{g[0], 0});
        if (at == given.end() || (*at)[0] != g[0]) throw Error("a slab's ghost triangle is no slab's own");
        joined.push_back({g[1], (*at)[1]});
    }
    return joined_topology(all_counts, all, joined, sum_);
}

Topology slab_topology(SlabPart part, TileScheduler& on) {
    SlabTopology slabs(part, on);
    slabs.count();
    if (on.rank() != 0) {
        slabs.send_to_first();
        return Topology();
    }
    slabs.take_others();
    return slabs.joined();
}

}  // namespace snvr::detail
