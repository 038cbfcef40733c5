// The check's topology of a mesh in slabs over processes (slab_topology.hpp).
#include "check/slab_topology.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "snvr/error.hpp"
#include "solver/sent_arrays.hpp"

namespace snvr::detail {
namespace {

using Tri = std::array<std::uint32_t, 3>;

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

SlabTopology::SlabTopology(SlabMesh& slabs, TileScheduler& on) : on_(on), slabs_(slabs) {
    if (slabs.starts().back()) sum_ = VolumeSum(slabs.box()[0], slabs.box()[1]);
}

void SlabTopology::count() {
    // The part as one mesh: the other slabs' vertices its triangles and ghosts use numbered
    // about its own in the whole mesh's order (so that each edge's smaller end is the whole
    // mesh's), its own triangles, then the ghosts.
    const std::size_t p = slabs_.rank();
    const SlabPart& part = slabs_.part();
    const auto lo = std::uint32_t(slabs_.starts()[p]), hi = std::uint32_t(slabs_.starts()[p + 1]);
    const std::vector<SlabGhost> ghosts = slabs_.take_ghosts();
    const std::vector<std::uint8_t> given = slabs_.take_given();
    std::vector<std::uint32_t> foreign = slabs_.foreign();  // those of the ghosts (no position needed) too
    for (const SlabGhost& g : ghosts)
        for (int c = 1; c < 4; ++c)
            if (g[std::size_t(c)] < lo || g[std::size_t(c)] >= hi) foreign.push_back(g[std::size_t(c)]);
    std::sort(foreign.begin(), foreign.end());
    foreign.erase(std::unique(foreign.begin(), foreign.end()), foreign.end());
    const std::size_t below = std::size_t(std::lower_bound(foreign.begin(), foreign.end(), lo) - foreign.begin());
    const std::size_t own = part.vertex_count;
    const auto local = [&](std::uint32_t v) {
        if (v >= lo && v < hi) return std::uint32_t(below + (v - lo));
        const std::size_t i = std::size_t(std::lower_bound(foreign.begin(), foreign.end(), v) - foreign.begin());
        return std::uint32_t(i < below ? i : i + own);
    };
    Mesh held;
    held.vertices.assign(foreign.size() + own, Vec3{0, 0, 0});
    std::copy(part.vertices, part.vertices + own, held.vertices.begin() + std::ptrdiff_t(below));
    for (std::size_t k = 0; k < slabs_.foreign().size(); ++k)
        held.vertices[local(slabs_.foreign()[k])] = slabs_.foreign_at()[k];
    held.triangles.reserve(part.triangle_count + ghosts.size());
    for (std::size_t t = 0; t < part.triangle_count; ++t) {
        const Tri& T = part.triangles[t];
        held.triangles.push_back({local(T[0]), local(T[1]), local(T[2])});
    }
    for (const SlabGhost& g : ghosts) held.triangles.push_back({local(g[1]), local(g[2]), local(g[3])});
    const std::size_t own_lo = below, own_hi = below + own, own_triangles = part.triangle_count;
    {
        const MeshAdjacency adjacency = adjacency_of(held);
        counts_ = part_counts(held, adjacency, own_triangles, own_lo, own_hi);
        pieces_ = part_pieces(held, adjacency, own_triangles, own_lo, own_hi, sum_);
    }
    held = Mesh();
    // The pieces that share a triangle: (the triangle's number, its piece here) for each
    // ghost here and each own triangle given, the proper ones.
    for (std::size_t k = 0; k < ghosts.size(); ++k)
        if (pieces_.label[own_triangles + k] != kNoPiece) ghost_pieces_.push_back({ghosts[k][0], pieces_.label[own_triangles + k]});
    const std::uint64_t first = slabs_.triangle_starts()[p];
    for (std::size_t t = 0; t < own_triangles; ++t)
        if (given[t] && pieces_.label[t] != kNoPiece) given_pieces_.push_back({std::uint32_t(first + t), pieces_.label[t]});
    pieces_.label = {};
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
    const std::size_t P = slabs_.processes();
    if (their_pieces_.size() + 1 != P) throw Error("the check of a mesh in slabs: not every slab's pieces came");
    MeshReport all_counts = counts_;
    all_counts.vertices = slabs_.starts()[P];
    all_counts.triangles = slabs_.triangle_starts()[P];
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
    SlabMesh slabs(part, on);
    SlabTopology topology(slabs, on);
    topology.count();
    if (on.rank() != 0) {
        topology.send_to_first();
        return Topology();
    }
    topology.take_others();
    return topology.joined();
}

}  // namespace snvr::detail
