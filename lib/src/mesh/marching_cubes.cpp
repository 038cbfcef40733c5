// Isosurface extraction by marching tetrahedra on the cell-centred sample grid.
//
// Every grid cube is split into the six tetrahedra of the Kuhn (Freudenthal)
// triangulation, which all share the cube's main diagonal.  That triangulation
// is translation invariant, so neighbouring cubes cut their common face along
// the same diagonal and the tetrahedra form one simplicial complex over the
// box of samples.  Its edges run from a sample to the 7 neighbours whose
// offsets are non-empty subsets of {+x, +y, +z}.
//
// The surface is the level set of the piecewise linear interpolant, with
// "value > iso" inside and "value <= iso" outside (exact ties go outside, so
// every crossing lies strictly on a sign-changing edge and no index repeats).
// Why the result is a closed, oriented 2-manifold when no edge on the box
// boundary changes sign (e.g. the field is <= iso on the boundary):
//  - each sign-changing edge gets exactly one vertex, keyed by (sample, direction);
//  - a mixed tetrahedron yields one triangle or one planar convex quad whose
//    sides lie on its mixed faces; every such face is interior, shared by
//    exactly two tetrahedra, so every mesh edge has exactly two triangles;
//  - the tetrahedra around an interior edge form a single cycle, so the
//    triangles around each vertex form a single disc;
//  - each polygon is oriented from the positive to the negative corners,
//    which makes neighbours traverse their common edge in opposite directions.
// There are no ambiguous cases; the price is more triangles than marching cubes.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "mesh/isosurface_grid.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh.hpp"
#include "parallel_sizes.hpp"

namespace snvr {
namespace {

using Tri = std::array<std::uint32_t, 3>;

constexpr int kDirs = 7;       // edge directions per sample: axis bit sets 1..7
constexpr int kPlaneDirs = 3;  // the ones without a z step: 1 (x), 2 (y), 3 (xy)
constexpr int kCubeEdges = 19;  // 12 cube edges, 6 face diagonals, 1 body diagonal

// Cube corners and edge directions are bit sets: bit 0 = +x, bit 1 = +y, bit 2 = +z.
struct CubeEdge {
    std::uint8_t corner = 0;  // lower end (the other end is corner | dir)
    std::uint8_t dir = 0;
};
struct Polygon {
    std::uint8_t size = 0;  // 3 or 4
    std::array<std::uint8_t, 4> edge{};  // cube edges, counter-clockwise seen from outside
};
struct CubeCase {
    std::uint8_t count = 0;
    std::array<Polygon, 6> poly{};  // at most one per tetrahedron
};
struct Tables {
    std::array<CubeEdge, kCubeEdges> edges{};
    std::array<CubeCase, 256> cases{};
};

Vec3 corner_pos(int c) { return {double(c & 1), double(c >> 1 & 1), double(c >> 2)}; }

// Derives the per-configuration polygons from the six tetrahedra, orienting
// each one geometrically on the unit cube (crossings at edge midpoints): the
// orientation of a tetrahedron's level-set polygon does not depend on where
// along the edges the crossings lie, so this holds for any field values.
Tables make_tables() {
    Tables t;
    int edge_id[8][8];
    for (auto& row : edge_id)
        for (int& e : row) e = -1;

    const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    int tets[6][4];
    int n_edges = 0;
    for (int p = 0; p < 6; ++p) {
        const int a = 1 << perms[p][0], b = a | 1 << perms[p][1];
        const int v[4] = {0, a, b, 7};  // a monotone path: each corner is a subset of the next
        for (int q = 0; q < 4; ++q) tets[p][q] = v[q];
        for (int q = 0; q < 4; ++q)
            for (int r = q + 1; r < 4; ++r)
                if (edge_id[v[q]][v[r]] < 0) {
                    t.edges[n_edges] = {std::uint8_t(v[q]), std::uint8_t(v[r] ^ v[q])};
                    edge_id[v[q]][v[r]] = n_edges++;
                }
    }
    if (n_edges != kCubeEdges) throw Error("marching tetrahedra: bad cube triangulation");

    for (int mask = 0; mask < 256; ++mask) {
        CubeCase& cc = t.cases[mask];
        for (const auto& tet : tets) {
            int pos[4], neg[4], np = 0, nn = 0;
            for (int c : tet) ((mask >> c & 1) ? pos[np++] : neg[nn++]) = c;
            if (np == 0 || nn == 0) continue;

            std::pair<int, int> ring[4];  // sign-changing corner pairs in cyclic order
            int size = 0;
            if (np == 1)
                for (int q = 0; q < 3; ++q) ring[size++] = {pos[0], neg[q]};
            else if (nn == 1)
                for (int q = 0; q < 3; ++q) ring[size++] = {pos[q], neg[0]};
            else {
                ring[0] = {pos[0], neg[0]};
                ring[1] = {pos[0], neg[1]};
                ring[2] = {pos[1], neg[1]};
                ring[3] = {pos[1], neg[0]};
                size = 4;
            }

            Vec3 pt[4], away{0, 0, 0};
            for (int q = 0; q < size; ++q) {
                const Vec3 a = corner_pos(ring[q].first), b = corner_pos(ring[q].second);
                for (int d = 0; d < 3; ++d) pt[q][d] = 0.5 * (a[d] + b[d]);
            }
            for (int q = 0; q < nn; ++q)
                for (int d = 0; d < 3; ++d) away[d] += corner_pos(neg[q])[d] / nn;
            for (int q = 0; q < np; ++q)
                for (int d = 0; d < 3; ++d) away[d] -= corner_pos(pos[q])[d] / np;
            Vec3 u, w;
            for (int d = 0; d < 3; ++d) {
                u[d] = pt[1][d] - pt[0][d];
                w[d] = pt[2][d] - pt[0][d];
            }
            const Vec3 normal{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
            const bool flip = normal[0] * away[0] + normal[1] * away[1] + normal[2] * away[2] < 0;

            Polygon& poly = cc.poly[cc.count++];
            poly.size = std::uint8_t(size);
            for (int q = 0; q < size; ++q) {
                const auto [a, b] = ring[flip ? size - 1 - q : q];
                poly.edge[q] = std::uint8_t(edge_id[a & b][a | b]);
            }
        }
    }
    return t;
}

const Tables& tables() {
    static const Tables t = make_tables();
    return t;
}

using contour::crossing;
using contour::ctz;
using contour::Grid;
using contour::SignBits;

// Keys (i + nx*j) * 7 + dir - 1 of the sign-changing edges leaving the samples
// of plane k, in increasing order; a vertex's index is its plane's base plus
// its rank here.
std::vector<std::uint32_t> plane_edges(const Grid& g, const SignBits& sb, int k) {
    std::vector<std::uint32_t> keys;
    for (int j = 0; j < g.ny; ++j)
        for (int w = 0; w < g.words; ++w) {
            const std::uint64_t here = sb.word(j, k, w, 0);
            std::uint64_t changes[kDirs + 1] = {}, any = 0;
            for (int d = 1; d <= kDirs; ++d) {
                const int dx = d & 1, dy = d >> 1 & 1, dz = d >> 2;
                if (j + dy >= g.ny || k + dz >= g.nz) continue;
                changes[d] = (here ^ sb.word(j + dy, k + dz, w, dx)) & sb.valid(w, dx);
                any |= changes[d];
            }
            for (; any; any &= any - 1) {
                const int b = ctz(any);
                const std::uint32_t cell = std::uint32_t(64 * w + b) + std::uint32_t(g.nx) * std::uint32_t(j);
                for (int d = 1; d <= kDirs; ++d)
                    if (changes[d] >> b & 1) keys.push_back(cell * kDirs + std::uint32_t(d - 1));
            }
        }
    return keys;
}

// Crossing vertex `key` of plane k (its edge), in world coordinates.
Vec3 place_vertex(const Field& field, const Domain& domain, double iso, Interpolation interpolation, const Grid& g,
                  int k, std::uint32_t key) {
    const std::uint32_t cell = key / kDirs;
    const int dir = int(key % kDirs) + 1;
    const int i = int(cell % std::uint32_t(g.nx)), j = int(cell / std::uint32_t(g.nx));
    const int dx = dir & 1, dy = dir >> 1 & 1, dz = dir >> 2;
    const double t = crossing(field.at(i, j, k), field.at(i + dx, j + dy, k + dz), iso, interpolation);
    const Vec3 a = domain.cell_center(i, j, k), b = domain.cell_center(i + dx, j + dy, k + dz);
    return {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
}

// The triangles of the mixed cubes of slab k (between planes k and k + 1); lower and
// upper: vertex index by edge key for the slab's two planes.
struct SlabTriangles {
    const Field& field;
    double iso;
    Interpolation interpolation;
    const Grid& g;
    const Tables& tab;
    const SignBits& sb;
    const std::uint32_t* lower;
    const std::uint32_t* upper;
    int k;
    std::vector<Tri>& tris;

    void run() const {
        for (int j = 0; j + 1 < g.ny; ++j)
            for (int w = 0; w < g.words; ++w) {
                std::uint64_t corner_bits[8], any = 0, all = ~std::uint64_t(0);
                for (int c = 0; c < 8; ++c) {
                    corner_bits[c] = sb.word(j + (c >> 1 & 1), k + (c >> 2), w, c & 1);
                    any |= corner_bits[c];
                    all &= corner_bits[c];
                }
                for (std::uint64_t mixed = any & ~all & sb.valid(w, 1); mixed; mixed &= mixed - 1) {
                    const int b = ctz(mixed), i = 64 * w + b;
                    int mask = 0;
                    double value[8];
                    for (int c = 0; c < 8; ++c) {
                        mask |= int(corner_bits[c] >> b & 1) << c;
                        value[c] = field.at(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2));
                    }
                    cube(i, j, mask, value);
                }
            }
    }

    // Cube (i, j, k)'s polygons, quads split along the shorter diagonal.
    void cube(int i, int j, int mask, const double value[8]) const {
        const auto vertex_of = [&](int e) {
            const CubeEdge ce = tab.edges[e];
            const std::size_t cell = std::size_t(i + (ce.corner & 1)) + std::size_t(g.nx) * (j + (ce.corner >> 1 & 1));
            return ce.corner >> 2 ? upper[cell * kPlaneDirs + ce.dir - 1] : lower[cell * kDirs + ce.dir - 1];
        };
        // Crossing point in cube-local coordinates, for choosing quad diagonals.
        const auto local_point = [&](int e) {
            const CubeEdge ce = tab.edges[e];
            const double t = crossing(value[ce.corner], value[ce.corner | ce.dir], iso, interpolation);
            Vec3 p = corner_pos(ce.corner);
            for (int d = 0; d < 3; ++d) p[d] += t * double(ce.dir >> d & 1);
            return p;
        };
        const CubeCase& cc = tab.cases[mask];
        for (int p = 0; p < cc.count; ++p) {
            const Polygon& poly = cc.poly[p];
            const std::uint32_t v0 = vertex_of(poly.edge[0]), v1 = vertex_of(poly.edge[1]), v2 = vertex_of(poly.edge[2]);
            if (poly.size == 3) {
                tris.push_back({v0, v1, v2});
                continue;
            }
            const std::uint32_t v3 = vertex_of(poly.edge[3]);
            Vec3 q[4];
            for (int c = 0; c < 4; ++c) q[c] = local_point(poly.edge[c]);
            double d02 = 0, d13 = 0;
            for (int d = 0; d < 3; ++d) {
                d02 += (q[2][d] - q[0][d]) * (q[2][d] - q[0][d]);
                d13 += (q[3][d] - q[1][d]) * (q[3][d] - q[1][d]);
            }
            // The shorter diagonal gives better-shaped triangles; either keeps the orientation.
            if (d02 <= d13) {
                tris.push_back({v0, v1, v2});
                tris.push_back({v0, v2, v3});
            } else {
                tris.push_back({v0, v1, v3});
                tris.push_back({v1, v2, v3});
            }
        }
    }
};

}  // namespace

Mesh extract_isosurface(const Field& field, const Domain& domain, double iso, Interpolation interpolation) {
    contour::check_field(field, domain, "extract_isosurface: ");
    Mesh mesh;
    if (field.nx < 2 || field.ny < 2 || field.nz < 2) return mesh;  // no cubes
    if (std::size_t(field.nx) * std::size_t(field.ny) * kDirs > std::numeric_limits<std::uint32_t>::max())
        throw ResourceError("extract_isosurface: grid planes too large for 32-bit edge keys");

    const Grid g{field.nx, field.ny, field.nz, (field.nx + 63) / 64};
    const Tables& tab = tables();
    const bool parallel = field.size() >= std::size_t(detail::kParallelCheapItems);
    const SignBits sb(g, field, iso, parallel);

    // Pass 1: the sign-changing edges of each plane fix the vertex numbering.
    std::vector<std::vector<std::uint32_t>> keys(g.nz);
#pragma omp parallel for schedule(dynamic) if (parallel)
    for (int k = 0; k < g.nz; ++k) keys[k] = plane_edges(g, sb, k);
    std::vector<std::size_t> base(g.nz + 1, 0);
    for (int k = 0; k < g.nz; ++k) base[k + 1] = base[k] + keys[k].size();
    if (base[g.nz] >= std::numeric_limits<std::uint32_t>::max())
        throw ResourceError("extract_isosurface: more than 2^32 vertices");
    mesh.vertices.resize(base[g.nz]);

    // Pass 2, one slab of cubes between planes k and k+1 at a time: place the
    // vertices owned by plane k, then triangulate the slab's mixed cubes.
    std::vector<std::vector<Tri>> slab_tris(g.nz - 1);
#pragma omp parallel if (parallel)
    {
        // Vertex index by edge key for the slab's two planes.  Stale entries
        // from earlier slabs are harmless: only sign-changing edges are read.
        // Left uninitialised: untouched pages of large grids then cost nothing.
        const std::size_t cells = std::size_t(g.nx) * g.ny;
        const std::unique_ptr<std::uint32_t[]> lower(new std::uint32_t[cells * kDirs]);
        const std::unique_ptr<std::uint32_t[]> upper(new std::uint32_t[cells * kPlaneDirs]);
#pragma omp for schedule(dynamic)
        for (int k = 0; k < g.nz - 1; ++k) {
            for (std::size_t n = 0; n < keys[k].size(); ++n) {
                lower[keys[k][n]] = std::uint32_t(base[k] + n);
                mesh.vertices[base[k] + n] = place_vertex(field, domain, iso, interpolation, g, k, keys[k][n]);
            }
            const bool last = k + 1 == g.nz - 1;  // the top plane has no slab of its own
            for (std::size_t n = 0; n < keys[k + 1].size(); ++n) {
                const std::uint32_t key = keys[k + 1][n], d = key % kDirs;
                if (d >= kPlaneDirs) continue;  // edges going up from plane k+1 belong to the next slab
                upper[key / kDirs * kPlaneDirs + d] = std::uint32_t(base[k + 1] + n);
                if (last) mesh.vertices[base[k + 1] + n] = place_vertex(field, domain, iso, interpolation, g, k + 1, key);
            }
            SlabTriangles{field, iso, interpolation, g, tab, sb, lower.get(), upper.get(), k, slab_tris[k]}.run();
        }
    }

    contour::concatenate_in_order(slab_tris, mesh.triangles, parallel);
    return mesh;
}

}  // namespace snvr
