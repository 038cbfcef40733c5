// A tiled run's surface from its tiles (tile_surface.hpp).
#include "solver/tile_surface.hpp"

#include <algorithm>
#include <utility>

#include "mesh/dual_pieces.hpp"
#include "snvr/error.hpp"
#include "solver/brick_grid.hpp"

namespace snvr {
namespace {

std::array<int, 3> samples_of(const Domain& d) { return {d.nx, d.ny, d.nz}; }

// The piece owning [lo, hi) and its field's box.
struct PieceBox {
    std::array<int, 3> lo{}, hi{}, field_lo{}, field_hi{};
    detail::DualRegion region;
};
PieceBox piece_box(const Domain& whole, const std::array<int, 3>& lo, const std::array<int, 3>& hi) {
    PieceBox b;
    b.lo = lo;
    b.hi = hi;
    detail::field_box(samples_of(whole), lo, hi, 0, b.field_lo, b.field_hi);
    b.region = detail::DualRegion::around(samples_of(whole), lo, hi, 0, b.field_lo, b.field_hi);
    return b;
}

// Whether the tile's core has a face inside the grid at its low (high) end along axis a.
bool inner_low(const Tile& tile, std::size_t a) { return tile.core_lo[a] > 0; }
bool inner_high(const Tile& tile, const std::array<int, 3>& n, std::size_t a) { return tile.core_hi[a] < n[a]; }

bool empty_box(const std::array<int, 3>& lo, const std::array<int, 3>& hi) {
    return lo[0] >= hi[0] || lo[1] >= hi[1] || lo[2] >= hi[2];
}

// The samples along one axis no interior owns: three about each plane between cores.
// Returns the planes' bands and, between them, the interiors' intervals.
void bands(int n, int core, std::vector<std::array<int, 2>>& seams, std::vector<std::array<int, 2>>& inner) {
    int from = 0;
    for (int c = core; c < n; c += core) {
        seams.push_back({c - 2, c + 1});
        inner.push_back({from, c - 2});
        from = c + 1;
    }
    inner.push_back({from, n});
}

}  // namespace

void tile_interior(const Tile& tile, const Domain& whole, std::array<int, 3>& lo, std::array<int, 3>& hi) {
    const std::array<int, 3> n = samples_of(whole);
    for (int a = 0; a < 3; ++a) {
        const std::size_t s = std::size_t(a);
        lo[s] = tile.core_lo[s] + (inner_low(tile, s) ? 1 : 0);
        hi[s] = tile.core_hi[s] - (inner_high(tile, n, s) ? 2 : 0);
    }
}

std::vector<detail::MeshPiece> tile_surface(const Field& tile_field, const Tile& tile, const Domain& whole, int slice) {
    std::array<int, 3> lo, hi;
    tile_interior(tile, whole, lo, hi);
    if (empty_box(lo, hi)) return {};
    const PieceBox b = piece_box(whole, lo, hi);
    std::array<int, 3> at_lo, at_hi;  // the box on the tile's grid: within its core
    for (std::size_t a = 0; a < 3; ++a) {
        if (b.field_lo[a] < tile.core_lo[a] || b.field_hi[a] > tile.core_hi[a])
            throw Error("tile_surface: the interior reaches beyond the tile's core");
        at_lo[a] = b.field_lo[a] - tile.lo[a];
        at_hi[a] = b.field_hi[a] - tile.lo[a];
    }
    detail::MeshPiece p = detail::extract_dual_piece(detail::field_part(tile_field, at_lo, at_hi), whole, b.region, 0.0,
                                                     Interpolation::PhaseField);
    if (slice > 0) return detail::split_planes(std::move(p), slice);
    std::vector<detail::MeshPiece> one;
    one.push_back(std::move(p));
    return one;
}

Field tile_faces(const Field& tile_field, const Tile& tile, const Domain& whole) {
    const std::array<int, 3> n = samples_of(whole);
    const int bx = tile_field.bricks_x(), by = tile_field.bricks_y(), bz = tile_field.bricks_z();
    std::vector<std::uint32_t> table(tile_field.brick_table().size(), kMinusSlot);
    const bool single = tile_field.precision == Precision::Single;
    std::vector<float> f32;
    std::vector<double> f64;
    const auto keep = [&](std::uint32_t slot) {  // the constant slots first, as the tile's layout has them
        const std::size_t from = std::size_t(slot) * kBrickCells;
        if (single) f32.insert(f32.end(), tile_field.stored_f32().begin() + std::ptrdiff_t(from),
                               tile_field.stored_f32().begin() + std::ptrdiff_t(from + kBrickCells));
        else f64.insert(f64.end(), tile_field.stored_f64().begin() + std::ptrdiff_t(from),
                        tile_field.stored_f64().begin() + std::ptrdiff_t(from + kBrickCells));
    };
    for (std::uint32_t c = 0; c < kConstantSlots; ++c) keep(c);
    std::uint32_t next = kConstantSlots;
    for (int k = 0; k < bz; ++k)
        for (int j = 0; j < by; ++j)
            for (int i = 0; i < bx; ++i) {
                const int at[3] = {tile.lo[0] + kBrick * i, tile.lo[1] + kBrick * j, tile.lo[2] + kBrick * k};
                bool core = true, face = false;
                for (std::size_t a = 0; a < 3; ++a) {
                    core = core && at[a] >= tile.core_lo[a] && at[a] < tile.core_hi[a];
                    face = face || (at[a] == tile.core_lo[a] && inner_low(tile, a)) ||
                           (at[a] + kBrick >= tile.core_hi[a] && inner_high(tile, n, a));
                }
                const std::size_t b = std::size_t(i) + std::size_t(bx) * (std::size_t(j) + std::size_t(by) * std::size_t(k));
                const std::uint32_t slot = tile_field.brick_table()[b];
                if (!core || !face) continue;
                if (slot < kConstantSlots) {
                    table[b] = slot;
                    continue;
                }
                keep(slot);
                table[b] = next++;
            }
    return single ? Field::from_bricks(tile_field.nx, tile_field.ny, tile_field.nz, std::move(table), std::move(f32))
                  : Field::from_bricks(tile_field.nx, tile_field.ny, tile_field.nz, std::move(table), std::move(f64));
}

int inner_faces(const Tile& tile, const Domain& whole) {
    const std::array<int, 3> n = samples_of(whole);
    int faces = 0;
    for (std::size_t a = 0; a < 3; ++a) faces += int(inner_low(tile, a)) + int(inner_high(tile, n, a));
    return faces;
}

std::size_t stored_core_bricks(const Field& tile_field, const Tile& tile) {
    std::size_t stored = 0;
    const int bx = tile_field.bricks_x(), by = tile_field.bricks_y();
    for (int k = tile.core_lo[2]; k < tile.core_hi[2]; k += kBrick)
        for (int j = tile.core_lo[1]; j < tile.core_hi[1]; j += kBrick)
            for (int i = tile.core_lo[0]; i < tile.core_hi[0]; i += kBrick) {
                const std::size_t b = std::size_t((i - tile.lo[0]) / kBrick) +
                                      std::size_t(bx) * (std::size_t((j - tile.lo[1]) / kBrick) +
                                                         std::size_t(by) * std::size_t((k - tile.lo[2]) / kBrick));
                stored += tile_field.brick_table()[b] >= kConstantSlots;
            }
    return stored;
}

FacesPart faces_for(const Field& faces, const detail::Planes& planes) {
    // A seam's cubes reach one sample below its planes, their samples and the tunnel test two above.
    FacesPart part;
    part.z = std::max(0, planes.lo - 1) / Field::kBrick * Field::kBrick;
    const int hi = std::min(faces.nz, (planes.hi + 2 + Field::kBrick - 1) / Field::kBrick * Field::kBrick);
    part.field = detail::field_part(faces, {0, 0, part.z}, {faces.nx, faces.ny, std::max(part.z, hi)});
    return part;
}

std::vector<detail::MeshPiece> seam_pieces(const FacesPart& faces, const Domain& whole, int core_cells,
                                           const detail::Planes& planes) {
    std::vector<detail::MeshPiece> pieces;
    // About the planes across x whole; across y between them; across z in what is left;
    // each within the slab's planes.
    const std::array<int, 3> n = samples_of(whole);
    std::array<std::vector<std::array<int, 2>>, 3> seam, inner;
    for (std::size_t a = 0; a < 3; ++a) bands(n[a], core_cells, seam[a], inner[a]);
    const auto add = [&](std::array<int, 3> lo, std::array<int, 3> hi) {
        lo[2] = std::max(lo[2], planes.lo);
        hi[2] = std::min(hi[2], planes.hi);
        if (empty_box(lo, hi)) return;
        const PieceBox b = piece_box(whole, lo, hi);
        if (b.field_lo[2] < faces.z || b.field_hi[2] > faces.z + faces.field.nz)
            throw Error("seam_pieces: a seam reaches beyond the faces' bricks given");
        pieces.push_back(detail::extract_dual_piece(
            detail::field_part(faces.field, {b.field_lo[0], b.field_lo[1], b.field_lo[2] - faces.z},
                               {b.field_hi[0], b.field_hi[1], b.field_hi[2] - faces.z}),
            whole, b.region, 0.0, Interpolation::PhaseField));
    };
    for (const auto& sx : seam[0]) add({sx[0], 0, 0}, {sx[1], n[1], n[2]});
    for (const auto& sy : seam[1])
        for (const auto& ix : inner[0]) add({ix[0], sy[0], 0}, {ix[1], sy[1], n[2]});
    for (const auto& sz : seam[2])
        for (const auto& ix : inner[0])
            for (const auto& iy : inner[1]) add({ix[0], iy[0], sz[0]}, {ix[1], iy[1], sz[1]});
    return pieces;
}

}  // namespace snvr
