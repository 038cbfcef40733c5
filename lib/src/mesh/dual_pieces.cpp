// The dual isosurface in pieces (dual_pieces.hpp): the regions, the field's parts, the weld.
#include "mesh/dual_pieces.hpp"

#include <algorithm>
#include <exception>
#include <functional>
#include <type_traits>
#include <limits>
#include <unordered_map>
#include <utility>

#include "snvr/error.hpp"

namespace snvr::detail {
namespace {

constexpr int kBrick = Field::kBrick;

int floor_brick(int v) { return v / kBrick * kBrick; }  // v >= 0
int ceil_brick(int v) { return (v + kBrick - 1) / kBrick * kBrick; }

}  // namespace

DualRegion DualRegion::whole_grid(const std::array<int, 3>& n) {
    DualRegion r;
    r.whole = n;
    for (int a = 0; a < 3; ++a) {
        r.cube_hi[a] = std::max(0, n[a] - 1);
        r.edge_hi[a] = n[a];
        r.own_hi[a] = n[a];
    }
    return r;
}

DualRegion DualRegion::around(const std::array<int, 3>& n, const std::array<int, 3>& lo, const std::array<int, 3>& hi,
                              int margin, const std::array<int, 3>& field_lo, const std::array<int, 3>& field_hi) {
    DualRegion r;
    r.whole = n;
    r.offset = field_lo;
    for (int a = 0; a < 3; ++a) {
        const int at = field_lo[a];
        // A polygon takes the cubes on both sides of its edge, so the cubes reach one further down.
        r.cube_lo[a] = std::max(0, lo[a] - 1 - margin) - at;
        r.cube_hi[a] = std::min(n[a] - 1, hi[a] + margin) - at;
        r.edge_lo[a] = std::max(0, lo[a] - margin) - at;
        r.edge_hi[a] = std::min(n[a], hi[a] + margin) - at;
        r.own_lo[a] = lo[a] - at;
        r.own_hi[a] = hi[a] - at;
        r.open_lo[a] = field_lo[a] > 0;
        r.open_hi[a] = field_hi[a] < n[a];
    }
    return r;
}

void DualRegion::check(const std::array<int, 3>& field_n, const std::array<int, 3>& whole_n,
                       const std::string& who) const {
    for (int a = 0; a < 3; ++a) {
        const bool fits = whole_n[a] == whole[a] && offset[a] >= 0 && offset[a] + field_n[a] <= whole[a] &&
                          cube_lo[a] >= 0 && edge_lo[a] >= 0 && own_lo[a] >= 0 && own_lo[a] <= own_hi[a] &&
                          // the cubes' samples, and past a face inside the grid the tunnel test's neighbour
                          cube_hi[a] + (open_hi[a] ? 2 : 1) <= field_n[a] && edge_hi[a] <= field_n[a] &&
                          (!open_lo[a] || (cube_lo[a] >= 0 && offset[a] > 0));
        if (!fits)
            throw ParameterError(who + "the region (axis " + std::to_string(a) + ") does not fit a field of " +
                                 std::to_string(field_n[a]) + " samples at " + std::to_string(offset[a]) + " of " +
                                 std::to_string(whole_n[a]));
    }
}

std::uint64_t triangle_key(const DualRegion& r, int i, int j, int k, int axis, int sub) {
    const auto words = std::uint64_t((r.whole[0] + 63) / 64);
    const auto gi = std::uint64_t(i + r.offset[0]), gj = std::uint64_t(j + r.offset[1]),
               gk = std::uint64_t(k + r.offset[2]);
    return ((((gk * std::uint64_t(r.whole[1]) + gj) * words + gi / 64) * 3 + std::uint64_t(axis)) * 64 + gi % 64) * 8 +
           std::uint64_t(sub);
}

bool DualRegion::owns_triangle(std::uint64_t key) const {
    const auto words = std::uint64_t((whole[0] + 63) / 64);
    key /= 8;
    const std::uint64_t bit = key % 64;
    key /= 64 * 3;
    const std::uint64_t w = key % words;
    key /= words;
    const auto j = int(key % std::uint64_t(whole[1])), k = int(key / std::uint64_t(whole[1]));
    return owns(int(w * 64 + bit) - offset[0], j - offset[1], k - offset[2]);
}

namespace {
std::uint64_t vertex_plane_keys(const std::array<int, 3>& n) {  // a plane of cubes' keys
    return std::uint64_t(std::max(1, n[0] - 1)) * std::uint64_t(std::max(1, n[1] - 1)) * kSlotsPerCube;
}
std::uint64_t triangle_plane_keys(const std::array<int, 3>& n) {  // a plane of samples' triangle keys
    return std::uint64_t(n[1]) * std::uint64_t((n[0] + 63) / 64) * 3 * 64 * 8;
}
}  // namespace

std::uint64_t first_vertex_key(int z, const std::array<int, 3>& n) { return std::uint64_t(z) * vertex_plane_keys(n); }
std::uint64_t first_triangle_key(int z, const std::array<int, 3>& n) {
    return std::uint64_t(z) * triangle_plane_keys(n);
}

std::vector<MeshPiece> split_planes(MeshPiece piece, int thickness) {
    if (thickness < 1) throw ParameterError("split_planes: a slice of no planes");
    const DualRegion& r = piece.region;
    const std::array<int, 3>& n = r.whole;
    const int lo = r.own_lo[2] + r.offset[2], hi = r.own_hi[2] + r.offset[2];
    const int first = lo / thickness, slices = hi > lo ? (hi - 1) / thickness - first + 1 : 0;
    const std::size_t nv = piece.vertex_keys.size(), nt = piece.triangle_keys.size();
    // Each owned vertex's and triangle's slice (-1: not owned here).
    std::vector<int> vertex_slice(nv, -1), triangle_slice(nt, -1);
    std::vector<std::size_t> owned(std::size_t(slices), 0), made(std::size_t(slices), 0);
    const auto slice_of = [&](int z, const char* what) {
        const int k = z / thickness - first;
        if (k < 0 || k >= slices) throw Error(std::string("split_planes: an owned ") + what + " beyond the piece's box");
        return k;
    };
    // A key's plane: the items come mostly in key order, so the last plane's bounds answer
    // most without a division.
    struct PlaneOf {
        std::uint64_t per_plane, from = 1, to = 0;
        int z = 0;
        int operator()(std::uint64_t key) {
            if (key < from || key >= to) {
                z = int(key / per_plane);
                from = std::uint64_t(z) * per_plane;
                to = from + per_plane;
            }
            return z;
        }
    };
    PlaneOf vertex_plane{vertex_plane_keys(n)}, triangle_plane{triangle_plane_keys(n)};
    for (std::size_t v = 0; v < nv; ++v) {
        if (!piece.vertex_owned[v]) continue;
        ++owned[std::size_t(vertex_slice[v] = slice_of(vertex_plane(piece.vertex_keys[v]), "vertex"))];
    }
    // Without a margin for edges every triangle is the piece's own.
    const bool all_owned = r.edge_lo == r.own_lo && r.edge_hi == r.own_hi;
    for (std::size_t t = 0; t < nt; ++t)
        if (all_owned || r.owns_triangle(piece.triangle_keys[t]))
            ++made[std::size_t(triangle_slice[t] = slice_of(triangle_plane(piece.triangle_keys[t]), "triangle"))];
    std::vector<MeshPiece> out(static_cast<std::size_t>(slices));
    std::vector<std::uint32_t> number(nv);  // an owned vertex's place in its slice
    for (int k = 0; k < slices; ++k) {
        MeshPiece& p = out[std::size_t(k)];
        p.region = r;
        p.region.own_lo[2] = std::max(lo, (first + k) * thickness) - r.offset[2];
        p.region.own_hi[2] = std::min(hi, (first + k + 1) * thickness) - r.offset[2];
        p.mesh.vertices.reserve(owned[std::size_t(k)]);
        p.vertex_keys.reserve(owned[std::size_t(k)]);
        p.vertex_owned.reserve(owned[std::size_t(k)]);
        p.mesh.triangles.reserve(made[std::size_t(k)]);
        p.triangle_keys.reserve(made[std::size_t(k)]);
    }
    for (std::size_t v = 0; v < nv; ++v)
        if (vertex_slice[v] >= 0) {
            MeshPiece& p = out[std::size_t(vertex_slice[v])];
            number[v] = std::uint32_t(p.mesh.vertices.size());
            p.mesh.vertices.push_back(piece.mesh.vertices[v]);
            p.vertex_keys.push_back(piece.vertex_keys[v]);
            p.vertex_owned.push_back(1);
        }
    // The vertices a slice's triangles use that another slice owns (or none), slice by slice.
    std::vector<int> seen(nv, -1);
    std::vector<std::uint32_t> extra(nv);
    for (std::size_t t = 0; t < nt; ++t) {
        const int k = triangle_slice[t];
        if (k < 0) continue;
        MeshPiece& p = out[std::size_t(k)];
        std::array<std::uint32_t, 3> tri{};
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t v = piece.mesh.triangles[t][std::size_t(c)];
            if (vertex_slice[v] == k) {
                tri[std::size_t(c)] = number[v];
                continue;
            }
            if (seen[v] != k) {
                seen[v] = k;
                extra[v] = std::uint32_t(p.mesh.vertices.size());
                p.mesh.vertices.push_back(piece.mesh.vertices[v]);
                p.vertex_keys.push_back(piece.vertex_keys[v]);
                p.vertex_owned.push_back(0);
            }
            tri[std::size_t(c)] = extra[v];
        }
        p.mesh.triangles.push_back(tri);
        p.triangle_keys.push_back(piece.triangle_keys[t]);
    }
    return out;
}

void field_box(const std::array<int, 3>& n, const std::array<int, 3>& lo, const std::array<int, 3>& hi, int margin,
               std::array<int, 3>& box_lo, std::array<int, 3>& box_hi) {
    for (int a = 0; a < 3; ++a) {
        // The cubes from lo - 1 - margin, their samples and their upper neighbours' (the tunnel test).
        box_lo[a] = floor_brick(std::max(0, lo[a] - 1 - margin));
        box_hi[a] = std::min(n[a], ceil_brick(hi[a] + margin + 2));
    }
}

Field field_part(const Field& whole, const std::array<int, 3>& lo, const std::array<int, 3>& hi) {
    const int nx = hi[0] - lo[0], ny = hi[1] - lo[1], nz = hi[2] - lo[2];
    const int bx = (nx + kBrick - 1) / kBrick, by = (ny + kBrick - 1) / kBrick, bz = (nz + kBrick - 1) / kBrick;
    const int b0 = lo[0] / kBrick, b1 = lo[1] / kBrick, b2 = lo[2] / kBrick;
    std::vector<std::uint32_t> table(std::size_t(bx) * std::size_t(by) * std::size_t(bz));
    std::vector<std::uint32_t> order;  // the whole's stored bricks, in the part's slots
    const auto fill = [&](auto&& slot_of) {
        for (int k = 0; k < bz; ++k)
            for (int j = 0; j < by; ++j)
                for (int i = 0; i < bx; ++i)
                    table[std::size_t(i) + std::size_t(bx) * (std::size_t(j) + std::size_t(by) * std::size_t(k))] =
                        slot_of(whole.brick_table()[std::size_t(b0 + i) +
                                                    std::size_t(whole.bricks_x()) *
                                                        (std::size_t(b1 + j) + std::size_t(whole.bricks_y()) *
                                                                                   std::size_t(b2 + k))]);
    };
    // The whole's stored brick -> the part's: by a table over the whole's where the part is
    // large beside them (a hash a brick took 0.23 s for a 2048-cell slab's face bricks),
    // else by a hash.
    constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
    if (whole.stored_bricks() <= 4 * table.size()) {
        std::vector<std::uint32_t> slot(whole.stored_bricks(), kNone);
        fill([&](std::uint32_t from) {
            std::uint32_t& s = slot[from];
            if (s == kNone) s = std::uint32_t(order.size()), order.push_back(from);
            return s;
        });
    } else {
        std::unordered_map<std::uint32_t, std::uint32_t> slot;
        fill([&](std::uint32_t from) {
            const auto [it, added] = slot.emplace(from, std::uint32_t(order.size()));
            if (added) order.push_back(from);
            return it->second;
        });
    }
    const auto copy = [&](const auto& stored) {
        std::remove_cv_t<std::remove_reference_t<decltype(stored)>> out(order.size() * Field::kBrickCells);
        for (std::size_t s = 0; s < order.size(); ++s)
            std::copy_n(stored.begin() + std::ptrdiff_t(std::size_t(order[s]) * Field::kBrickCells), Field::kBrickCells,
                        out.begin() + std::ptrdiff_t(s * Field::kBrickCells));
        return out;
    };
    return whole.precision == Precision::Double ? Field::from_bricks(nx, ny, nz, std::move(table), copy(whole.stored_f64()))
                                                : Field::from_bricks(nx, ny, nz, std::move(table), copy(whole.stored_f32()));
}

namespace {

// Items of the pieces spread over rows (`width` of them a plane), in the whole order when
// each piece's items come in its own order and the pieces in the order of their owned
// boxes along x (no sort of the whole): each piece counts its items by the rows its owned
// box spans, the rows' slots are dealt to the pieces in that order, and the pieces place
// their items at once, on the team's threads (the weld was one thread's: 1.1 s of the
// 12.5 M-point city block's at 1536 cells). row(p, n) names piece p's item n's row, or -1
// for an item not placed; sized(count) is told how many are placed, then place(p, n,
// slot) moves each (from any thread; what it throws is thrown here).
template <class Row, class Sized, class Place>
void spread_over_rows(const std::vector<MeshPiece>& pieces, const std::vector<std::size_t>& by_x, std::size_t width,
                      std::vector<std::size_t>& row_start, const std::function<std::size_t(std::size_t)>& items,
                      const Row& row, const Sized& sized, const Place& place) {
    struct Rows {  // the box of rows a piece's items take, and per row its count, then its next slot
        std::size_t j0 = 0, j1 = 0, k0 = 0, k1 = 0;
        std::vector<std::size_t> at;
        std::size_t of(std::size_t r, std::size_t width) const { return r % width - j0 + (j1 - j0) * (r / width - k0); }
    };
    const std::ptrdiff_t np = std::ptrdiff_t(pieces.size());
    const std::size_t planes = (row_start.size() - 1) / width;
    std::vector<Rows> rows(pieces.size());
    std::exception_ptr failed;
    const auto guarded = [&failed](auto&& part) {
        try {
            part();
        } catch (...) {
#pragma omp critical(snvr_spread_over_rows)
            failed = std::current_exception();
        }
    };
#pragma omp parallel for schedule(dynamic, 1)
    for (std::ptrdiff_t p = 0; p < np; ++p)
        guarded([&] {
            // A piece's items lie in the rows of its owned box.
            const DualRegion& r = pieces[std::size_t(p)].region;
            Rows& mine = rows[std::size_t(p)];
            mine.j0 = std::size_t(r.own_lo[1] + r.offset[1]), mine.k0 = std::size_t(r.own_lo[2] + r.offset[2]);
            mine.j1 = std::max(mine.j0, std::min(width, std::size_t(r.own_hi[1] + r.offset[1])));
            mine.k1 = std::max(mine.k0, std::min(planes, std::size_t(r.own_hi[2] + r.offset[2])));
            mine.at.assign((mine.j1 - mine.j0) * (mine.k1 - mine.k0), 0);
            for (std::size_t n = 0; n < items(std::size_t(p)); ++n)
                if (const long long row_of = row(std::size_t(p), n); row_of >= 0) {
                    const std::size_t j = std::size_t(row_of) % width, k = std::size_t(row_of) / width;
                    if (j < mine.j0 || j >= mine.j1 || k < mine.k0 || k >= mine.k1)
                        throw Error("weld_pieces: a piece's item lies beyond its owned box");
                    ++mine.at[mine.of(std::size_t(row_of), width)];
                }
        });
    if (failed) std::rethrow_exception(failed);
    std::fill(row_start.begin(), row_start.end(), 0);
    const auto each_row = [&](Rows& mine, auto&& f) {  // in the order `at` holds them
        std::size_t i = 0;
        for (std::size_t k = mine.k0; k < mine.k1; ++k)
            for (std::size_t j = mine.j0; j < mine.j1; ++j) f(j + width * k, mine.at[i++]);
    };
    for (Rows& mine : rows) each_row(mine, [&](std::size_t r, std::size_t& count) { row_start[r + 1] += count; });
    for (std::size_t r = 1; r < row_start.size(); ++r) row_start[r] += row_start[r - 1];
    sized(row_start.back());
    std::vector<std::size_t> next(row_start.begin(), row_start.end() - 1);
    for (std::size_t p : by_x)
        each_row(rows[p], [&](std::size_t r, std::size_t& count) {
            const std::size_t first = next[r];
            next[r] += count;
            count = first;
        });
#pragma omp parallel for schedule(dynamic, 1)
    for (std::ptrdiff_t p = 0; p < np; ++p)
        guarded([&] {
            Rows& mine = rows[std::size_t(p)];
            for (std::size_t n = 0; n < items(std::size_t(p)); ++n)
                if (const long long r = row(std::size_t(p), n); r >= 0)
                    place(std::size_t(p), n, mine.at[mine.of(std::size_t(r), width)]++);
        });
    if (failed) std::rethrow_exception(failed);
}

}  // namespace

Mesh weld_pieces(std::vector<MeshPiece>& pieces, WeldedKeys* keys_out, const Planes* planes) {
    Mesh mesh;
    if (keys_out) *keys_out = WeldedKeys();
    if (pieces.empty()) return mesh;
    const std::array<int, 3> n = pieces[0].region.whole;
    for (const MeshPiece& p : pieces)
        if (p.region.whole != n) throw ParameterError("weld_pieces: the pieces come from different grids");
    // Along x within each row of the grid, the pieces' boxes in turn.
    std::vector<std::size_t> by_x(pieces.size());
    for (std::size_t p = 0; p < pieces.size(); ++p) by_x[p] = p;
    std::stable_sort(by_x.begin(), by_x.end(), [&](std::size_t a, std::size_t b) {
        return pieces[a].region.own_lo[0] + pieces[a].region.offset[0] < pieces[b].region.own_lo[0] + pieces[b].region.offset[0];
    });
    // The keys of the planes kept: [from, to).
    struct Bounds {
        std::uint64_t vertices, triangles;
    };
    const Bounds keys_from{planes ? first_vertex_key(planes->lo, n) : 0, planes ? first_triangle_key(planes->tri_lo, n) : 0},
        keys_to{planes ? first_vertex_key(planes->hi, n) : ~std::uint64_t(0),
                planes ? first_triangle_key(planes->hi, n) : ~std::uint64_t(0)};
    // The owned vertices, row of cubes by row: their keys' order.
    const auto cx = std::uint64_t(std::max(1, n[0] - 1));
    std::vector<std::size_t> row_start(std::size_t(std::max(1, n[1] - 1)) * std::size_t(std::max(1, n[2] - 1)) + 1);
    std::vector<std::vector<std::uint32_t>> whole(pieces.size());
    for (std::size_t p = 0; p < pieces.size(); ++p)
        whole[p].assign(pieces[p].vertex_keys.size(), std::numeric_limits<std::uint32_t>::max());
    std::vector<std::uint64_t> keys;
    spread_over_rows(
        pieces, by_x, std::size_t(std::max(1, n[1] - 1)), row_start,
        [&](std::size_t p) { return pieces[p].vertex_keys.size(); },
        [&](std::size_t p, std::size_t v) {
            if (!pieces[p].vertex_owned[v]) return -1LL;
            const std::uint64_t key = pieces[p].vertex_keys[v];
            return key < keys_from.vertices || key >= keys_to.vertices ? -1LL : (long long)(key / kSlotsPerCube / cx);
        },
        [&](std::size_t count) {
            if (count >= std::numeric_limits<std::uint32_t>::max())
                throw ResourceError("weld_pieces: more than 2^32 vertices");
            mesh.vertices.resize(count);
            keys.resize(count);
        },
        [&](std::size_t p, std::size_t v, std::size_t slot) {
            mesh.vertices[slot] = pieces[p].mesh.vertices[v];
            keys[slot] = pieces[p].vertex_keys[v];
            whole[p][v] = std::uint32_t(slot);
        });
    for (std::size_t v = 1; v < keys.size(); ++v)
        if (keys[v] <= keys[v - 1])
            throw Error("weld_pieces: two pieces own the vertex of key " + std::to_string(keys[v]) +
                        ", or their boxes overlap");
    // A vertex another piece owns (on a seam, or in the margin): found by its key.
    const auto number = [&](std::size_t p, std::uint32_t v) {
        std::uint32_t& at = whole[p][v];
        if (at == std::numeric_limits<std::uint32_t>::max()) {
            const std::uint64_t key = pieces[p].vertex_keys[v];
            const auto it = std::lower_bound(keys.begin(), keys.end(), key);
            if (it == keys.end() || *it != key)
                throw Error("weld_pieces: no piece owns the vertex of key " + std::to_string(key));
            at = std::uint32_t(it - keys.begin());
        }
        return at;
    };
    // The owned triangles, row of samples by row, then within a row by key (a row's
    // word of 64 samples may span two pieces).
    const auto words = std::uint64_t((n[0] + 63) / 64);
    row_start.assign(std::size_t(n[1]) * std::size_t(n[2]) + 1, 0);
    std::vector<std::uint64_t> tri_keys;
    spread_over_rows(
        pieces, by_x, std::size_t(n[1]), row_start, [&](std::size_t p) { return pieces[p].triangle_keys.size(); },
        [&](std::size_t p, std::size_t t) {
            const std::uint64_t key = pieces[p].triangle_keys[t];
            if (key < keys_from.triangles || key >= keys_to.triangles || !pieces[p].region.owns_triangle(key))
                return -1LL;
            return (long long)(key / (8 * 64 * 3) / words);
        },
        [&](std::size_t count) {
            mesh.triangles.resize(count);
            tri_keys.resize(count);
        },
        [&](std::size_t p, std::size_t t, std::size_t slot) {
            const auto& tri = pieces[p].mesh.triangles[t];
            mesh.triangles[slot] = {number(p, tri[0]), number(p, tri[1]), number(p, tri[2])};
            tri_keys[slot] = pieces[p].triangle_keys[t];
        });
    const std::ptrdiff_t rows = std::ptrdiff_t(row_start.size() - 1);
#pragma omp parallel
    {
        std::vector<std::pair<std::uint64_t, std::array<std::uint32_t, 3>>> row;
#pragma omp for schedule(dynamic, 4096)
        for (std::ptrdiff_t r = 0; r < rows; ++r) {
            const std::size_t first = row_start[std::size_t(r)], last = row_start[std::size_t(r) + 1];
            if (std::is_sorted(tri_keys.begin() + std::ptrdiff_t(first), tri_keys.begin() + std::ptrdiff_t(last))) continue;
            row.clear();
            for (std::size_t t = first; t < last; ++t) row.emplace_back(tri_keys[t], mesh.triangles[t]);
            std::sort(row.begin(), row.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
            for (std::size_t t = first; t < last; ++t) {  // the keys too: a slab's weld gives them (WeldedKeys)
                tri_keys[t] = row[t - first].first;
                mesh.triangles[t] = row[t - first].second;
            }
        }
    }
    for (MeshPiece& p : pieces) p = MeshPiece();
    if (keys_out) {
        keys_out->vertices = std::move(keys);
        keys_out->triangles = std::move(tri_keys);
    }
    return mesh;
}

Mesh extract_in_pieces(const Field& field, const Domain& domain, int cells, int margin, double iso,
                       Interpolation interpolation) {
    if (cells < 1 || margin < 0) throw ParameterError("extract_in_pieces: cells must be positive, margin not negative");
    const std::array<int, 3> n{field.nx, field.ny, field.nz};
    std::vector<MeshPiece> pieces;
    for (int k = 0; k < n[2]; k += cells)
        for (int j = 0; j < n[1]; j += cells)
            for (int i = 0; i < n[0]; i += cells) {
                const std::array<int, 3> lo{i, j, k};
                const std::array<int, 3> hi{std::min(n[0], i + cells), std::min(n[1], j + cells), std::min(n[2], k + cells)};
                std::array<int, 3> box_lo, box_hi;
                field_box(n, lo, hi, margin, box_lo, box_hi);
                const DualRegion region = DualRegion::around(n, lo, hi, margin, box_lo, box_hi);
                pieces.push_back(
                    extract_dual_piece(field_part(field, box_lo, box_hi), domain, region, iso, interpolation));
            }
    return weld_pieces(pieces);
}

}  // namespace snvr::detail
