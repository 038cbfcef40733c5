#include "geometry/band_distance.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>


namespace snvr {

namespace {

// Level-0 bricks whose cell centres come within `radius` (world) of some point: each
// leaf's box rules out the bricks beyond it, and its points are looked at one by one only
// for a brick no point has marked yet.
std::vector<std::uint8_t> bricks_near_points(const detail::PointTree& tree, const Domain& d, const BrickTiling& lv,
                                             double radius) {
    std::vector<std::uint8_t> near(lv.brick_count(), 0);
    const int nb[3] = {lv.bx, lv.by, lv.bz};
    const int n[3] = {d.nx, d.ny, d.nz};
    const double span = kBrick * d.h;
    const double rr = radius * radius;
    // The leaves that can mark a brick of this grid: within the radius of its box (a
    // tile's grid is a small part of the cloud's; every leaf, each tile over, cost a tiled
    // run of 98.5 M points 7x the whole run's distance).
    std::vector<const detail::PointTree::Node*> leaves;
    const auto near_grid = [&](const detail::PointTree::Node& node) {
        const Vec3 lo = tree.lo(node), hi = tree.hi(node);
        for (int a = 0; a < 3; ++a)
            if (hi[a] + radius < d.origin[a] - span || lo[a] - radius > d.origin[a] + (n[a] + kBrick) * d.h) return false;
        return true;
    };
    tree.for_each_leaf(near_grid, [&](const detail::PointTree::Node& leaf) { leaves.push_back(&leaf); });
    // The box of brick b's cell centres along axis a.
    const auto centres = [&](int a, int b, double& c0, double& c1) {
        c0 = d.origin[a] + (b * kBrick + 0.5) * d.h;
        c1 = d.origin[a] + (std::min(n[a], (b + 1) * kBrick) - 0.5) * d.h;
    };
    const std::ptrdiff_t nl = std::ptrdiff_t(leaves.size());
#pragma omp parallel for schedule(dynamic, 256)
    for (std::ptrdiff_t l = 0; l < nl; ++l) {
        const detail::PointTree::Node& leaf = *leaves[l];
        const Vec3 lo = tree.lo(leaf), hi = tree.hi(leaf);
        int b0[3], b1[3];
        for (int a = 0; a < 3; ++a) {
            b0[a] = std::max(0, int(std::floor((lo[a] - radius - d.origin[a]) / span)));
            b1[a] = std::min(nb[a] - 1, int(std::floor((hi[a] + radius - d.origin[a]) / span)));
        }
        for (int bk = b0[2]; bk <= b1[2]; ++bk)
            for (int bj = b0[1]; bj <= b1[1]; ++bj)
                for (int bi = b0[0]; bi <= b1[0]; ++bi) {
                    std::uint8_t& flag =
                        near[std::size_t(bi) + std::size_t(lv.bx) * (std::size_t(bj) + std::size_t(lv.by) * std::size_t(bk))];
                    std::uint8_t marked;
#pragma omp atomic read
                    marked = flag;
                    if (marked) continue;
                    const int b[3] = {bi, bj, bk};
                    // The gap of the leaf's box (below each point's: rounding is monotone).
                    double c0[3], c1[3], box_gap = 0;
                    for (int a = 0; a < 3; ++a) {
                        centres(a, b[a], c0[a], c1[a]);
                        const double g = std::max({c0[a] - hi[a], 0.0, lo[a] - c1[a]});
                        box_gap = a == 0 ? g * g : box_gap + g * g;
                    }
                    if (box_gap > rr) continue;
                    for (std::uint32_t k = leaf.begin; k < leaf.end; ++k) {
                        const Vec3 p = tree.point(k);
                        double g2[3];
                        for (int a = 0; a < 3; ++a) {
                            const double g = std::max({c0[a] - p[a], 0.0, p[a] - c1[a]});
                            g2[a] = g * g;
                        }
                        if ((g2[0] + g2[1]) + g2[2] <= rr) {
#pragma omp atomic write
                            flag = 1;
                            break;
                        }
                    }
                }
    }
    return near;
}

// Two doubles in one SIMD register (a GCC and Clang extension): GCC's auto-vectoriser
// does poorly on the loops that use it, which spell the vector code out instead.
typedef double Pair __attribute__((vector_size(16)));

Pair load_pair(const double* p) {
    Pair v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

// Candidate points as structure of arrays, so that the loops over them vectorise.
struct Candidates {
    std::vector<double> x, y, z, w;  // w: scratch, one value per point
    std::size_t n = 0;

    void clear_for(std::size_t most) {
        n = 0;
        if (x.size() < most) {
            x.resize(most);
            y.resize(most);
            z.resize(most);
            w.resize(most);
        }
    }
    // Appends src's points [m0, m1).
    void append(const Candidates& src, std::size_t m0, std::size_t m1) {
        if (x.size() < n + (m1 - m0)) {
            const std::size_t keep = n;
            clear_for(std::max(2 * x.size(), n + (m1 - m0)));
            n = keep;
        }
        const auto at = [](const std::vector<double>& v, std::size_t m) { return v.begin() + std::ptrdiff_t(m); };
        std::copy(at(src.x, m0), at(src.x, m1), x.begin() + std::ptrdiff_t(n));
        std::copy(at(src.y, m0), at(src.y, m1), y.begin() + std::ptrdiff_t(n));
        std::copy(at(src.z, m0), at(src.z, m1), z.begin() + std::ptrdiff_t(n));
        n += m1 - m0;
    }
};

// Half-open cell ranges per axis.
struct Cells {
    int lo[3], hi[3];
};

// A box of cell centres.
struct Box {
    double lo[3], hi[3];
};

// The leaves whose boxes come within sqrt(lim_sq) of `box`; returns how many points they hold.
std::size_t leaves_near(const detail::PointTree& tree, const Box& box, double lim_sq,
                        std::vector<const detail::PointTree::Node*>& leaves) {
    const Vec3 lo{box.lo[0], box.lo[1], box.lo[2]}, hi{box.hi[0], box.hi[1], box.hi[2]};
    leaves.clear();
    std::size_t total = 0;
    const auto gap_sq = [&](const detail::PointTree::Node& n) {
        const Vec3 a = tree.lo(n), b = tree.hi(n);
        double s = 0;
        for (int d = 0; d < 3; ++d) {
            const double g = std::max({a[d] - hi[d], 0.0, lo[d] - b[d]});
            s += g * g;
        }
        return s;
    };
    tree.for_each_leaf([&](const detail::PointTree::Node& n) { return gap_sq(n) <= lim_sq; },
                       [&](const detail::PointTree::Node& n) {
                           leaves.push_back(&n);
                           total += n.count();
                       });
    return total;
}

// Whether more than `most` points lie in the leaves within sqrt(lim_sq) of `box`: the
// count stops there, and a node whose box lies inside the box widened by the limit
// counts whole (a choice of method, not an answer: the count need not be exact).
bool more_near_than(const detail::PointTree& tree, const Box& box, double lim_sq, std::size_t most) {
    const double lim = std::sqrt(lim_sq);
    std::size_t total = 0;
    bool more = false;
    tree.for_each_leaf(
        [&](const detail::PointTree::Node& n) {
            if (more) return false;
            const Vec3 a = tree.lo(n), b = tree.hi(n);
            double s = 0;
            bool inside = true;
            for (int d = 0; d < 3; ++d) {
                const double g = std::max({a[d] - box.hi[d], 0.0, box.lo[d] - b[d]});
                s += g * g;
                inside = inside && a[d] >= box.lo[d] - lim && b[d] <= box.hi[d] + lim;
            }
            if (s > lim_sq) return false;
            if (!inside) return true;
            total += n.count();
            more = total > most;
            return false;
        },
        [&](const detail::PointTree::Node& n) {
            total += n.count();
            more = total > most;
        });
    return more;
}

// The points of the leaves within sqrt(lim_sq) of `box`.
void gather(const detail::PointTree& tree, const std::vector<const detail::PointTree::Node*>& leaves, const Box& box,
            double lim_sq, Candidates& out) {
    std::size_t total = 0;
    for (const auto* leaf : leaves) total += leaf->count();
    out.clear_for(total);
    double* x = out.x.data();
    double* y = out.y.data();
    double* z = out.z.data();
    double* w = out.w.data();
    std::size_t m = 0;
    for (const auto* leaf : leaves)
        for (std::uint32_t k = leaf->begin; k < leaf->end; ++k, ++m) {
            const Vec3 p = tree.point(k);
            x[m] = p[0];
            y[m] = p[1];
            z[m] = p[2];
        }
    // Keep those near enough, in place and branch-free (the outcome is a coin toss).
    for (m = 0; m < total; ++m) {
        const double gx = std::max(std::max(box.lo[0] - x[m], 0.0), x[m] - box.hi[0]);
        const double gy = std::max(std::max(box.lo[1] - y[m], 0.0), y[m] - box.hi[1]);
        const double gz = std::max(std::max(box.lo[2] - z[m], 0.0), z[m] - box.hi[2]);
        w[m] = gx * gx + gy * gy + gz * gz;
    }
    std::size_t kept = 0;
    for (m = 0; m < total; ++m) {
        x[kept] = x[m];
        y[kept] = y[m];
        z[kept] = z[m];
        kept += w[m] <= lim_sq;
    }
    out.n = kept;
}

// Marks (in.w <= 0) the points of `in` that can be the nearest point of some spot in the
// box: all but those whose bisector with s, the point nearest the box centre c, leaves
// the whole box on s's side. With u = p - c, v = s - c and the box c +- e, the least of
// |q - p|^2 - |q - s|^2 over the box is |u|^2 - |v|^2 - 2 sum e |s - p|; p goes only
// where that is clearly positive, far beyond rounding, so no nearest point is lost.
// `in` must not be empty.
void mark(Candidates& in, const Box& box) {
    const std::size_t n = in.n;
    double c[3], e2[3];
    for (int a = 0; a < 3; ++a) {
        c[a] = 0.5 * (box.lo[a] + box.hi[a]);
        // 2e, widened so that the box around the rounded centre surely holds every cell centre.
        e2[a] = (box.hi[a] - box.lo[a]) * (1 + 1e-9) + 0x1p-39 * (std::abs(box.lo[a]) + std::abs(box.hi[a]));
    }
    const double* x = in.x.data();
    const double* y = in.y.data();
    const double* z = in.z.data();
    double* w = in.w.data();
    // w = |u|^2, two at a time, and its least value.
    const double inf = std::numeric_limits<double>::infinity();
    Pair least = {inf, inf};
    std::size_t m = 0;
    for (; m + 2 <= n; m += 2) {
        const Pair ux = load_pair(x + m) - c[0], uy = load_pair(y + m) - c[1], uz = load_pair(z + m) - c[2];
        const Pair uu = ux * ux + uy * uy + uz * uz;
        std::memcpy(w + m, &uu, sizeof uu);
        least = uu < least ? uu : least;
    }
    double vv = std::min(least[0], least[1]);
    for (; m < n; ++m) {
        const double ux = x[m] - c[0], uy = y[m] - c[1], uz = z[m] - c[2];
        w[m] = ux * ux + uy * uy + uz * uz;
        vv = std::min(vv, w[m]);
    }
    std::size_t s = 0;
    while (s + 1 < n && w[s] != vv) ++s;
    // The slack 3e-12 (|u|^2 + |v|^2 + (sum e)^2) bounds the rounding many times over.
    const double sx = x[s], sy = y[s], sz = z[s];
    const double es = 0.5 * (e2[0] + e2[1] + e2[2]);
    const double keep_below = vv * (1 + 3e-12) + 3e-12 * es * es;
    for (m = 0; m < n; ++m) {
        const double spread = e2[0] * std::abs(x[m] - sx) + e2[1] * std::abs(y[m] - sy) + e2[2] * std::abs(z[m] - sz);
        w[m] = (w[m] * (1 - 3e-12) - spread) - keep_below;
    }
}

// The marked points of `in`, copied (branch-free: whether one stays is a coin toss).
void keep_marked(const Candidates& in, Candidates& out) {
    out.clear_for(in.n);
    std::size_t k = 0;
    for (std::size_t m = 0; m < in.n; ++m) {
        out.x[k] = in.x[m];
        out.y[k] = in.y[m];
        out.z[k] = in.z[m];
        k += in.w[m] <= 0;
    }
    out.n = k;
}

// The positions of the marked points of `in`; returns how many.
std::size_t marked(const Candidates& in, std::vector<std::uint32_t>& at) {
    if (at.size() < in.n) at.resize(in.n);
    std::size_t k = 0;
    for (std::size_t m = 0; m < in.n; ++m) {
        at[k] = std::uint32_t(m);
        k += in.w[m] <= 0;
    }
    return k;
}

constexpr int kBlock = 4;  // cells per axis of the blocks that are brute-forced
constexpr int kBlockCells = kBlock * kBlock * kBlock;

// Squared distances from the cells of a block (at most kBlock per axis) to their nearest
// candidate, pts at positions at[0, count); a block cut by the grid edge repeats its last
// cells. The expression is the one the kd-tree query evaluated, (x^2 + y^2) + z^2 with
// x = q - p per axis, so the minimum is bit for bit the same; but as the cells form a
// tensor grid, the squares are taken once per axis value and each cell only adds.
void block_distances(const Candidates& pts, const std::uint32_t* at, std::size_t count,
                     const std::vector<double> (&centre)[3], const Cells& c, double (&out)[kBlockCells]) {
    static_assert(kBlock == 4, "a row of the block is two pairs");
    double q[3][kBlock];
    for (int a = 0; a < 3; ++a)
        for (int i = 0; i < kBlock; ++i) q[a][i] = centre[a][std::size_t(std::min(c.lo[a] + i, c.hi[a] - 1))];
    const Pair x01 = {q[0][0], q[0][1]}, x23 = {q[0][2], q[0][3]};
    const double inf = std::numeric_limits<double>::infinity();
    Pair best[kBlockCells / 2];
    for (Pair& b : best) b = Pair{inf, inf};
    for (std::size_t t = 0; t < count; ++t) {
        const std::size_t m = at[t];
        const double px = pts.x[m], py = pts.y[m], pz = pts.z[m];
        const Pair a01 = x01 - px, a23 = x23 - px;
        const Pair xx01 = a01 * a01, xx23 = a23 * a23;
        double yy[kBlock], zz[kBlock];
        for (int i = 0; i < kBlock; ++i) {
            const double y = q[1][i] - py, z = q[2][i] - pz;
            yy[i] = y * y;
            zz[i] = z * z;
        }
        for (int j = 0; j < kBlock; ++j) {
            const Pair xy01 = xx01 + yy[j], xy23 = xx23 + yy[j];
            for (int k = 0; k < kBlock; ++k) {
                Pair* row = best + 2 * (j + kBlock * k);
                const Pair d01 = xy01 + zz[k], d23 = xy23 + zz[k];
                row[0] = d01 < row[0] ? d01 : row[0];
                row[1] = d23 < row[1] ? d23 : row[1];
            }
        }
    }
    for (int b = 0; b < kBlockCells / 2; ++b) {
        out[2 * b] = best[b][0];
        out[2 * b + 1] = best[b][1];
    }
}

double dist_sq(const Vec3& a, const Vec3& b) {
    const double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
    return x * x + y * y + z * z;
}

// The distances (or `far`) of the cells of brick r, from its candidates in_brick, block by
// block: each block's own candidates, then all its cells against them.
template <class Real, class BoxOf>
void brick_by_blocks(Candidates& in_brick, const std::vector<double> (&centre)[3], const BoxOf& box_of,
                     const CellRange& r, double rr, double L, Real far, std::vector<std::uint32_t>& in_block,
                     Real* values) {
    for (int k0 = r.k0; k0 < r.k1; k0 += kBlock)
        for (int j0 = r.j0; j0 < r.j1; j0 += kBlock)
            for (int i0 = r.i0; i0 < r.i1; i0 += kBlock) {
                const Cells blk{{i0, j0, k0},
                                {std::min(r.i1, i0 + kBlock), std::min(r.j1, j0 + kBlock), std::min(r.k1, k0 + kBlock)}};
                mark(in_brick, box_of(blk));
                const std::size_t count = marked(in_brick, in_block);
                double best[kBlockCells];
                block_distances(in_brick, in_block.data(), count, centre, blk, best);
                for (int k = blk.lo[2]; k < blk.hi[2]; ++k)
                    for (int j = blk.lo[1]; j < blk.hi[1]; ++j)
                        for (int i = blk.lo[0]; i < blk.hi[0]; ++i) {
                            const double dd = best[(i - i0) + kBlock * ((j - j0) + kBlock * (k - k0))];
                            values[(i - r.i0) + kBrick * ((j - r.j0) + kBrick * (k - r.k0))] =
                                dd < rr ? Real(std::sqrt(dd) / L) : far;
                        }
            }
}

// Where the points are far denser than the cells, the candidate lists grow long and the
// tree's packets (brick_by_tree) are cheaper: in bricks with more points around them
// than this many per cell. Single-threaded band distance at 256 cells, noisy sphere of
// 24.6 M points: 3.5 s at 16 (and at 8), 3.9 s at 32, 5.5 s at 64; alike at 1.5 M
// points and on the bunny and the dragon. At 512 cells (both threads, whole stage) the
// 24.6 M sphere takes 4.0 s at 8, 3.8-3.9 s at 4, 4.5 s at 16, 6.8 s at 64; the 1.5 M
// one 0.6 s at 4 to 16, 1.0 s at 2.
constexpr std::size_t kDenseRatio = 8;

// The brick's cells by 2x2x2 packets, one walk of the tree per packet (the eight lanes
// of PointTree::nearest_lanes: the same expression, so the same distances). The nearest
// points of the packets before it, along each axis, start each lane's search: a
// neighbour's nearest point is nearly always this cell's, or close, so the walk prunes
// almost everything from the start.
template <class Real>
void brick_by_tree(const detail::PointTree& tree, const std::vector<double> (&centre)[3], const CellRange& r,
                   double rr, double L, Real far, Real* values) {
    constexpr int P = 2, kPackets = kBrick / P, kLanes = detail::PointTree::kLanes;
    static_assert(P * P * P == kLanes, "a packet is one lane per cell");
    constexpr std::uint32_t npos = detail::PointTree::npos;
    std::uint32_t found[kPackets][kPackets][kPackets][kLanes];
    const int lo[3] = {r.i0, r.j0, r.k0}, hi[3] = {r.i1, r.j1, r.k1};
    for (int c = 0; c < kPackets && lo[2] + P * c < hi[2]; ++c)
        for (int b = 0; b < kPackets && lo[1] + P * b < hi[1]; ++b)
            for (int a = 0; a < kPackets && lo[0] + P * a < hi[0]; ++a) {
                // The lanes' cells; those beyond the grid repeat its last cell.
                double q[3][kLanes];
                const int at[3] = {a, b, c};
                for (int lane = 0; lane < kLanes; ++lane)
                    for (int x = 0; x < 3; ++x) {
                        const int cell = std::min(lo[x] + P * at[x] + ((lane >> x) & 1), hi[x] - 1);
                        q[x][lane] = centre[x][std::size_t(cell)];
                    }
                double best[kLanes];
                std::uint32_t index[kLanes];
                std::fill(best, best + kLanes, rr);
                std::fill(index, index + kLanes, npos);
                const auto start_from = [&](const std::uint32_t (&before)[kLanes]) {
                    for (std::uint32_t p : before) {
                        if (p == npos) continue;
                        const Vec3 pt = tree.point(p);
                        for (int lane = 0; lane < kLanes; ++lane) {
                            const double dd = dist_sq({q[0][lane], q[1][lane], q[2][lane]}, pt);
                            if (dd < best[lane]) best[lane] = dd, index[lane] = p;
                        }
                    }
                };
                if (a > 0) start_from(found[c][b][a - 1]);
                if (b > 0) start_from(found[c][b - 1][a]);
                if (c > 0) start_from(found[c - 1][b][a]);
                tree.nearest_lanes(q, best, index);
                std::copy(index, index + kLanes, found[c][b][a]);
                for (int lane = 0; lane < kLanes; ++lane) {
                    const int i = P * a + (lane & 1), j = P * b + ((lane >> 1) & 1), k = P * c + (lane >> 2);
                    if (i < kBrick && j < kBrick && k < kBrick)
                        values[i + kBrick * (j + kBrick * k)] = index[lane] != npos ? Real(std::sqrt(best[lane]) / L) : far;
                }
            }
}

}  // namespace


// Per brick: the points within the radius of it, pruned to those that can be nearest to
// some cell of it, then again per 4^3 block, whose cells are brute-forced against that
// short list (on the bunny at 256 cells, a tenth of the CPU time of one kd-tree query
// per cell).
template <class Real>
BandDistance<Real> band_distance(const detail::PointTree& tree, const Domain& d,
                                 const Band& band, const std::function<void(std::size_t)>& before_values) {
    const double L = d.length_scale();
    const double radius = (band.offset + band.cut) * L * (1 + 1e-9);  // world units
    const double rr = radius * radius;  // cells whose nearest point is not closer are far
    const Real far = Real(band.offset + 2 * band.cut);

    const BrickTiling lv = BrickTiling::of(d.nx, d.ny, d.nz);
    std::vector<std::uint8_t> near = bricks_near_points(tree, d, lv, radius);
    std::vector<std::uint32_t> todo;
    for (std::uint32_t b = 0; b < near.size(); ++b)
        if (near[b]) todo.push_back(b);

    if (before_values) before_values(todo.size());
    BandDistance<Real> out;
    out.near_bricks = todo;
    out.far = far;
    out.near_values.resize(todo.size() * std::size_t(kBrick * kBrick * kBrick));  // each brick's own thread writes it
    if (todo.empty()) return out;

    // Cell centres per axis, as Domain::cell_center computes them.
    std::vector<double> centre[3];
    const int n[3] = {d.nx, d.ny, d.nz};
    for (int a = 0; a < 3; ++a)
        for (int i = 0; i < n[a]; ++i) centre[a].push_back(d.origin[a] + (i + 0.5) * d.h);
    const auto box_of = [&](const Cells& c) {
        return Box{{centre[0][std::size_t(c.lo[0])], centre[1][std::size_t(c.lo[1])], centre[2][std::size_t(c.lo[2])]},
                   {centre[0][std::size_t(c.hi[0] - 1)], centre[1][std::size_t(c.hi[1] - 1)],
                    centre[2][std::size_t(c.hi[2] - 1)]}};
    };

    const std::size_t dense = kDenseRatio * std::size_t(kBrick * kBrick * kBrick);
    // The gathering radius, with slack for rounding far below any spacing that matters.
    double scale = 0;
    for (int a = 0; a < 3; ++a) scale = std::max({scale, std::abs(centre[a].front()), std::abs(centre[a].back())});
    const double lim = radius + 1e-6 * d.h + 0x1p-40 * scale;

    std::size_t queried = 0;
#pragma omp parallel
    {
        Candidates gathered, in_brick;
        std::vector<std::uint32_t> in_block;
        std::vector<const detail::PointTree::Node*> leaves;
        Real values[kBrick * kBrick * kBrick];  // the brick's, x fastest, kBrick per axis
#pragma omp for schedule(dynamic, 4) reduction(+ : queried)
        for (std::size_t t = 0; t < todo.size(); ++t) {
            const CellRange r = lv.range(todo[t]);
            const Cells brick{{r.i0, r.j0, r.k0}, {r.i1, r.j1, r.k1}};
            queried += std::size_t(r.i1 - r.i0) * std::size_t(r.j1 - r.j0) * std::size_t(r.k1 - r.k0);
            const Box bb = box_of(brick);
            if (more_near_than(tree, bb, lim * lim, dense)) {
                brick_by_tree(tree, centre, r, rr, L, far, values);
            } else {
                leaves_near(tree, bb, lim * lim, leaves);
                gather(tree, leaves, bb, lim * lim, gathered);
                if (gathered.n == 0) {  // nothing within the radius: all far
                    std::fill(values, values + kBrick * kBrick * kBrick, far);
                } else {
                    mark(gathered, bb);
                    keep_marked(gathered, in_brick);
                    brick_by_blocks(in_brick, centre, box_of, r, rr, L, far, in_block, values);
                }
            }
            Real* const to = out.near_values.data() + t * std::size_t(kBrick * kBrick * kBrick);
            if (r.i1 - r.i0 < kBrick || r.j1 - r.j0 < kBrick || r.k1 - r.k0 < kBrick)
                std::fill(to, to + kBrick * kBrick * kBrick, far);  // its cells beyond the grid
            for (int k = r.k0; k < r.k1; ++k)
                for (int j = r.j0; j < r.j1; ++j) {
                    const std::size_t row = std::size_t(kBrick) * std::size_t((j - r.j0) + kBrick * (k - r.k0));
                    std::copy_n(values + row, r.i1 - r.i0, to + row);
                }
        }
    }
    out.queried_cells = queried;
    return out;
}

template <class Real>
void classify_band(BandDistance<Real>& bd, const Domain& d, const Band& band) {
    const BrickTiling lv = BrickTiling::of(d.nx, d.ny, d.nz);
    const Real l = Real(band.offset), cut = Real(band.cut);
    bd.brick_mask.assign(lv.brick_count(), 0);
    bd.inside_bricks.assign(lv.brick_count(), 0);
    std::size_t active = 0;
#pragma omp parallel for schedule(static) reduction(+ : active)
    for (std::size_t t = 0; t < bd.near_bricks.size(); ++t) {
        const CellRange r = lv.range(bd.near_bricks[t]);
        const Real* v = bd.brick_values(t);
        std::size_t here = 0;
        for (int k = r.k0; k < r.k1; ++k)
            for (int j = r.j0; j < r.j1; ++j)
                for (int i = r.i0; i < r.i1; ++i)
                    here += std::abs(l - v[(i - r.i0) + kBrick * ((j - r.j0) + kBrick * (k - r.k0))]) <= cut;
        if (here) bd.brick_mask[bd.near_bricks[t]] = 1;
        // Without band cells a brick is all +1 or all -1 (see band_of): its first cell says which.
        else bd.inside_bricks[bd.near_bricks[t]] = l - v[0] > 0;
        active += here;
    }
    bd.active_cells = active;
}

template <class Real>
std::vector<Real> BandDistance<Real>::dense(const Domain& d) const {
    const BrickTiling lv = BrickTiling::of(d.nx, d.ny, d.nz);
    std::vector<Real> out(d.cells(), far);
    for (std::size_t t = 0; t < near_bricks.size(); ++t) {
        const CellRange r = lv.range(near_bricks[t]);
        const Real* v = brick_values(t);
        for (int k = r.k0; k < r.k1; ++k)
            for (int j = r.j0; j < r.j1; ++j)
                for (int i = r.i0; i < r.i1; ++i)
                    out[d.index(i, j, k)] = v[(i - r.i0) + kBrick * ((j - r.j0) + kBrick * (k - r.k0))];
    }
    return out;
}

template struct BandDistance<double>;
template struct BandDistance<float>;
template BandDistance<double> band_distance<double>(const detail::PointTree&, const Domain&, const Band&,
                                                   const std::function<void(std::size_t)>&);
template BandDistance<float> band_distance<float>(const detail::PointTree&, const Domain&, const Band&,
                                                 const std::function<void(std::size_t)>&);
template void classify_band<double>(BandDistance<double>&, const Domain&, const Band&);
template void classify_band<float>(BandDistance<float>&, const Domain&, const Band&);

}  // namespace snvr
