// A mesh held in slabs by the processes of a run, one slab a process, no process holding
// the whole mesh: where each slab lies in the whole, the whole's box, and what each slab
// needs of its neighbours: the others' triangles at its vertices (its ghosts, for the
// topology: slab_topology.hpp) and the positions of the others' vertices its own triangles
// use (for the check's shares: slab_shares.hpp).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "snvr/mesh.hpp"
#include "snvr/tiles.hpp"

namespace snvr::detail {

// A slab as the process holds it (a run of the whole mesh's vertices and triangles): its
// vertices are the whole mesh's from the count of those of the processes before it (by
// rank), its triangles the whole mesh's from the count of theirs, by the whole mesh's
// vertex numbers (any vertex of any slab). Kept by the caller while a SlabMesh uses it,
// and unchanged.
struct SlabPart {
    const Vec3* vertices = nullptr;
    std::size_t vertex_count = 0;
    const std::array<std::uint32_t, 3>* triangles = nullptr;
    std::size_t triangle_count = 0;
    // The first `vertices` and `triangles` of a mesh, or all of them.
    static SlabPart of(const Mesh& mesh, std::size_t vertices, std::size_t triangles) {
        return {mesh.vertices.data(), vertices, mesh.triangles.data(), triangles};
    }
    static SlabPart of(const Mesh& mesh) { return of(mesh, mesh.vertices.size(), mesh.triangles.size()); }
};

// A triangle of one slab given to another: its number in the whole mesh, then its corners.
using SlabGhost = std::array<std::uint32_t, 4>;

class SlabMesh {
public:
    // Every process makes it at once: the slabs' sizes summed, the box agreed, the ghosts
    // and the positions exchanged. Throws InputError for a vertex number beyond the whole
    // mesh's, ResourceError beyond 2^32 vertices or triangles.
    SlabMesh(SlabPart part, TileScheduler& on);
    const SlabPart& part() const { return part_; }
    std::size_t processes() const { return starts_.size() - 1; }
    std::size_t rank() const { return rank_; }
    // Where each slab's vertices and triangles begin in the whole mesh, then the whole's counts.
    const std::vector<std::uint64_t>& starts() const { return starts_; }
    const std::vector<std::uint64_t>& triangle_starts() const { return triangle_starts_; }
    // The whole mesh's box (infinite, inverted, where it has no vertex).
    const std::array<Vec3, 2>& box() const { return box_; }
    // The slab holding vertex v.
    std::size_t owner(std::uint32_t v) const;
    // Vertex v's place here: its own vertices first, then the foreign ones (npos where it
    // is neither this slab's nor used by its triangles).
    static constexpr std::size_t npos = std::size_t(-1);
    std::size_t slot(std::uint32_t v) const;
    // Vertex v, of this slab or used by its triangles.
    const Vec3& position(std::uint32_t v) const;
    // The other slabs' vertices its own triangles use (ascending), and where they are.
    const std::vector<std::uint32_t>& foreign() const { return foreign_; }
    const std::vector<Vec3>& foreign_at() const { return foreign_at_; }
    // The others' triangles that use its vertices (by their order in the whole mesh), and
    // for each own triangle whether another slab was given it: taken once.
    std::vector<SlabGhost> take_ghosts() { return std::move(ghosts_); }
    std::vector<std::uint8_t> take_given() { return std::move(given_); }

private:
    SlabPart part_;
    std::size_t rank_ = 0;
    std::vector<std::uint64_t> starts_, triangle_starts_;
    std::array<Vec3, 2> box_{};
    std::vector<std::uint32_t> foreign_;
    std::vector<Vec3> foreign_at_;
    std::vector<SlabGhost> ghosts_;
    std::vector<std::uint8_t> given_;
};

}  // namespace snvr::detail
