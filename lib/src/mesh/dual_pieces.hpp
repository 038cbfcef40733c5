// The dual isosurface in pieces: each piece owns a box of the whole grid's samples (the
// cubes whose low corner, and the edges whose low end, lie in it) and is extracted from
// a region of the field around that box alone; the pieces welded by the whole grid's
// keys (a vertex's cube and slot, a triangle's edge) give the whole grid's mesh, the same
// vertices in the same order, bit for bit. Why this is exact: a cube's patches, vertices
// and tunnel faces are functions of its own eight samples and its upper neighbours' (the
// tunnel test), and an edge's polygon of the four cubes around it, so a piece whose
// region holds those samples as the whole field does computes what the whole
// extraction computes, whichever piece it is; the keys then join what two pieces share
// without any distance tolerance.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "snvr/domain.hpp"
#include "snvr/field.hpp"
#include "snvr/mesh.hpp"

namespace snvr::detail {

// A cube holds at most 4 patch vertices and 2 tunnel vertices on each of its 3 upper faces.
constexpr std::uint64_t kSlotsPerCube = 16;

// What one extraction covers, in the samples of the field it is given (local), and where
// that field lies in the whole grid.
struct DualRegion {
    std::array<int, 3> offset{0, 0, 0};           // the whole grid's sample at local (0, 0, 0)
    std::array<int, 3> whole{0, 0, 0};            // the whole grid's samples per axis
    std::array<int, 3> cube_lo{}, cube_hi{};      // cubes classified (by low corner)
    std::array<int, 3> edge_lo{}, edge_hi{};      // edges given polygons (by low end)
    std::array<int, 3> own_lo{}, own_hi{};        // the samples owned
    std::array<bool, 3> open_lo{}, open_hi{};     // a face of the field inside the whole grid

    // The whole grid, owned whole.
    static DualRegion whole_grid(const std::array<int, 3>& n);
    // The samples [lo, hi) of a whole grid of n, owned, with their cubes and edges out to
    // `margin` samples beyond (clipped to the grid), in a field of the samples [field_lo,
    // field_hi) (see field_box).
    static DualRegion around(const std::array<int, 3>& n, const std::array<int, 3>& lo, const std::array<int, 3>& hi,
                             int margin, const std::array<int, 3>& field_lo, const std::array<int, 3>& field_hi);

    std::uint64_t cube_key(int i, int j, int k) const {
        const auto cx = std::uint64_t(whole[0] - 1), cy = std::uint64_t(whole[1] - 1);
        return std::uint64_t(i + offset[0]) + cx * (std::uint64_t(j + offset[1]) + cy * std::uint64_t(k + offset[2]));
    }
    bool owns(int i, int j, int k) const {
        return i >= own_lo[0] && i < own_hi[0] && j >= own_lo[1] && j < own_hi[1] && k >= own_lo[2] && k < own_hi[2];
    }
    // Whether the edge a triangle's key names starts in the owned box.
    bool owns_triangle(std::uint64_t key) const;
    // Throws ParameterError, starting with `who`, when the field cannot hold what the
    // region asks for.
    void check(const std::array<int, 3>& field_n, const std::array<int, 3>& whole_n, const std::string& who) const;
};

// Where a triangle comes in the whole grid's order: the plane, row, word of 64 samples,
// axis and sample of its edge's low end (local (i, j, k) in `r`), and its place among
// that edge's triangles.
std::uint64_t triangle_key(const DualRegion& r, int i, int j, int k, int axis, int sub);

// The first key of plane z's vertices (triangles) in a whole grid of n samples a side:
// the whole order of each is plane by plane, and this is where the plane's begins.
std::uint64_t first_vertex_key(int z, const std::array<int, 3>& n);
std::uint64_t first_triangle_key(int z, const std::array<int, 3>& n);

// The field's box around the owned samples [lo, hi) that a piece with `margin` needs,
// aligned to bricks (so that it is cut from the whole field brick by brick).
void field_box(const std::array<int, 3>& n, const std::array<int, 3>& lo, const std::array<int, 3>& hi, int margin,
               std::array<int, 3>& box_lo, std::array<int, 3>& box_hi);
// The whole field's samples [lo, hi) (lo a multiple of the brick) as a field of their own.
Field field_part(const Field& whole, const std::array<int, 3>& lo, const std::array<int, 3>& hi);

struct MeshPiece {
    Mesh mesh;  // every vertex the region made (the owned, and those its polygons or margin use)
    std::vector<std::uint64_t> vertex_keys;    // cube key * kSlotsPerCube + slot
    std::vector<std::uint8_t> vertex_owned;
    std::vector<std::uint64_t> triangle_keys;  // triangle_key
    DualRegion region;
};

// extract_dual_isosurface's piece for `region` of the whole grid `whole` (its domain),
// from `field`, the samples the region covers.
MeshPiece extract_dual_piece(const Field& field, const Domain& whole, const DualRegion& region, double iso,
                             Interpolation interpolation);

// The piece in slices of `thickness` planes along z (slice k: the whole grid's planes from
// k * thickness): each owns its part of the piece's box, with the piece's owned vertices
// and triangles there and the vertices those use besides, in the piece's order; welded,
// the slices are the piece.
std::vector<MeshPiece> split_planes(MeshPiece piece, int thickness);

// Planes of the whole grid a weld keeps (solver/slab_surface.hpp's slabs): the
// vertices of cubes in [lo, hi) and the triangles of edges in [tri_lo, hi) (a triangle
// uses vertices of its own plane and the one below).
struct Planes {
    int lo = 0, hi = 0, tri_lo = 0;
};

// The whole grid's mesh from pieces that own every sample once, in the whole
// extraction's order. Throws Error when an owned triangle uses a vertex no piece owns, or
// two pieces own one vertex. Frees the pieces as it goes. `planes`: only the items of
// those planes, the whole mesh's run of them (the pieces may own more: the rest is left
// out); the vertices' and triangles' keys in the mesh's order go to `keys` where given.
struct WeldedKeys {
    std::vector<std::uint64_t> vertices, triangles;
};
Mesh weld_pieces(std::vector<MeshPiece>& pieces, WeldedKeys* keys = nullptr, const Planes* planes = nullptr);

// The whole extraction made in pieces owning boxes of `cells` samples a side with their
// margin: what a tiled run computes, here from one field (tests, benchmarks).
Mesh extract_in_pieces(const Field& field, const Domain& domain, int cells, int margin, double iso = 0.0,
                       Interpolation interpolation = Interpolation::PhaseField);

}  // namespace snvr::detail
