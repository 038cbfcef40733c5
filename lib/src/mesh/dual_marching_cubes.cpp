// Dual marching cubes on the cell-centred sample grid.
//
// Grid cubes span 2x2x2 neighbouring samples.  Inside a cube, the crossings on its
// sign-changing edges are joined face by face into segments (a face with two
// crossings has one segment; an ambiguous face, four crossings, has two, chosen by
// the asymptotic decider on that face's four values alone), and the segments chain
// into cycles: the cube's patches, i.e. the polygons of a marching-cubes surface.
// Every patch gets one vertex, the mean of its crossings (in a one-patch cube then
// moved onto the surface by Newton steps on the trilinear interpolant, in the space
// the crossings interpolate in, staying inside the cube); every sign-changing grid
// edge gets the polygon through the patches holding its crossing in the four cubes
// around it, ordered around the edge and oriented from its inside end outward.
//
// Why the result is a closed, oriented 2-manifold when no edge on the grid boundary
// changes sign:
//  - both cubes sharing a face see the same values, so they cut it into the same
//    segments: the marching-cubes polygons form a closed manifold, and our mesh is its
//    dual (vertex per polygon, face per crossing);
//  - a segment s on the face between cubes A and B gives one mesh edge, from A's patch
//    of s to B's, and lies on exactly the two polygons of its two crossings;
//  - a crossing lies in exactly one cycle of each cube, once, and consecutive
//    crossings of a cycle share a segment, so the polygons around a patch vertex form
//    a single fan (the cycle);
//  - neighbouring polygons traverse their shared edge in opposite directions, both
//    being oriented by the same inside/outside sides of the face they cross.
// The dual is a polygon mesh whose edges are distinct as vertex pairs, except in one
// configuration: an ambiguous face both of whose segments belong to a single patch on
// both sides (a tunnel through the face).  Its two mesh edges would join the same two
// vertices; instead each runs through an extra vertex at its segment's midpoint, and
// the polygons that gain such vertices are fanned from one of them.  Every edge is
// then a distinct vertex pair (the only vertices two polygons share are their common
// edge's ends), and quads are split along a diagonal between cubes that meet only at
// that grid edge, which no other polygon contains.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "mesh/dual_pieces.hpp"
#include "mesh/isosurface_grid.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh.hpp"
#include "parallel_sizes.hpp"
#include "threads_here.hpp"

namespace snvr {
namespace {

using contour::crossing;
using contour::ctz;
using contour::Grid;
using contour::SignBits;
using Tri = std::array<std::uint32_t, 3>;

constexpr int kSlabRun = 8;                        // slabs of cubes a thread takes at once
constexpr int kNone = 15;                          // patch id of an edge without a crossing

// Cube corners are bit sets (bit 0 = +x, bit 1 = +y, bit 2 = +z).  Cube edge
// axis*4 + o runs along `axis` from the corner whose other two coordinates are the
// bits of o (lower axis first).
int edge_index(int axis, int corner) {
    const int a1 = axis == 0 ? 1 : 0, a2 = axis == 2 ? 1 : 2;
    return axis * 4 + (corner >> a1 & 1) + 2 * (corner >> a2 & 1);
}
int edge_corner(int e) {
    const int axis = e / 4, a1 = axis == 0 ? 1 : 0, a2 = axis == 2 ? 1 : 2;
    return (e & 1) << a1 | (e >> 1 & 1) << a2;
}

// Face n*2 + s has normal axis n and lies at coordinate s; u < v span it.
// Corners in face order 00, 10, 01, 11 ((u, v) bits); edges u0, u1 (along u at
// v = 0, 1) and v0, v1 (along v at u = 0, 1).
struct Face {
    std::array<int, 4> corner;
    int u0, u1, v0, v1;
};
Face face(int f) {
    const int n = f / 2, s = f % 2, u = n == 0 ? 1 : 0, v = n == 2 ? 1 : 2;
    Face r{};
    for (int q = 0; q < 4; ++q) r.corner[q] = s << n | (q & 1) << u | (q >> 1) << v;
    r.u0 = edge_index(u, r.corner[0]);
    r.u1 = edge_index(u, r.corner[2]);
    r.v0 = edge_index(v, r.corner[0]);
    r.v1 = edge_index(v, r.corner[1]);
    return r;
}

// A cube's surface topology: the patch (0..3) holding each edge's crossing, 4 bits
// per edge, and the number of patches in bits 48..51.
using Topology = std::uint64_t;
int patch_of(Topology t, int e) { return int(t >> (4 * e) & 15); }
int patch_count(Topology t) { return int(t >> 48 & 15); }

struct Tables {
    std::array<Face, 6> faces{};
    std::array<std::uint8_t, 256> ambiguous{};   // bit f: face f has four crossings
    std::vector<Topology> topology;              // by mask * 64 + face decisions
};

// Segments of face f: pairs of its crossing edges.  An ambiguous face is cut at
// corners 00 and 11 exactly when corner 00's side does not own the face centre.
int face_segments(const Face& fc, int mask, bool centre_inside, int seg[2][2]) {
    const bool in00 = mask >> fc.corner[0] & 1, in10 = mask >> fc.corner[1] & 1, in01 = mask >> fc.corner[2] & 1,
               in11 = mask >> fc.corner[3] & 1;
    int cut[4], n = 0;
    if (in00 != in10) cut[n++] = fc.u0;
    if (in01 != in11) cut[n++] = fc.u1;
    if (in00 != in01) cut[n++] = fc.v0;
    if (in10 != in11) cut[n++] = fc.v1;
    if (n == 2) {
        seg[0][0] = cut[0];
        seg[0][1] = cut[1];
        return 1;
    }
    if (n != 4) return 0;
    const bool cut00 = in00 != centre_inside;
    seg[0][0] = fc.u0;
    seg[0][1] = cut00 ? fc.v0 : fc.v1;
    seg[1][0] = fc.u1;
    seg[1][1] = cut00 ? fc.v1 : fc.v0;
    return 2;
}

Tables make_tables() {
    Tables t;
    for (int f = 0; f < 6; ++f) t.faces[f] = face(f);
    for (int mask = 0; mask < 256; ++mask)
        for (int f = 0; f < 6; ++f) {
            const auto& c = t.faces[f].corner;
            const int a = mask >> c[0] & 1, b = mask >> c[1] & 1, d = mask >> c[2] & 1, e = mask >> c[3] & 1;
            if (a == e && b == d && a != b) t.ambiguous[mask] |= std::uint8_t(1 << f);
        }
    t.topology.resize(256 * 64);
    for (int mask = 0; mask < 256; ++mask)
        for (int dec = 0; dec < 64; ++dec) {
            // Each crossing has one partner on each of its two faces: the cycles are the patches.
            int adj[12][2], deg[12] = {};
            for (int f = 0; f < 6; ++f) {
                int seg[2][2];
                const int n = face_segments(t.faces[f], mask, dec >> f & 1, seg);
                for (int q = 0; q < n; ++q) {
                    adj[seg[q][0]][deg[seg[q][0]]++] = seg[q][1];
                    adj[seg[q][1]][deg[seg[q][1]]++] = seg[q][0];
                }
            }
            Topology topo = 0;
            int id[12], patches = 0;
            for (int e = 0; e < 12; ++e) id[e] = kNone;
            for (int e = 0; e < 12; ++e) {
                if (deg[e] == 0 || id[e] != kNone) continue;
                if (deg[e] != 2) throw Error("dual marching cubes: bad face segments");
                for (int prev = adj[e][1], cur = e; id[cur] == kNone;) {
                    id[cur] = patches;
                    const int next = adj[cur][0] != prev ? adj[cur][0] : adj[cur][1];
                    prev = cur;
                    cur = next;
                }
                ++patches;
            }
            if (patches > 4) throw Error("dual marching cubes: more than four patches in a cube");
            for (int e = 0; e < 12; ++e) topo |= Topology(id[e]) << (4 * e);
            t.topology[mask * 64 + dec] = topo | Topology(patches) << 48;
        }
    return t;
}

const Tables& tables() {
    static const Tables t = make_tables();
    return t;
}

// Asymptotic decider: does the bilinear interpolant's saddle on face f lie inside?
// g holds the corner values minus iso in the space the crossings interpolate in.
bool centre_inside(const Face& fc, const double g[8]) {
    const double a = g[fc.corner[0]], b = g[fc.corner[1]], c = g[fc.corner[2]], d = g[fc.corner[3]];
    return (a * d - b * c) / (a + d - b - c) > 0;
}

struct CubeTopology {
    Topology topo = 0;
    int decisions = 0;  // bit f: face f's centre is inside
};

// g: the corner values minus iso in the space the crossings interpolate in.
CubeTopology cube_topology(const Tables& tab, int mask, const double g[8]) {
    CubeTopology r;
    const int amb = tab.ambiguous[mask];
    for (int f = 0; amb && f < 6; ++f)
        if (amb >> f & 1 && centre_inside(tab.faces[f], g)) r.decisions |= 1 << f;
    r.topo = tab.topology[mask * 64 + r.decisions];
    return r;
}

CubeTopology cube_topology(const Tables& tab, int mask, const double value[8], double iso, Interpolation mode) {
    if (!tab.ambiguous[mask]) return cube_topology(tab, mask, value);  // g unused
    double g[8];
    const double iso_g = mode == Interpolation::PhaseField ? contour::unfold(iso) : iso;
    for (int c = 0; c < 8; ++c) g[c] = (mode == Interpolation::PhaseField ? contour::unfold(value[c]) : value[c]) - iso_g;
    return cube_topology(tab, mask, g);
}

// atanh of the samples of two neighbouring planes, each computed once however many
// cubes share it (a sample near the surface is a corner of up to eight): per thread,
// plane p in buffer p % 2, an entry valid while its stamp is p + 1.
class UnfoldedPlanes {
public:
    explicit UnfoldedPlanes(std::size_t plane) {
        for (int b = 0; b < 2; ++b) {
            value_[b].resize(plane);
            stamp_[b].assign(plane, 0);
        }
    }
    // n: index within plane p; v: the sample.
    double at(int p, std::size_t n, double v) {
        const int b = p & 1;
        if (stamp_[b][n] != p + 1) {
            stamp_[b][n] = p + 1;
            value_[b][n] = contour::unfold(v);
        }
        return value_[b][n];
    }

private:
    std::vector<double> value_[2];
    std::vector<int> stamp_[2];
};

// A cube with a sign change.  Its vertices are `first` (counted within its slab),
// one per patch, then two per doubled upper face (segment 0, the one through edge
// u0, then segment 1).
struct CubeRecord {
    std::uint32_t cell = 0;  // i + (nx - 1) * j
    std::uint32_t first = 0;
    Topology topo = 0;
    std::uint8_t doubled = 0;  // bit n: the face at +n is a tunnel face (see the header comment)
    std::uint8_t cut00 = 0;    // bit n: that face's segments cut its corners 00 and 11
};

Vec3 corner_pos(int c) { return {double(c & 1), double(c >> 1 & 1), double(c >> 2)}; }

// Trilinear interpolant of the corner values g over the unit cube, and its gradient.
double trilinear(const double g[8], const Vec3& x, Vec3& grad) {
    double f = 0;
    grad = {0, 0, 0};
    for (int c = 0; c < 8; ++c) {
        double w[3], dw[3];
        for (int a = 0; a < 3; ++a) {
            w[a] = c >> a & 1 ? x[a] : 1 - x[a];
            dw[a] = c >> a & 1 ? 1 : -1;
        }
        f += g[c] * w[0] * w[1] * w[2];
        grad[0] += g[c] * dw[0] * w[1] * w[2];
        grad[1] += g[c] * w[0] * dw[1] * w[2];
        grad[2] += g[c] * w[0] * w[1] * dw[2];
    }
    return f;
}

// Newton steps from x towards the zero set of the corner values' trilinear
// interpolant.  Each step is capped, as the interpolant's gradient may nearly vanish
// in a cube; the result stays strictly inside the cube, so it never meets another
// cube's vertex nor a tunnel vertex on a face.
Vec3 project(const double g[8], Vec3 x) {
    constexpr int kSteps = 2;            // a second step gains little; the mean is already close
    constexpr double kMaxStep = 0.25;    // in cube sides
    constexpr double kMargin = 1e-3;     // from the cube's faces, in cube sides
    for (int it = 0; it < kSteps; ++it) {
        Vec3 grad;
        const double f = trilinear(g, x, grad);
        const double gg = grad[0] * grad[0] + grad[1] * grad[1] + grad[2] * grad[2];
        if (!(gg > 0) || !std::isfinite(f)) break;
        double scale = -f / gg;
        const double len = std::fabs(scale) * std::sqrt(gg);
        if (len > kMaxStep) scale *= kMaxStep / len;
        for (int a = 0; a < 3; ++a) x[a] = std::clamp(x[a] + scale * grad[a], kMargin, 1 - kMargin);
    }
    return x;
}

struct Slab {
    std::vector<CubeRecord> cubes;
    std::vector<Vec3> vertices;
};

// What every stage reads: the field, its cubes and their sign bits.
struct DualGrid {
    DualGrid(const Field& f, const Domain& d, double iso_value, Interpolation mode, const detail::DualRegion& r)
        : field(f),
          domain(d),
          region(r),
          iso(iso_value),
          interpolation(mode),
          g{f.nx, f.ny, f.nz, (f.nx + 63) / 64},
          tab(tables()),
          unfolded(mode == Interpolation::PhaseField),
          iso_g(unfolded ? contour::unfold(iso_value) : iso_value),
          parallel(f.size() >= std::size_t(detail::kParallelCheapItems)),
          sb(g, f, iso_value, parallel),
          cx(g.nx - 1),
          cy(g.ny - 1),
          cz(g.nz - 1) {}

    void cube_values(int i, int j, int k, double value[8]) const {
        for (int c = 0; c < 8; ++c) value[c] = field.at(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2));
    }
    int cube_mask(const double value[8]) const {
        int mask = 0;
        for (int c = 0; c < 8; ++c) mask |= int(value[c] > iso) << c;
        return mask;
    }
    // Cubes of row j in slab k whose corners are not all on one side, 64 at a time
    // (those of the region's cubes).
    std::uint64_t mixed_cubes(int j, int k, int w) const {
        std::uint64_t any = 0, all = ~std::uint64_t(0);
        for (int c = 0; c < 8; ++c) {
            const std::uint64_t bits = sb.word(j + (c >> 1 & 1), k + (c >> 2), w, c & 1);
            any |= bits;
            all &= bits;
        }
        return any & ~all & sb.valid(w, 1) & columns(w, region.cube_lo[0], region.cube_hi[0]);
    }
    // Bits of word w for the columns [lo, hi).
    static std::uint64_t columns(int w, int lo, int hi) {
        const auto below = [w](int c) {
            const int n = c - 64 * w;
            return n <= 0 ? std::uint64_t(0) : n >= 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << n) - 1;
        };
        return below(hi) & ~below(lo);
    }
    // Sign changes along x, y, z leaving the samples of word w of row j in plane k.
    std::uint64_t changes(int j, int k, int w, std::uint64_t change[3]) const {
        const std::uint64_t here = sb.word(j, k, w, 0);
        change[0] = change[1] = change[2] = 0;
        if (k >= 1 && k + 1 < g.nz) {
            if (j >= 1 && j + 1 < g.ny) change[0] = (here ^ sb.word(j, k, w, 1)) & sb.valid(w, 1);
            if (j + 1 < g.ny) change[1] = (here ^ sb.word(j + 1, k, w, 0)) & sb.valid(w, 0);
        }
        if (k + 1 < g.nz && j >= 1 && j + 1 < g.ny) change[2] = (here ^ sb.word(j, k + 1, w, 0)) & sb.valid(w, 0);
        return here;
    }

    const Field& field;
    const Domain& domain;  // the whole grid's
    const detail::DualRegion& region;
    const double iso;
    const Interpolation interpolation;
    const Grid g;
    const Tables& tab;
    const bool unfolded;
    const double iso_g;  // iso in the space the crossings interpolate in
    const bool parallel;
    const SignBits sb;
    const int cx, cy, cz;  // cubes per axis
};

// Cube (i, j, k)'s values minus iso in the space the crossings interpolate in.
void interpolated_values(const DualGrid& d, int i, int j, int k, const double value[8], UnfoldedPlanes* planes,
                         double gv[8]) {
    for (int c = 0; c < 8; ++c)
        gv[c] = (d.unfolded ? planes->at(k + (c >> 2), std::size_t(i + (c & 1)) + std::size_t(d.g.nx) * (j + (c >> 1 & 1)),
                                         value[c])
                            : value[c]) -
                d.iso_g;
}

// A crossing on the grid boundary would leave the mesh open there: notes the cube.
void note_boundary_crossing(const DualGrid& d, int i, int j, int k, Topology topo,
                            std::atomic<long long>& boundary_cube) {
    const int lo[3] = {i, j, k}, hi[3] = {d.cx, d.cy, d.cz};
    for (int n = 0; n < 3; ++n)
        for (int side = 0; side < 2; ++side) {
            if (side ? lo[n] != hi[n] - 1 || d.region.open_hi[n] : lo[n] != 0 || d.region.open_lo[n]) continue;
            const Face& fc = d.tab.faces[2 * n + side];
            for (int e : {fc.u0, fc.u1, fc.v0, fc.v1})
                if (patch_of(topo, e) != kNone)
                    boundary_cube = (long long)(i) + (long long)(d.g.nx) * (j + (long long)(d.g.ny) * k);
        }
}

// One vertex per patch: the mean of its crossings (local, in cube sides), in a
// one-patch cube moved onto the surface.
void patch_vertices(const Vec3 local[12], Topology topo, const double gv[8], const Vec3& base, double h,
                    std::vector<Vec3>& vertices) {
    const int patches = patch_count(topo);
    Vec3 sum[4] = {};
    int count[4] = {};
    for (int e = 0; e < 12; ++e) {
        const int p = patch_of(topo, e);
        if (p == kNone) continue;
        for (int d = 0; d < 3; ++d) sum[p][d] += local[e][d];
        ++count[p];
    }
    // The mean of a curved patch's crossings lies towards its centre of
    // curvature; a one-patch cube moves it onto the surface.  Several
    // patches keep the mean: their interpolant may pull it to another patch.
    for (int p = 0; p < patches; ++p) {
        const Vec3 mean{sum[p][0] / count[p], sum[p][1] / count[p], sum[p][2] / count[p]};
        const Vec3 l = patches == 1 ? project(gv, mean) : mean;
        vertices.push_back(Vec3{base[0] + h * l[0], base[1] + h * l[1], base[2] + h * l[2]});
    }
}

// Tunnel faces at +n: ambiguous, and one patch holds all four crossings on both
// sides; each gets its two segments' midpoints as vertices.
void tunnel_faces(const DualGrid& d, int i, int j, int k, int mask, const CubeTopology& ct, const Vec3 local[12],
                  const Vec3& base, CubeRecord& rec, std::vector<Vec3>& vertices) {
    const int lo[3] = {i, j, k}, hi[3] = {d.cx, d.cy, d.cz};
    const Tables& tab = d.tab;
    for (int n = 0; n < 3; ++n) {
        const Face& fc = tab.faces[2 * n + 1];
        if (!(tab.ambiguous[mask] >> (2 * n + 1) & 1) || lo[n] + 1 >= hi[n]) continue;
        const int p = patch_of(ct.topo, fc.u0);
        if (patch_of(ct.topo, fc.u1) != p || patch_of(ct.topo, fc.v0) != p || patch_of(ct.topo, fc.v1) != p) continue;
        double other[8];
        d.cube_values(i + (n == 0), j + (n == 1), k + (n == 2), other);
        const Topology ot = cube_topology(tab, d.cube_mask(other), other, d.iso, d.interpolation).topo;
        const Face& oc = tab.faces[2 * n];
        const int q = patch_of(ot, oc.u0);
        if (patch_of(ot, oc.u1) != q || patch_of(ot, oc.v0) != q || patch_of(ot, oc.v1) != q) continue;
        const bool cut00 = bool(mask >> fc.corner[0] & 1) != bool(ct.decisions >> (2 * n + 1) & 1);
        rec.doubled |= std::uint8_t(1 << n);
        rec.cut00 |= std::uint8_t(cut00 << n);
        const int segs[2][2] = {{fc.u0, cut00 ? fc.v0 : fc.v1}, {fc.u1, cut00 ? fc.v1 : fc.v0}};
        for (const auto& sg : segs) {
            Vec3 m;
            for (int a = 0; a < 3; ++a) m[a] = 0.5 * (local[sg[0]][a] + local[sg[1]][a]);
            vertices.push_back(Vec3{base[0] + d.domain.h * m[0], base[1] + d.domain.h * m[1], base[2] + d.domain.h * m[2]});
        }
    }
}

// Cube (i, j, k), which has a sign change: its patches, their vertices, its tunnel faces.
void add_cube(const DualGrid& d, int i, int j, int k, UnfoldedPlanes* planes, Slab& slab,
              std::atomic<long long>& boundary_cube) {
    double value[8];
    d.cube_values(i, j, k, value);
    const int mask = d.cube_mask(value);
    double gv[8];
    interpolated_values(d, i, j, k, value, planes, gv);
    const CubeTopology ct = cube_topology(d.tab, mask, gv);
    note_boundary_crossing(d, i, j, k, ct.topo, boundary_cube);

    CubeRecord rec;
    rec.cell = std::uint32_t(i) + std::uint32_t(d.cx) * std::uint32_t(j);
    rec.first = std::uint32_t(slab.vertices.size());
    rec.topo = ct.topo;
    Vec3 local[12];  // the crossings, in cube sides
    for (int e = 0; e < 12; ++e) {
        if (patch_of(ct.topo, e) == kNone) continue;
        const int c0 = edge_corner(e), axis = e / 4;
        local[e] = corner_pos(c0);
        local[e][axis] += crossing(gv[c0], gv[c0 | 1 << axis], 0.0);
    }
    const auto& at = d.region.offset;
    const Vec3 base = d.domain.cell_center(i + at[0], j + at[1], k + at[2]);
    patch_vertices(local, ct.topo, gv, base, d.domain.h, slab.vertices);
    tunnel_faces(d, i, j, k, mask, ct, local, base, rec, slab.vertices);
    slab.cubes.push_back(rec);
}

// Pass 1 for slab k: its cubes with a sign change, in order.
void classify_slab(const DualGrid& d, int k, UnfoldedPlanes* planes, Slab& slab,
                   std::atomic<long long>& boundary_cube) {
    std::size_t count = 0;  // to size the slab's lists once
    const int j_lo = d.region.cube_lo[1], j_hi = d.region.cube_hi[1];
    for (int j = j_lo; j < j_hi; ++j)
        for (int w = 0; w < d.g.words; ++w) count += std::size_t(contour::popcount(d.mixed_cubes(j, k, w)));
    slab.cubes.reserve(count);
    slab.vertices.reserve(count + count / 8);
    for (int j = j_lo; j < j_hi; ++j)
        for (int w = 0; w < d.g.words; ++w)
            for (std::uint64_t mixed = d.mixed_cubes(j, k, w); mixed; mixed &= mixed - 1)
                add_cube(d, 64 * w + ctz(mixed), j, k, planes, slab, boundary_cube);
}

// Pass 1, one slab of cubes at a time: patches, their vertices, tunnel faces.
std::vector<Slab> classify_cubes(const DualGrid& d, const std::string& who) {
    std::vector<Slab> slabs(d.cz);
    std::atomic<long long> boundary_cube{-1};
    std::vector<std::unique_ptr<UnfoldedPlanes>> thread_planes(static_cast<std::size_t>(detail::threads_here()));
    // Slabs in runs of neighbours, so that a thread's planes serve the next slab (one
    // slab at a time, two threads each took every other slab and unfolded every plane
    // twice: 1.5x from the second thread instead of 2x).
#pragma omp parallel for schedule(dynamic, kSlabRun) if (d.parallel)
    for (int k = d.region.cube_lo[2]; k < d.region.cube_hi[2]; ++k) {
        std::unique_ptr<UnfoldedPlanes>& mine = thread_planes[std::size_t(detail::thread_number())];
        if (d.unfolded && !mine) mine = std::make_unique<UnfoldedPlanes>(std::size_t(d.g.nx) * std::size_t(d.g.ny));
        classify_slab(d, k, mine.get(), slabs[k], boundary_cube);
    }
    if (boundary_cube >= 0) {
        const long long c = boundary_cube;
        const Grid& g = d.g;
        throw InputError(who + "the field crosses iso on the boundary of the grid (at sample " +
                         std::to_string(c % g.nx) + ", " + std::to_string(c / g.nx % g.ny) + ", " +
                         std::to_string(c / g.nx / g.ny) +
                         "), which would leave the mesh open; the field must stay on one side of iso there");
    }
    return slabs;
}

// The slabs' vertices into the mesh, in slab order; returns each slab's first vertex.
std::vector<std::size_t> gather_vertices(const DualGrid& d, std::vector<Slab>& slabs, Mesh& mesh,
                                         const std::string& who) {
    const int cz = d.cz;
    std::vector<std::size_t> vbase(cz + 1, 0);
    for (int k = 0; k < cz; ++k) vbase[k + 1] = vbase[k] + slabs[k].vertices.size();
    if (vbase[cz] >= std::numeric_limits<std::uint32_t>::max())
        throw ResourceError(who + "more than 2^32 vertices");
    mesh.vertices.resize(vbase[cz]);
#pragma omp parallel for schedule(dynamic) if (d.parallel)
    for (int k = 0; k < cz; ++k) {
        std::copy(slabs[k].vertices.begin(), slabs[k].vertices.end(), mesh.vertices.begin() + std::ptrdiff_t(vbase[k]));
        std::vector<Vec3>().swap(slabs[k].vertices);
    }
    return vbase;
}

// Per axis of an edge: (b, c) with b x c = axis; the four cubes around the edge
// counter-clockwise seen from +axis (offsets, and the edge's index in each); for each
// cube t and the next, u, the normal axis n of the face they share and which of the
// two cubes is on its low side.
struct Around {
    int b, c;
    int off[4][3], local[4], n[4], low[4];
};

std::array<Around, 3> around_edges() {
    std::array<Around, 3> around{};
    for (int axis = 0; axis < 3; ++axis) {
        Around& a = around[axis];
        a.b = (axis + 1) % 3;
        a.c = (axis + 2) % 3;
        const int ob[4] = {-1, 0, 0, -1}, oc[4] = {-1, -1, 0, 0};
        for (int t = 0; t < 4; ++t) {
            int o[3] = {0, 0, 0};
            o[a.b] = ob[t];
            o[a.c] = oc[t];
            for (int d = 0; d < 3; ++d) a.off[t][d] = o[d];
            a.local[t] = edge_index(axis, (-o[a.b]) << a.b | (-o[a.c]) << a.c);
        }
        for (int t = 0; t < 4; ++t) {
            const int u = (t + 1) % 4;
            a.n[t] = ob[t] != ob[u] ? a.b : a.c;
            a.low[t] = a.off[t][a.n[t]] < a.off[u][a.n[t]] ? t : u;
        }
    }
    return around;
}

// A quad's two triangles: split where the two triangles' normals agree best (no
// fold); on a near tie, along the shorter diagonal.
void split_quad(const std::uint32_t ring[4], const std::vector<Vec3>& vertices, std::vector<Tri>& tris) {
    const Vec3* p[4];
    for (int t = 0; t < 4; ++t) p[t] = &vertices[ring[t]];
    const auto sub = [](const Vec3& x, const Vec3& y) { return Vec3{x[0] - y[0], x[1] - y[1], x[2] - y[2]}; };
    const auto cross = [](const Vec3& x, const Vec3& y) {
        return Vec3{x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]};
    };
    const auto dot = [](const Vec3& x, const Vec3& y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; };
    const auto agreement = [&](int a0, int a1, int a2, int b0, int b1, int b2) {
        const Vec3 na = cross(sub(*p[a1], *p[a0]), sub(*p[a2], *p[a0]));
        const Vec3 nb = cross(sub(*p[b1], *p[b0]), sub(*p[b2], *p[b0]));
        const double l = std::sqrt(dot(na, na) * dot(nb, nb));
        return l > 0 ? dot(na, nb) / l : -1.0;
    };
    const double a02 = agreement(0, 1, 2, 0, 2, 3), a13 = agreement(0, 1, 3, 1, 2, 3);
    bool split02 = a02 > a13;
    if (std::abs(a02 - a13) < 1e-3) {
        const Vec3 d02 = sub(*p[2], *p[0]), d13 = sub(*p[3], *p[1]);
        split02 = dot(d02, d02) <= dot(d13, d13);
    }
    if (split02) {
        tris.push_back({ring[0], ring[1], ring[2]});
        tris.push_back({ring[0], ring[2], ring[3]});
    } else {
        tris.push_back({ring[0], ring[1], ring[3]});
        tris.push_back({ring[1], ring[2], ring[3]});
    }
}

// Pass 2 for plane k: a polygon across each sign-changing edge leaving it. below and
// above: record index by cube for the slabs below and above the plane.
struct PlanePolygons {
    const DualGrid& d;
    const std::vector<Slab>& slabs;
    const std::vector<std::size_t>& vbase;
    const std::array<Around, 3>& around;
    const std::vector<Vec3>& vertices;
    const std::uint32_t* below;
    const std::uint32_t* above;
    int k;
    std::vector<Tri>& tris;
    std::vector<std::uint64_t>* keys;  // a piece's: each triangle's place in the whole grid's order

    // Sign changes along x, y, z leaving the region's edges of word w of row j.
    std::uint64_t changes(int j, int w, std::uint64_t change[3]) const {
        const std::uint64_t here = d.changes(j, k, w, change);
        const std::uint64_t mine = DualGrid::columns(w, d.region.edge_lo[0], d.region.edge_hi[0]);
        for (int axis = 0; axis < 3; ++axis) change[axis] &= mine;
        return here;
    }

    void run() const {
        std::size_t count = 0;  // two triangles per polygon but for rare fans
        const int j_lo = d.region.edge_lo[1], j_hi = d.region.edge_hi[1];
        for (int j = j_lo; j < j_hi; ++j)
            for (int w = 0; w < d.g.words; ++w) {
                std::uint64_t change[3];
                changes(j, w, change);
                for (int axis = 0; axis < 3; ++axis) count += std::size_t(contour::popcount(change[axis]));
            }
        tris.reserve(2 * count);
        if (keys) keys->reserve(2 * count);
        for (int j = j_lo; j < j_hi; ++j)
            for (int w = 0; w < d.g.words; ++w) {
                std::uint64_t change[3];
                const std::uint64_t here = changes(j, w, change);
                for (int axis = 0; axis < 3; ++axis)
                    for (std::uint64_t bits = change[axis]; bits; bits &= bits - 1) {
                        const int i = 64 * w + ctz(bits);
                        if (axis != 0 && (i == 0 || i + 1 == d.g.nx)) continue;  // on the grid boundary
                        const std::size_t first = tris.size();
                        emit(i, j, axis, here >> (i - 64 * w) & 1);
                        if (keys)
                            for (std::size_t t = first; t < tris.size(); ++t)
                                keys->push_back(detail::triangle_key(d.region, i, j, k, axis, int(t - first)));
                    }
            }
    }

    // Edge (i, j, k) along `axis`: the patches around it, ordered and oriented from its
    // inside end outward, with the tunnel vertices on the faces between them.
    void emit(int i, int j, int axis, bool inside_low) const {
        const Around& a = around[axis];
        const auto& off = a.off;
        const auto& local = a.local;
        const CubeRecord* rec[4];
        std::size_t first[4];
        for (int t = 0; t < 4; ++t) {
            const int ck = k + off[t][2];
            const std::uint32_t cell = std::uint32_t(i + off[t][0]) + std::uint32_t(d.cx) * std::uint32_t(j + off[t][1]);
            rec[t] = &slabs[ck].cubes[(ck == k ? above : below)[cell]];
            first[t] = vbase[ck] + rec[t]->first;
        }
        std::uint32_t ring[8];
        int size = 0, fan = -1;
        for (int t = 0; t < 4; ++t) {
            ring[size++] = std::uint32_t(first[t] + std::size_t(patch_of(rec[t]->topo, local[t])));
            const int n = a.n[t], low = a.low[t];
            const CubeRecord& lr = *rec[low];
            if (!(lr.doubled >> n & 1)) continue;
            const Face& fc = d.tab.faces[2 * n + 1];
            const int e = local[low];
            const int seg = e == fc.u0 || e == ((lr.cut00 >> n & 1) ? fc.v0 : fc.v1) ? 0 : 1;
            const int rank = __builtin_popcount(unsigned(lr.doubled) & ((1u << n) - 1));
            if (fan < 0) fan = size;
            ring[size++] =
                std::uint32_t(vbase[k + (off[low][2])] + lr.first + std::uint32_t(patch_count(lr.topo) + 2 * rank + seg));
        }
        if (!inside_low) std::reverse(ring, ring + size);
        if (size > 4) {  // fan from a tunnel vertex: it shares no other polygon's vertices
            const int m = inside_low ? fan : size - 1 - fan;
            for (int q = 1; q + 1 < size; ++q) tris.push_back({ring[m], ring[(m + q) % size], ring[(m + q + 1) % size]});
            return;
        }
        split_quad(ring, vertices, tris);
    }
};

// Pass 2, one plane of samples at a time: a polygon across each sign-changing
// edge leaving it (along x and y within it, along z to the next plane).
// plane_keys (a piece's): each triangle's place in the whole grid's order, by plane.
std::vector<std::vector<Tri>> polygons(const DualGrid& d, const std::vector<Slab>& slabs,
                                       const std::vector<std::size_t>& vbase, const std::vector<Vec3>& vertices,
                                       std::vector<std::vector<std::uint64_t>>* plane_keys) {
    std::vector<std::vector<Tri>> plane_tris(d.g.nz);
    if (plane_keys) plane_keys->assign(std::size_t(d.g.nz), {});
    const std::array<Around, 3> around = around_edges();
#pragma omp parallel if (d.parallel)
    {
        // Stale entries are harmless: only cubes around sign-changing edges are read.
        const std::size_t cells = std::size_t(d.cx) * d.cy;
        const std::unique_ptr<std::uint32_t[]> below(new std::uint32_t[cells]);
        const std::unique_ptr<std::uint32_t[]> above(new std::uint32_t[cells]);
#pragma omp for schedule(dynamic)
        for (int k = d.region.edge_lo[2]; k < d.region.edge_hi[2]; ++k) {
            if (k >= 1)
                for (std::size_t r = 0; r < slabs[k - 1].cubes.size(); ++r)
                    below[slabs[k - 1].cubes[r].cell] = std::uint32_t(r);
            if (k < d.cz)
                for (std::size_t r = 0; r < slabs[k].cubes.size(); ++r) above[slabs[k].cubes[r].cell] = std::uint32_t(r);
            PlanePolygons{d,     slabs,         vbase,
                          around, vertices,     below.get(),
                          above.get(), k,       plane_tris[k],
                          plane_keys ? &(*plane_keys)[std::size_t(k)] : nullptr}
                .run();
        }
    }
    return plane_tris;
}

}  // namespace

Mesh extract_dual_isosurface(const Field& field, const Domain& domain, double iso, Interpolation interpolation) {
    const std::string who = "extract_dual_isosurface: ";
    contour::check_field(field, domain, who);
    Mesh mesh;
    if (field.nx < 2 || field.ny < 2 || field.nz < 2) return mesh;  // no cubes
    if (std::size_t(field.nx) * std::size_t(field.ny) >= std::numeric_limits<std::uint32_t>::max())
        throw ResourceError(who + "grid planes too large for 32-bit cube keys");
    const detail::DualRegion whole = detail::DualRegion::whole_grid({field.nx, field.ny, field.nz});
    const DualGrid d(field, domain, iso, interpolation, whole);
    std::vector<Slab> slabs = classify_cubes(d, who);
    const std::vector<std::size_t> vbase = gather_vertices(d, slabs, mesh, who);
    std::vector<std::vector<Tri>> plane_tris = polygons(d, slabs, vbase, mesh.vertices, nullptr);
    contour::concatenate_in_order(plane_tris, mesh.triangles, d.parallel);
    return mesh;
}

detail::MeshPiece detail::extract_dual_piece(const Field& field, const Domain& whole, const DualRegion& region,
                                             double iso, Interpolation interpolation) {
    const std::string who = "extract_dual_piece: ";
    field.validate(who);
    region.check({field.nx, field.ny, field.nz}, {whole.nx, whole.ny, whole.nz}, who);
    MeshPiece piece;
    piece.region = region;
    if (field.nx < 2 || field.ny < 2 || field.nz < 2) return piece;
    const DualGrid d(field, whole, iso, interpolation, region);
    std::vector<Slab> slabs = classify_cubes(d, who);
    const std::vector<std::size_t> vbase = gather_vertices(d, slabs, piece.mesh, who);
    // Each vertex's key: its cube's place in the whole grid, and its slot in the cube.
    piece.vertex_keys.resize(piece.mesh.vertices.size());
    piece.vertex_owned.resize(piece.mesh.vertices.size());
#pragma omp parallel for schedule(dynamic) if (d.parallel)
    for (int k = 0; k < d.cz; ++k) {
        const std::vector<CubeRecord>& cubes = slabs[std::size_t(k)].cubes;
        for (std::size_t r = 0; r < cubes.size(); ++r) {
            const std::size_t first = vbase[std::size_t(k)] + cubes[r].first;
            const std::size_t last = r + 1 < cubes.size() ? vbase[std::size_t(k)] + cubes[r + 1].first : vbase[std::size_t(k) + 1];
            const int i = int(cubes[r].cell % std::uint32_t(d.cx)), j = int(cubes[r].cell / std::uint32_t(d.cx));
            const std::uint64_t cube = region.cube_key(i, j, k);
            const bool owned = region.owns(i, j, k);
            for (std::size_t v = first; v < last; ++v) {
                piece.vertex_keys[v] = cube * kSlotsPerCube + (v - first);
                piece.vertex_owned[v] = owned;
            }
        }
    }
    std::vector<std::vector<std::uint64_t>> plane_keys;
    std::vector<std::vector<Tri>> plane_tris = polygons(d, slabs, vbase, piece.mesh.vertices, &plane_keys);
    contour::concatenate_in_order(plane_tris, piece.mesh.triangles, d.parallel);
    contour::concatenate_in_order(plane_keys, piece.triangle_keys, d.parallel);
    return piece;
}

}  // namespace snvr
