// keep_points_deep: moves a shell's vertices outward, smoothly, until no point lies
// nearer than the promised depth to the surface.
//
// Why the mesh needs it although the field keeps the depth: the tube holds phi above
// the profile of the surface d = depth at every grid node, but between nodes the
// interpolant of a ball two or three cells in radius sags inward, and flat triangles
// across it cut deeper still (a point on a scan's open rim ended 0.72 l deep on the
// bunny at l = 2.5 voxels with the tube at 0.8 l). Where that happens the patch of
// surface is lifted along its normals by a displacement that is spread over two rings
// of neighbours, so the lifted patch has no kink at its edge.
//
// Speed (the same vertices, bit for bit, as when every vertex and every point asked a
// point index): nearly all of a shell lies about the offset from the points, a little
// beyond the depth, so the searches start from the points (on a scan, a tenth as many
// as the vertices) and rule out whole cells of mesh with bounds (a box and a slab
// around each cell's piece of surface) before any exact test, which is the test the
// index made. Only the few vertices the lift reaches are moved and checked for turning
// over; a point's list of near triangles is gathered only when a repair needs it; ties
// between equally near triangles are settled in the index's order, as before.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "geometry/point_tree.hpp"
#include "snvr/error.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/mesh.hpp"
#include "mesh/guard_search.hpp"
#include "mesh/triangle_grid.hpp"  // point_triangle_dist_sq
#include "geometry/vec3_math.hpp"
#include "mesh/vertex_lists.hpp"
#include "parallel_sizes.hpp"
#include "threads_here.hpp"

namespace snvr {
namespace {

using detail::PointTree;
using detail::VertexLists;
using detail::GuardElsewhere;
using detail::GuardFound;
using detail::PointTriangle;
using detail::GuardCounted;

// Vertices are aimed this far (in voxels) beyond the depth: a triangle about a voxel
// across on a ball of radius 2 voxels sags about 0.1 voxel between its corners.
constexpr double kMarginVoxels = 0.1;
// Rounds of (largest of the ring, then mean of the ring) that spread each lift.
constexpr int kSpreadRounds = 2;
// Repair rounds for the points still too shallow after the first lift; each lifts the
// nearest triangle of each such point by what it lacks.
constexpr int kRepairRounds = 8;
constexpr int kUntangleRounds = 16;
constexpr double kInf = std::numeric_limits<double>::infinity();
// Loops whose items cost a few nanoseconds run threaded only above this many: waking
// threads for less costs more than it saves, the more so on a busy machine.

// Squared distance as the point index measures it (the sum of the squared differences,
// query minus point, in axis order), so that a test here agrees with the index's.
double index_dist_sq(const Vec3& q, const Vec3& p) {
    double s = 0;
    for (int d = 0; d < 3; ++d) {
        const double x = q[d] - p[d];
        s += x * x;
    }
    return s;
}

double largest_coordinate(const Vec3& c) { return std::max({std::fabs(c[0]), std::fabs(c[1]), std::fabs(c[2])}); }

// r widened by a few rounding errors of coordinates near c: what a range built from
// rounded sums must add to hold everything an exact test within r could accept.
double slack(double r, const Vec3& c) { return r + 8 * DBL_EPSILON * (r + largest_coordinate(c)); }

// Squared distance from q to the box [a, b]. Rounding is monotone, so for a point p in
// the box it is never above index_dist_sq(q, p).
double box_dist_sq(const Vec3& q, const Vec3& a, const Vec3& b) {
    double s = 0;
    for (int d = 0; d < 3; ++d) {
        const double x = std::max({0.0, a[d] - q[d], q[d] - b[d]});
        s += x * x;
    }
    return s;
}

// Items filed by cells of a uniform grid over a box, as compressed rows: slot s of the
// rows holds item order[s]; the non-empty cells are numbered (rank) so that callers can
// keep something per cell. Cells are at least `cell` wide, coarser where that would make
// more than about `cap` cells. Few items in many cells (a repair's moved triangles: the
// grid as fine as the whole mesh's) are filed by their used cells alone, found by a hash:
// a row for each of the grid's 36 M cells made the repairs' start take 1.65 s, 0.31 s so
// (the 12.5 M-point city block at 1536 cells: 17.9 M triangles).
class CellGrid {
public:
    std::vector<std::uint32_t> order;

    CellGrid(const Vec3& lo, const Vec3& hi, double cell, std::size_t cap) : lo_(lo) {
        Vec3 top = hi;
        for (int d = 0; d < 3; ++d)
            if (!(lo_[d] <= top[d])) lo_[d] = top[d] = 0;  // nothing finite
        size_ = cell;
        for (;;) {
            std::size_t cells = 1;
            for (int d = 0; d < 3; ++d) {
                const double span = (top[d] - lo_[d]) / size_;
                n_[d] = span < 1 << 20 ? int(span) + 1 : std::isfinite(span) ? 1 << 20 : 1;
                cells *= std::size_t(n_[d]);
            }
            if (cells <= cap) break;
            size_ *= 1.25;
        }
    }
    // The cell holding x (clamped to the grid).
    std::uint32_t cell_of(const Vec3& x) const {
        return std::uint32_t(std::size_t(coord(x[0], 0)) +
                             std::size_t(n_[0]) * (coord(x[1], 1) + std::size_t(n_[1]) * coord(x[2], 2)));
    }
    // Files items 0 .. cells.size() - 1, item i in cell cells[i].
    void file(const std::vector<std::uint32_t>& cells) {
        const std::size_t all = std::size_t(n_[0]) * n_[1] * n_[2];
        if (cells.size() < all / kSparseCellsPerItem) return file_sparse(cells);
        // Counted at c + 2 and summed, start_[c + 1] is where cell c begins; each item
        // placed there moves it on, so that it ends where c + 1 begins. Ranks: the used
        // cells before a cell's word of 64, and those in the word before it. (A copy of
        // the starts and a rank a cell took 0.9 s at 17.9 M triangles, 0.3 s so.)
        start_.assign(all + 2, 0);
        for (std::uint32_t c : cells) ++start_[c + 2];
        used_bits_.assign((all + 63) / 64, 0);
        word_rank_.resize(used_bits_.size());
        for (std::size_t c = 0; c < all; ++c) {
            if (c % 64 == 0) word_rank_[c / 64] = std::uint32_t(used_);
            if (start_[c + 2]) {
                used_bits_[c / 64] |= std::uint64_t(1) << (c % 64);
                ++used_;
            }
            start_[c + 2] += start_[c + 1];
        }
        order.resize(cells.size());
        for (std::size_t i = 0; i < cells.size(); ++i) order[start_[cells[i] + 1]++] = std::uint32_t(i);
    }
    std::uint32_t rank(std::uint32_t cell) const {
        if (sparse_) return find(cell);
        const std::uint64_t before = used_bits_[cell / 64] & ((std::uint64_t(1) << (cell % 64)) - 1);
        return word_rank_[cell / 64] + std::uint32_t(__builtin_popcountll(before));
    }

    std::size_t used_cells() const { return used_; }
    // Calls f(rank, begin, end) (the slots) for each non-empty cell holding keys in [a, b].
    template <class F>
    void for_cells(const Vec3& a, const Vec3& b, F f) const {
        const int x0 = coord(a[0], 0), x1 = coord(b[0], 0), y0 = coord(a[1], 1), y1 = coord(b[1], 1);
        const int z0 = coord(a[2], 2), z1 = coord(b[2], 2);
        for (int z = z0; z <= z1; ++z)
            for (int y = y0; y <= y1; ++y) {
                const std::size_t row = std::size_t(n_[0]) * (y + std::size_t(n_[1]) * z);
                if (sparse_) {
                    for (int x = x0; x <= x1; ++x)
                        if (const std::uint32_t r = find(std::uint32_t(row + std::size_t(x))); r != kNone)
                            f(r, start_[r], start_[r + 1]);
                    continue;
                }
                for (int x = x0; x <= x1; ++x)
                    if (start_[row + x] != start_[row + x + 1])
                        f(rank(std::uint32_t(row + std::size_t(x))), start_[row + x], start_[row + x + 1]);
            }
    }
    // Calls f(rank, begin, end) for every non-empty cell, in parallel if asked to.
    template <class F>
    void for_each_cell(F f, [[maybe_unused]] bool parallel = true) const {
        if (sparse_) {
            const std::ptrdiff_t used = std::ptrdiff_t(used_);
#pragma omp parallel for schedule(dynamic, 256) if (parallel && order.size() > std::size_t(detail::kParallelCheapItems))
            for (std::ptrdiff_t r = 0; r < used; ++r) f(std::uint32_t(r), start_[r], start_[r + 1]);
            return;
        }
        const std::ptrdiff_t cells = std::ptrdiff_t(start_.size() - 2);
#pragma omp parallel for schedule(dynamic, 4096) if (parallel && order.size() > std::size_t(detail::kParallelCheapItems))
        for (std::ptrdiff_t c = 0; c < cells; ++c)
            if (start_[c] != start_[c + 1]) f(rank(std::uint32_t(c)), start_[c], start_[c + 1]);
    }

private:
    static constexpr std::size_t kSparseCellsPerItem = 16;
    static constexpr std::uint32_t kNone = ~std::uint32_t(0);

    // As file, by the used cells: their ids in order (a rank is a place among them, as
    // in the rows) with their slots, and a table of open addresses from id to rank.
    void file_sparse(const std::vector<std::uint32_t>& cells) {
        sparse_ = true;
        std::vector<std::uint64_t> by_cell(cells.size());
        for (std::size_t i = 0; i < cells.size(); ++i) by_cell[i] = std::uint64_t(cells[i]) << 32 | i;
        std::sort(by_cell.begin(), by_cell.end());  // within a cell by item, as the rows have them
        order.resize(cells.size());
        for (std::size_t s = 0; s < by_cell.size(); ++s) {
            const auto cell = std::uint32_t(by_cell[s] >> 32);
            if (used_id_.empty() || used_id_.back() != cell) {
                used_id_.push_back(cell);
                start_.push_back(std::uint32_t(s));  // rank r's slots: start_[r] .. start_[r + 1]
            }
            order[s] = std::uint32_t(by_cell[s]);
        }
        start_.push_back(std::uint32_t(by_cell.size()));
        used_ = used_id_.size();
        std::size_t size = 16;
        while (size < 2 * used_) size *= 2;
        table_.assign(size, kNone);
        for (std::size_t r = 0; r < used_; ++r) {
            std::size_t at = slot_of(used_id_[r]);
            while (table_[at] != kNone) at = (at + 1) & (table_.size() - 1);
            table_[at] = std::uint32_t(r);
        }
    }
    std::size_t slot_of(std::uint32_t cell) const {
        return std::size_t((std::uint64_t(cell) * 0x9E3779B97F4A7C15ull) >> 32) & (table_.size() - 1);
    }
    // The rank of a used cell; kNone for one without items.
    std::uint32_t find(std::uint32_t cell) const {
        for (std::size_t at = slot_of(cell);; at = (at + 1) & (table_.size() - 1)) {
            const std::uint32_t r = table_[at];
            if (r == kNone || used_id_[r] == cell) return r;
        }
    }

    // Cell coordinate of x on axis d, clamped to the grid (NaN to 0).
    int coord(double x, int d) const {
        const double t = (x - lo_[d]) / size_;
        return t >= 0 ? (t < n_[d] ? int(t) : n_[d] - 1) : 0;
    }

    Vec3 lo_;
    double size_ = 1;
    int n_[3] = {1, 1, 1};
    std::size_t used_ = 0;
    std::vector<std::uint32_t> start_;  // rows: by cell; by used cells: by rank
    std::vector<std::uint64_t> used_bits_;  // rows: a bit a used cell, 64 cells a word
    std::vector<std::uint32_t> word_rank_;  // rows: the used cells before each word
    bool sparse_ = false;
    std::vector<std::uint32_t> used_id_, table_;  // by used cells only
};

// What a cell's items can come near: their box, and a slab along the cell's mean normal
// (a piece of smooth surface is thin along its normal, so the slab rules out the cells
// that face a point from beyond the radius, where a box would not).
struct Bound {
    Vec3 lo{kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf};
    Vec3 n{0, 0, 0};
    double n_lo = kInf, n_hi = -kInf;

    void add_to_box(const Vec3& x) {
        for (int d = 0; d < 3; ++d) {
            lo[d] = std::min(lo[d], x[d]);
            hi[d] = std::max(hi[d], x[d]);
        }
    }
    // Makes the summed normal n a unit one (no slab if it has no direction).
    void normalize() {
        const double len = norm(n);
        if (len > 0 && std::isfinite(len))
            for (double& c : n) c /= len;
        else
            n = {0, 0, 0};
    }
    void add_to_slab(const Vec3& x) {
        const double s = dot(n, x);
        n_lo = std::min(n_lo, s);
        n_hi = std::max(n_hi, s);
    }
    // False only when nothing within r of q can be in the cell: r_sq and slab_r hold a
    // margin over r^2 and r for rounding (the box distance of a point never exceeds
    // index_dist_sq; a triangle's distance and the slab's projections err by about
    // 1e-15 relative and a few ulps of the coordinates, far below the margins).
    bool may_reach(const Vec3& q, double r_sq, double slab_r) const {
        if (!(box_dist_sq(q, lo, hi) < r_sq)) return false;
        if (n[0] == 0 && n[1] == 0 && n[2] == 0) return true;
        const double s = dot(n, q);
        return !(s < n_lo - slab_r || s > n_hi + slab_r);
    }
};

// A cell's Bound::may_reach widened into the point tree's own float coordinates (about
// its origin): what it rejects, may_reach rejects too, so a point's exact test runs only
// when this lets it through. Bounds are rounded outwards, and the room covers the float
// projection's rounding (a few 2^-24 of the coordinates) and the double one's many times.
struct FloatReach {
    float lo[3], hi[3], n[3], n_lo, n_hi;
    bool slab;
    bool may_reach(const Vec3f& q) const {
        for (int d = 0; d < 3; ++d)
            if (!(q[d] >= lo[d] && q[d] <= hi[d])) return false;
        if (!slab) return true;
        const float s = n[0] * q[0] + n[1] * q[1] + n[2] * q[2];
        return s >= n_lo && s <= n_hi;
    }
};

class FloatFrame {
public:
    FloatFrame(const detail::PointTree& tree, double r, double slab_extent) : origin_(tree.origin) {
        double m = 0;  // the largest coordinate of a point about the origin
        if (!tree.nodes.empty())
            for (int d = 0; d < 3; ++d)
                m = std::max({m, std::fabs(double(tree.nodes[0].lo[d])), std::fabs(double(tree.nodes[0].hi[d]))});
        const double far = largest_coordinate(origin_);
        room_ = 1e-5 * (m + r + slab_extent) + 1e-9 * far;
        box_r_ = r * (1 + 1e-6) + room_;
        slab_r_ = r * (1 + 1e-6) + 1e-6 * slab_extent + room_;
    }
    FloatReach reach(const Bound& cb) const {
        FloatReach f{};
        for (int d = 0; d < 3; ++d) {
            f.lo[d] = down(cb.lo[d] - origin_[d] - box_r_);
            f.hi[d] = up(cb.hi[d] - origin_[d] + box_r_);
            f.n[d] = float(cb.n[d]);
        }
        f.slab = !(cb.n[0] == 0 && cb.n[1] == 0 && cb.n[2] == 0);
        if (f.slab) {
            const double at = dot(cb.n, origin_);
            f.n_lo = down(cb.n_lo - at - slab_r_);
            f.n_hi = up(cb.n_hi - at + slab_r_);
        }
        // A cell beyond the floats' range lets everything through.
        if (!(std::isfinite(f.lo[0]) && std::isfinite(f.lo[1]) && std::isfinite(f.lo[2]) && std::isfinite(f.hi[0]) &&
              std::isfinite(f.hi[1]) && std::isfinite(f.hi[2]) && (!f.slab || (std::isfinite(f.n_lo) && std::isfinite(f.n_hi))))) {
            for (int d = 0; d < 3; ++d) f.lo[d] = -std::numeric_limits<float>::infinity(), f.hi[d] = -f.lo[d];
            f.slab = false;
        }
        return f;
    }

private:
    static float down(double v) {
        const float f = float(v);
        return double(f) > v ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
    }
    static float up(double v) {
        const float f = float(v);
        return double(f) < v ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
    }

    Vec3 origin_;
    double room_ = 0, box_r_ = 0, slab_r_ = 0;
};

bool inside(const Vec3& q, const Vec3& a, const Vec3& b) {
    return q[0] >= a[0] && q[0] <= b[0] && q[1] >= a[1] && q[1] <= b[1] && q[2] >= a[2] && q[2] <= b[2];
}
bool overlap(const Bound& c, const Vec3& a, const Vec3& b) {
    return c.lo[0] <= b[0] && c.hi[0] >= a[0] && c.lo[1] <= b[1] && c.hi[1] >= a[1] && c.lo[2] <= b[2] &&
           c.hi[2] >= a[2];
}

// The radius a slab test uses for an exact test within r near q, over items of size up
// to `size`: relative 1e-9 above r, plus rounding of the coordinates.
double slab_radius(double r, double size, const Vec3& q) {
    return r + 1e-9 * (r + size) + 64 * DBL_EPSILON * largest_coordinate(q);
}


// The vertices each vertex's ring reads, and the vertices whose rings read it: the
// corners of its fan. Marks them in `in` and appends the new ones to `set`.
void grow(const Mesh& mesh, const VertexLists& fans, std::vector<std::uint32_t>& set, std::vector<std::uint8_t>& in) {
    const std::size_t n = set.size();
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t f = fans.start[set[i]]; f < fans.start[set[i] + 1]; ++f)
            for (std::uint32_t c : mesh.triangles[fans.items[f]])
                if (!in[c]) in[c] = 1, set.push_back(c);
}

// Widens each lift to the vertex's ring, then averages it over the ring: a lift on one
// vertex becomes a smooth bump over two rings. Each step reaches one ring further, so it
// is computed where it can be non-zero, `region` (grown from the lifted vertices); the
// rest stays +0, as the sums and maxima of zeros there would be. Returns the region.
std::vector<std::uint32_t> spread(const Mesh& mesh, const VertexLists& rings, const VertexLists& fans,
                                  std::vector<double>& lift) {
    std::vector<std::uint32_t> region;
    std::vector<std::uint8_t> in(lift.size(), 0);
    for (std::size_t v = 0; v < lift.size(); ++v)
        if (lift[v] != 0 || std::isnan(lift[v])) in[v] = 1, region.push_back(std::uint32_t(v));
    std::vector<double> wide(lift.size(), 0.0);
    const auto step = [&](std::vector<double>& out, const std::vector<double>& in_values, bool mean) {
        grow(mesh, fans, region, in);
        std::sort(region.begin(), region.end());
        const std::ptrdiff_t n = std::ptrdiff_t(region.size());
#pragma omp parallel for schedule(static) if (n > detail::kParallelCheapItems)
        for (std::ptrdiff_t i = 0; i < n; ++i) {
            const std::uint32_t v = region[i];
            double m = in_values[v];
            for (std::size_t r = rings.start[v]; r < rings.start[v + 1]; ++r)
                m = mean ? m + in_values[rings.items[r]] : std::max(m, in_values[rings.items[r]]);
            out[v] = mean ? m / double(1 + rings.start[v + 1] - rings.start[v]) : m;
        }
    };
    for (int round = 0; round < kSpreadRounds; ++round) {
        step(wide, lift, false);
        step(lift, wide, true);
    }
    return region;
}

// The vertices that may move (active), each with where it started and its shift, and the
// triangles around them; every other vertex stays where it started with a zero shift.
// (Whether such a shift is +0 or -0 only matters to a coordinate that is -0, the only
// one that x + 0 changes; vertices with one are made active with their exact shift.)
class Moving {
public:
    static constexpr std::uint32_t kNone = ~std::uint32_t(0);
    std::vector<std::uint32_t> vertices;   // active, in the order they became so
    std::vector<Vec3> start, shift, push;  // by the same index (push: a repair round's)
    std::vector<std::uint32_t> triangles;  // with an active corner
    std::vector<Vec3> faces;               // theirs where they started (face_vector)

    Moving(Mesh& mesh, const VertexLists& fans)
        : mesh_(mesh), fans_(fans), slot_(mesh.vertices.size(), kNone), on_(mesh.triangles.size(), 0) {}

    bool active(std::uint32_t v) const { return slot_[v] != kNone; }
    Vec3 shift_of(std::uint32_t v) const { return active(v) ? shift[slot_[v]] : Vec3{0, 0, 0}; }
    // v's shift, making v active (from where it is, which is where it started).
    Vec3& shift_ref(std::uint32_t v) {
        if (!active(v)) add(v, {0, 0, 0});
        return shift[slot_[v]];
    }
    Vec3 push_of(std::uint32_t v) const { return active(v) ? push[slot_[v]] : Vec3{0, 0, 0}; }
    Vec3& push_ref(std::uint32_t v) {
        if (!active(v)) add(v, {0, 0, 0});
        return push[slot_[v]];
    }
    void add(std::uint32_t v, const Vec3& s) {
        slot_[v] = std::uint32_t(vertices.size());
        vertices.push_back(v);
        start.push_back(mesh_.vertices[v]);
        shift.push_back(s);
        push.push_back({0, 0, 0});
        for (std::size_t f = fans_.start[v]; f < fans_.start[v + 1]; ++f) {
            const std::uint32_t t = fans_.items[f];
            if (on_[t]) continue;
            on_[t] = 1;
            triangles.push_back(t);
            const auto& tri = mesh_.triangles[t];
            const Vec3 a = start_of(tri[0]), b = start_of(tri[1]), c = start_of(tri[2]);
            faces.push_back(cross(sub(b, a), sub(c, a)));
        }
    }
    // Moves the active vertices from where they started by their shifts; returns the
    // triangles now turned over (facing against where they faced), ascending.
    std::vector<std::uint32_t> place() {
        const std::ptrdiff_t na = std::ptrdiff_t(vertices.size()), nt = std::ptrdiff_t(triangles.size());
#pragma omp parallel for schedule(static) if (na > detail::kParallelCheapItems)
        for (std::ptrdiff_t i = 0; i < na; ++i)
            for (int d = 0; d < 3; ++d) mesh_.vertices[vertices[i]][d] = start[i][d] + shift[i][d];
        turned_.assign(triangles.size(), 0);
#pragma omp parallel for schedule(static) if (nt > detail::kParallelCheapItems)
        for (std::ptrdiff_t i = 0; i < nt; ++i)
            turned_[i] = dot(faces[i], faces[i]) > 0 && dot(face_vector(mesh_, mesh_.triangles[triangles[i]]), faces[i]) <= 0;
        std::vector<std::uint32_t> turned;
        for (std::size_t i = 0; i < triangles.size(); ++i)
            if (turned_[i]) turned.push_back(triangles[i]);
        std::sort(turned.begin(), turned.end());
        return turned;
    }

private:
    Vec3 start_of(std::uint32_t v) const { return active(v) ? start[slot_[v]] : mesh_.vertices[v]; }

    Mesh& mesh_;
    const VertexLists& fans_;
    std::vector<std::uint32_t> slot_;
    std::vector<std::uint8_t> on_, turned_;
};

// Lifts along neighbouring normals differ, and a sliver of a triangle a hundredth of a
// voxel across turns over under the difference. Giving its corners their mean shift
// moves it without turning it; repeated until no triangle is turned, or the rounds end
// (then those triangles' corners go back to where they started). Calls moving(v) before
// it sets the shift of vertex v. (Only triangles with a moving corner can turn.)
template <class OnMove>
void untangle(Mesh& mesh, Moving& m, OnMove on_move) {
    for (int round = 0; round < kUntangleRounds; ++round) {
        const std::vector<std::uint32_t> turned = m.place();
        if (turned.empty()) return;
        for (std::uint32_t t : turned) {
            const auto& tri = mesh.triangles[t];
            Vec3 mean{0, 0, 0};
            for (std::uint32_t v : tri) {
                const Vec3 s = m.shift_of(v);
                for (int d = 0; d < 3; ++d) mean[d] += s[d] / 3;
            }
            for (std::uint32_t v : tri) on_move(v), m.shift_ref(v) = mean;
        }
    }
    const std::vector<std::uint32_t> turned = m.place();
    if (turned.empty()) return;
    for (std::uint32_t t : turned)
        for (std::uint32_t v : mesh.triangles[t]) on_move(v), m.shift_ref(v) = {0, 0, 0};
    m.place();
}

// Unit vertex normal of v where the mesh started (as vertex_normals: its faces summed in
// triangle order, its fan's order); `faces_at` gives a triangle's face vector there.
template <class FaceAt>
Vec3 vertex_normal(const VertexLists& fans, std::uint32_t v, FaceAt face_at) {
    Vec3 n{0, 0, 0};
    for (std::size_t f = fans.start[v]; f < fans.start[v + 1]; ++f) {
        const Vec3 fv = face_at(fans.items[f]);
        for (int d = 0; d < 3; ++d) n[d] += fv[d];
    }
    const double len = norm(n);
    if (len > 0)
        for (double& c : n) c /= len;
    return n;
}

// x: the vertices' positions (a vector, or ListTime).
template <class X>
double triangle_distance(const X& x, const Mesh& m, const Vec3& p, std::uint32_t t) {
    const auto& tri = m.triangles[t];
    return std::sqrt(point_triangle_dist_sq(p, x[tri[0]], x[tri[1]], x[tri[2]]));
}

// The watch list: for each point, the triangles within `within` of it when the list is
// made (its row). The list was gathered through an index of the corners: the corners
// within `reach` = within + longest edge / sqrt 3 (the largest circumradius, so every
// triangle within `within` has one) found each triangle of their fans, from its first
// corner within reach. Rows here are gathered from a grid of the triangles, keeping the
// index's distance test on the corners (index_takes), so they hold the same triangles,
// in triangle order instead of the index's. Of a point's equally near triangles (two
// sharing the nearest edge, say) the repair takes the lowest, so that order never matters.
//
// A row is only needed for a point that is too shallow, or whose triangles moved since
// it was last looked at: in the first round each point asks the grid for triangles
// within the depth alone; a row, when needed, is gathered from the same grid and the
// mesh as the list saw it (ListTime).

// Whether the index-based gathering took triangle t for the point at `at`: from a corner
// that its radius search finds, unless an earlier corner of t lies within reach (then
// from that corner, which the search finds too).
template <class X>
bool index_takes(const X& x, const Mesh& m, const Vec3& at, std::uint32_t t, double reach) {
    const double reach_sq = reach * reach;
    for (std::uint32_t c : m.triangles[t]) {
        if (index_dist_sq(at, x[c]) < reach_sq) return true;
        if (norm(sub(x[c], at)) < reach) return false;
    }
    return false;
}

// A point's nearest triangle of a set.
struct Nearest {
    double dist = kInf;
    std::uint32_t triangle = 0;  // the lowest of those at dist: the same whatever the order of add
    void add(double d, std::uint32_t t) {
        if (d < dist || (d == dist && t < triangle)) {
            dist = d;
            triangle = t;
        }
    }
};

// Triangles (all, or a subset) filed by the low corner of their boxes, with each cell's
// bound and largest squared edge length, as the mesh is when the cells are made.
class TriangleCells {
public:
    TriangleCells(const Mesh& mesh, const std::vector<std::uint32_t>* subset, double cell) : mesh_(mesh) {
        const std::ptrdiff_t n = std::ptrdiff_t(subset ? subset->size() : mesh.triangles.size());
        const std::vector<Vec3>& x = mesh.vertices;
        if (subset) ids_ = *subset;
        // The grid spans the corners (all vertices for the whole mesh).
        Bound frame;
        if (subset) {
            for (std::uint32_t t : ids_)
                for (std::uint32_t v : mesh.triangles[t]) frame.add_to_box(x[v]);
        } else {
            for (const Vec3& v : x) frame.add_to_box(v);
        }
        // As many cells as the whole mesh's would have, for a subset too: the moved
        // triangles of a repair lie scattered over the whole shell, and a grid sized to
        // their number made cells so wide that each held dozens of triangles for every
        // point near it (1.4 s of the 50 M-point city block's 4.4 s guard, 0.4 s so).
        grid_ = std::make_unique<CellGrid>(frame.lo, frame.hi, cell, 2 * mesh.triangles.size() + 4096);
        cell_of_.resize(std::size_t(n));
        Vec3 extent{0, 0, 0};
#pragma omp parallel if (n > detail::kParallelCheapItems)
        {
            Vec3 my_extent{0, 0, 0};
#pragma omp for schedule(static)
            for (std::ptrdiff_t i = 0; i < n; ++i) {
                const auto& tri = mesh.triangles[id(std::uint32_t(i))];
                Vec3 lo;
                for (int d = 0; d < 3; ++d) {
                    const double a = x[tri[0]][d], b = x[tri[1]][d], c = x[tri[2]][d];
                    lo[d] = std::min({a, b, c});
                    my_extent[d] = std::max(my_extent[d], std::max({a, b, c}) - lo[d]);
                }
                cell_of_[i] = grid_->cell_of(lo);
            }
#pragma omp critical
            for (int d = 0; d < 3; ++d) extent[d] = std::max(extent[d], my_extent[d]);
        }
        extent_ = extent;
        grid_->file(cell_of_);
        cell_.resize(grid_->used_cells());
        edge_sq_.resize(grid_->used_cells());
        grid_->for_each_cell([&](std::uint32_t c, std::uint32_t b, std::uint32_t e) {
            Bound& cb = cell_[c];
            double most = 0;
            for (std::uint32_t s = b; s < e; ++s) {
                const auto& tri = mesh.triangles[id(grid_->order[s])];
                for (std::uint32_t v : tri) cb.add_to_box(x[v]);
                const Vec3 f = face_vector(mesh, tri);  // area-weighted: any direction bounds
                if (std::isfinite(dot(f, f)))
                    for (int d = 0; d < 3; ++d) cb.n[d] += f[d];
                most = std::max(most, edge_sq(x, tri));
            }
            edge_sq_[c] = most;
            cb.normalize();
            for (std::uint32_t s = b; s < e; ++s)
                for (std::uint32_t v : mesh.triangles[id(grid_->order[s])]) cb.add_to_slab(x[v]);
        });
        for (double e2 : edge_sq_) longest_sq_ = std::max(longest_sq_, e2);
    }

    // Calls f(t, box) for every triangle that may lie within r of q (a superset; the
    // caller makes the exact test), box being q's squared distance to its box, with x
    // the vertices as the cells were made.
    template <class X, class F>
    void near(const X& x, const Vec3& q, double r, F f) const {
        const double lo_r = slack(r, q), r_box = slack(r * (1 + 1e-9), q), r_box_sq = r_box * r_box;
        const double slab_r = slab_radius(r, std::sqrt(longest_sq_), q);
        grid_->for_cells({q[0] - lo_r - extent_[0], q[1] - lo_r - extent_[1], q[2] - lo_r - extent_[2]},
                         {q[0] + lo_r, q[1] + lo_r, q[2] + lo_r}, [&](std::uint32_t c, std::uint32_t b, std::uint32_t e) {
                             if (cell_[c].may_reach(q, r_box_sq, slab_r)) boxes_near(x, q, r_box_sq, b, e, f);
                         });
    }

    // The same pairs as near(x, q, r, f) for every point q of `tree` before `end`, found
    // from the cells: calls f(k, t, box) for each point k and triangle t that near(x,
    // point k, r) would hand over, from the team's threads. A pair is handed over when the
    // point passes its cell's exact test (Bound::may_reach) and the triangle's box test; a
    // node of the tree is passed by when its box is beyond a cell's bound, and a point when
    // its float coordinates are (FloatReach): the cost follows the points near the mesh.
    template <class X, class F>
    void near_points(const X& x, const detail::PointTree& tree, double r, F f,
                     std::size_t end = std::numeric_limits<std::size_t>::max()) const {
        using Node = detail::PointTree::Node;
        const double slab_extent = std::sqrt(longest_sq_);
        const FloatFrame frame(tree, r, slab_extent);
        // Whether any point of node n may come within r of cell c's bound.
        const auto node_may_reach = [&](const Bound& cb, const Vec3& lo, const Vec3& hi, const Vec3& big) {
            const double r_box = slack(r * (1 + 1e-9), big);
            double gap = 0;
            for (int d = 0; d < 3; ++d) {
                const double g = std::max({0.0, cb.lo[d] - hi[d], lo[d] - cb.hi[d]});
                gap += g * g;
            }
            if (!(gap < r_box * r_box)) return false;
            if (cb.n[0] == 0 && cb.n[1] == 0 && cb.n[2] == 0) return true;
            double s_lo = 0, s_hi = 0;
            for (int d = 0; d < 3; ++d) {
                s_lo += std::min(cb.n[d] * lo[d], cb.n[d] * hi[d]);
                s_hi += std::max(cb.n[d] * lo[d], cb.n[d] * hi[d]);
            }
            const double slab_r = slab_radius(r, slab_extent, big) + 64 * DBL_EPSILON * largest_coordinate(big);
            return !(s_hi < cb.n_lo - slab_r || s_lo > cb.n_hi + slab_r);
        };
        const auto points_of = [&](const Node& n, std::uint32_t c, std::uint32_t b, std::uint32_t e,
                                   const FloatReach& reach) {
            const Bound& cb = cell_[c];
            const std::uint32_t last = std::uint32_t(std::min<std::size_t>(n.end, end));
            for (std::uint32_t k = n.begin; k < last; ++k) {
                if (!reach.may_reach(tree.xyz[k])) continue;  // nearly every point of a dense scan
                const Vec3 q = tree.point(k);
                const double r_box = slack(r * (1 + 1e-9), q), r_box_sq = r_box * r_box;
                if (!cb.may_reach(q, r_box_sq, slab_radius(r, slab_extent, q))) continue;
                boxes_near(x, q, r_box_sq, b, e, [&](std::uint32_t t, double box) { f(k, t, box); });
            }
        };
        const auto corners = [&](const Node& n, Vec3& lo, Vec3& hi, Vec3& big) {
            lo = tree.lo(n), hi = tree.hi(n);
            for (int d = 0; d < 3; ++d) big[d] = std::max(std::fabs(lo[d]), std::fabs(hi[d]));
        };
        const auto& nodes = tree.nodes;
        std::size_t leaves = 0;
        for (const Node& n : nodes) leaves += n.leaf();
        if (grid_->used_cells() < leaves / 8) {
            // Few cells (a repair's): each walks the tree down to the leaves it may reach.
            grid_->for_each_cell([&](std::uint32_t c, std::uint32_t b, std::uint32_t e) {
                const FloatReach reach = frame.reach(cell_[c]);
                tree.for_each_leaf(
                    [&](const Node& n) {
                        if (n.begin >= end) return false;
                        Vec3 lo, hi, big;
                        corners(n, lo, hi, big);
                        return node_may_reach(cell_[c], lo, hi, big);
                    },
                    [&](const Node& n) { points_of(n, c, b, e, reach); });
            });
            return;
        }
        // Many (the whole mesh's): each leaf looks up the cells about it, tens of box
        // tests where a walk from the root made hundreds per cell. A cell's triangles have
        // their least corner in it and reach `extent_` beyond, so the cells whose bound
        // comes within r_box of the leaf lie in its box widened by that much.
        const std::ptrdiff_t nn = std::ptrdiff_t(nodes.size());
#pragma omp parallel for schedule(dynamic, 256) if (leaves > detail::kParallelCheapItems / 16)
        for (std::ptrdiff_t i = 0; i < nn; ++i) {
            const Node& n = nodes[std::size_t(i)];
            if (!n.leaf() || n.begin >= end) continue;
            Vec3 lo, hi, big;
            corners(n, lo, hi, big);
            const double r_box = slack(r * (1 + 1e-9), big);
            grid_->for_cells({lo[0] - r_box - extent_[0], lo[1] - r_box - extent_[1], lo[2] - r_box - extent_[2]},
                             {hi[0] + r_box, hi[1] + r_box, hi[2] + r_box},
                             [&](std::uint32_t c, std::uint32_t b, std::uint32_t e) {
                                 if (node_may_reach(cell_[c], lo, hi, big)) points_of(n, c, b, e, frame.reach(cell_[c]));
                             });
        }
    }

    // The largest squared edge length as the cells were made.
    double longest_sq() const { return longest_sq_; }

    // Of the whole mesh's triangles but those in `skip` (also flagged in `skipped`), with x
    // where the others still are.
    double longest_sq(const std::vector<std::uint32_t>& skip, const std::vector<std::uint8_t>& skipped) const {
        std::vector<std::uint8_t> redo(cell_.size(), 0);
        for (std::uint32_t t : skip) redo[grid_->rank(cell_of_[t])] = 1;
        double most = 0;
        grid_->for_each_cell(
            [&](std::uint32_t c, std::uint32_t b, std::uint32_t e) {
                if (!redo[c]) {
                    most = std::max(most, edge_sq_[c]);
                    return;
                }
                for (std::uint32_t s = b; s < e; ++s)
                    if (!skipped[grid_->order[s]]) most = std::max(most, edge_sq(mesh_.vertices, mesh_.triangles[grid_->order[s]]));
            },
            false);
        return most;
    }

private:
    std::uint32_t id(std::uint32_t i) const { return ids_.empty() ? i : ids_[i]; }
    // Calls f(t, box) for each triangle t in slots [b, e) of a cell whose box (with x the
    // vertices) lies below r_box_sq of q, box being that squared distance.
    template <class X, class F>
    void boxes_near(const X& x, const Vec3& q, double r_box_sq, std::uint32_t b, std::uint32_t e, F&& f) const {
        for (std::uint32_t s = b; s < e; ++s) {
            const std::uint32_t t = id(grid_->order[s]);
            Bound tb;
            for (std::uint32_t v : mesh_.triangles[t]) tb.add_to_box(x[v]);
            const double box = box_dist_sq(q, tb.lo, tb.hi);
            if (box < r_box_sq) f(t, box);
        }
    }
    // A triangle's largest squared edge length.
    template <class X>
    static double edge_sq(const X& x, const std::array<std::uint32_t, 3>& tri) {
        double most = 0;
        for (int e = 0; e < 3; ++e) {
            const Vec3 d = sub(x[tri[e]], x[tri[(e + 1) % 3]]);
            most = std::max(most, dot(d, d));
        }
        return most;
    }

    const Mesh& mesh_;
    std::vector<std::uint32_t> ids_;      // the subset, if any
    std::vector<std::uint32_t> cell_of_;  // each item's cell
    Vec3 extent_{0, 0, 0};                // the largest box side of a triangle, per axis
    std::unique_ptr<CellGrid> grid_;
    std::vector<Bound> cell_;
    std::vector<double> edge_sq_;  // by cell
    double longest_sq_ = 0;
};

// The vertices as the watch list saw them: the repairs save each vertex they move before
// its first move, and reading a vertex gives the saved position if there is one.
class ListTime {
public:
    explicit ListTime(const Mesh& mesh) : mesh_(mesh), slot_(mesh.vertices.size(), 0) {}
    void save(std::uint32_t v) {
        if (slot_[v]) return;
        was_.push_back(mesh_.vertices[v]);
        slot_[v] = std::uint32_t(was_.size());
    }
    const Vec3& operator[](std::size_t v) const { return slot_[v] ? was_[slot_[v] - 1] : mesh_.vertices[v]; }

private:
    const Mesh& mesh_;
    std::vector<std::uint32_t> slot_;  // 1 + index in was_, 0 if not moved
    std::vector<Vec3> was_;
};

// A triangle's face vector where the mesh started (before any vertex moved).
struct StartFaces {
    const Mesh& mesh;
    Vec3 operator()(std::uint32_t t) const { return face_vector(mesh, mesh.triangles[t]); }
};

bool counts_point(const GuardCounted* counted, std::size_t p) { return !counted || counted->point(std::uint32_t(p)); }
bool counts_vertex(const GuardCounted* counted, std::size_t v) {
    return !counted || (v >= counted->vertex_begin && v < counted->vertex_end);
}

// The points the promise covers: those with another point within `lone`.
std::vector<std::uint8_t> covered_points(const PointTree& points, double lone, const GuardCounted* counted,
                                         DepthGuardReport& report) {
    std::vector<std::uint8_t> kept(points.size(), 1);
    if (!std::isfinite(lone)) return kept;
    const std::ptrdiff_t np = std::ptrdiff_t(points.size());
#pragma omp parallel for schedule(dynamic, 1024) if (np > detail::kParallelItems)
    for (std::ptrdiff_t p = 0; p < np; ++p) kept[p] = points.nearest_other(std::size_t(p)) <= lone;
    for (std::size_t p = 0; p < kept.size(); ++p) report.lone_points += !kept[p] && counts_point(counted, p);
    return kept;
}

// The search, on the mesh as it starts, in cells: each point finds the vertices within
// the aim of it (the index's distance test, so exactly those the index would find),
// and, for the first repair round, the triangles within the depth of it (those that the
// lift leaves where they are stay that near). The cells look for their points, so that
// the points far from the mesh (most of a dense scan) cost nothing. The points before
// `end` (the others elsewhere); the pairs of the `kept` ones (null: every one).
struct StartSearch {
    std::vector<std::uint8_t> near_point;  // by vertex: a point within the aim
    std::vector<PointTriangle> close;      // (kept point, triangle) nearer than the depth, by point
};

StartSearch search_start(const Mesh& mesh, const PointTree& points, const TriangleCells& start_cells,
                         const std::vector<std::uint8_t>* kept, double aim, double depth, std::size_t end) {
    StartSearch found;
    found.near_point.assign(mesh.vertices.size(), 0);
    const double aim_sq = aim * aim;
    const std::size_t team = std::size_t(detail::threads_here());
    std::vector<std::vector<std::uint32_t>> near_of(team);
    std::vector<std::vector<PointTriangle>> close_of(team);
    start_cells.near_points(mesh.vertices, points, aim, [&](std::uint32_t p, std::uint32_t t, double box) {
        std::vector<std::uint32_t>& mine = near_of[std::size_t(detail::thread_number())];
        const Vec3 q = points.point(p);
        for (std::uint32_t c : mesh.triangles[t])
            if (index_dist_sq(mesh.vertices[c], q) < aim_sq) mine.push_back(c);
        // The box bound keeps a margin far above the exact distance's rounding.
        const double depth_box = slack(depth * (1 + 1e-9), q), depth_box_sq = depth_box * depth_box;
        if ((kept && !(*kept)[p]) || !(box < depth_box_sq)) return;
        const double d = triangle_distance(mesh.vertices, mesh, q, t);
        if (d < depth) close_of[std::size_t(detail::thread_number())].push_back({p, t, d});
    }, end);
    for (const auto& mine : near_of)
        for (std::uint32_t v : mine) found.near_point[v] = 1;
    for (const auto& mine : close_of) found.close.insert(found.close.end(), mine.begin(), mine.end());
    std::sort(found.close.begin(), found.close.end(), [](const PointTriangle& a, const PointTriangle& b) {
        return a.point != b.point ? a.point < b.point : a.triangle < b.triangle;
    });
    return found;
}

// How far to lift each vertex nearer than the aim to a kept point on its inner side.
// Only the vertices with a point that near ask the index for their nearest; a vertex no
// triangle uses has no normal and is never lifted. (Also notes the vertices with a -0
// coordinate, see Moving.)
std::vector<double> vertex_lifts(const Mesh& mesh, const VertexLists& fans, const PointTree& points,
                                 const std::vector<std::uint8_t>& kept, const std::vector<std::uint8_t>& near_point,
                                 double aim, std::vector<std::uint32_t>& negative_zero) {
    const std::ptrdiff_t nv = std::ptrdiff_t(mesh.vertices.size());
    std::vector<std::uint32_t> asking;
    for (std::ptrdiff_t v = 0; v < nv; ++v) {
        if (near_point[v] && fans.start[v] != fans.start[v + 1]) asking.push_back(std::uint32_t(v));
        for (int d = 0; d < 3; ++d)
            if (mesh.vertices[v][d] == 0 && std::signbit(mesh.vertices[v][d])) {
                negative_zero.push_back(std::uint32_t(v));
                break;
            }
    }
    std::vector<double> lift(mesh.vertices.size(), 0.0);
    const StartFaces start_face{mesh};
    const std::ptrdiff_t na = std::ptrdiff_t(asking.size());
#pragma omp parallel for schedule(dynamic, 64) if (na > detail::kParallelItems)
    for (std::ptrdiff_t i = 0; i < na; ++i) {
        const std::uint32_t v = asking[i];
        const PointTree::Hit hit = points.nearest(mesh.vertices[v], aim * aim);
        const std::uint32_t p = hit.index;
        if (p != PointTree::npos && kept[p] &&
            dot(sub(mesh.vertices[v], points.point(p)), vertex_normal(fans, v, start_face)) > 0)
            lift[v] = aim - std::sqrt(hit.dist_sq);
    }
    return lift;
}

// The vertices that can move: where the lift reaches (region), and any with a -0
// coordinate (see Moving), each shifted along its normal by its lift.
void add_lifted(Moving& moving, const Mesh& mesh, const VertexLists& fans, const std::vector<std::uint32_t>& region,
                const std::vector<std::uint32_t>& negative_zero, const std::vector<double>& lift) {
    std::vector<std::uint32_t> order = region;
    order.insert(order.end(), negative_zero.begin(), negative_zero.end());
    std::sort(order.begin(), order.end());
    order.erase(std::unique(order.begin(), order.end()), order.end());
    std::vector<Vec3> shift(order.size());
    const StartFaces start_face{mesh};
    const std::ptrdiff_t nr = std::ptrdiff_t(order.size());
#pragma omp parallel for schedule(static) if (nr > detail::kParallelItems)
    for (std::ptrdiff_t i = 0; i < nr; ++i) {
        const Vec3 n = vertex_normal(fans, order[i], start_face);
        for (int d = 0; d < 3; ++d) shift[i][d] = n[d] * lift[order[i]];
    }
    for (std::size_t i = 0; i < order.size(); ++i) moving.add(order[i], shift[i]);
}

// The repairs: move the nearest triangle of each point still shallower than the depth
// along its own normal, all three corners alike, round by round. The watch list holds
// every triangle within a quarter voxel of the depth from a point; repairs move a few
// vertices by a fraction of that, outward, away from the points inside. Each round
// tests which points' rows a move touched, renews their nearest, and moves.
class Repairs {
public:
    // The triangles that moved go in cells of their own; the others are where
    // start_cells has them. The longest edge: a root of the largest square (the root
    // is monotone).
    Repairs(Mesh& mesh, const PointTree& points, const std::vector<std::uint8_t>& kept, const VertexLists& fans,
            const TriangleCells& start_cells, Moving& moving, double depth, double voxel, double aim, double within,
            const GuardCounted* counted)
        : mesh_(mesh),
          points_(points),
          kept_(kept),
          fans_(fans),
          start_cells_(start_cells),
          moving_(moving),
          depth_(depth),
          voxel_(voxel),
          within_(within),
          counted_(counted),
          moved_tri_(moved_triangles(mesh, moving)),
          moved_cells_(mesh, &moving.triangles, aim),
          reach_(within + std::sqrt(std::max(start_cells.longest_sq(moving.triangles, moved_tri_),
                                             moved_cells_.longest_sq())) /
                              std::sqrt(3.0)),
          list_time_(mesh),
          touched_(mesh.vertices.size(), 0) {}

    // Each point's nearest triangle of its row, as far as it matters: exact where below
    // the depth; a point without an entry is not below the depth. Kept for the few points
    // near a lift only (a dense scan has millions). From the search's pairs for the
    // triangles that stayed, and the moved cells for the others.
    void find_nearest(const std::vector<PointTriangle>& close) {
        std::size_t c = 0;
        while (c < close.size()) {
            const std::uint32_t p = close[c].point;
            Nearest n;
            for (; c < close.size() && close[c].point == p; ++c)
                if (!moved_tri_[close[c].triangle] &&
                    index_takes(mesh_.vertices, mesh_, points_.point(p), close[c].triangle, reach_))
                    n.add(close[c].dist, close[c].triangle);
            if (n.dist < kInf) nearest_[p] = n;
        }
        std::vector<std::vector<PointTriangle>> near_moved(std::size_t(detail::threads_here()));
        moved_cells_.near_points(mesh_.vertices, points_, depth_, [&](std::uint32_t p, std::uint32_t t, double) {
            if (!kept_[p]) return;  // the repairs pass it by
            const Vec3 at = points_.point(p);
            const double d = triangle_distance(mesh_.vertices, mesh_, at, t);
            if (d < depth_ && index_takes(mesh_.vertices, mesh_, at, t, reach_))
                near_moved[std::size_t(detail::thread_number())].push_back({p, t, d});
        });
        for (const auto& mine : near_moved)
            for (const PointTriangle& m : mine) nearest_[m.point].add(m.dist, m.triangle);
    }

    void run(DepthGuardReport& report, const detail::Begun& begun) {
        for (report.repair_rounds = 0;; ++report.repair_rounds) {
            if (report.repair_rounds > 0) renew(stale_points());
            const std::size_t shallow = push_shallow(report.shallow_points);
            if (shallow == 0 || report.repair_rounds == kRepairRounds) break;
            if (begun)
                begun("the depth guard: repair round " + std::to_string(report.repair_rounds + 1) + ", " +
                      std::to_string(shallow) + " points still too shallow");
            // shift += push (elsewhere both are zero: nothing to add).
            for (std::size_t i = 0; i < moving_.vertices.size(); ++i)
                for (int d = 0; d < 3; ++d) moving_.shift[i][d] += moving_.push[i][d];
            // A vertex that untangling moves is, before it first moves, where the list saw it.
            untangle(mesh_, moving_, [&](std::uint32_t v) {
                list_time_.save(v);
                touched_[v] = 1;
            });
        }
    }

private:
    static std::vector<std::uint8_t> moved_triangles(const Mesh& mesh, const Moving& moving) {
        std::vector<std::uint8_t> moved(mesh.triangles.size(), 0);
        for (std::uint32_t t : moving.triangles) moved[t] = 1;
        return moved;
    }

    // The test: points whose rows hold a triangle with a corner that moved in the last
    // round: the triangles around the moved vertices, and the kept points within
    // `within` of them as the list saw them, that the index would have taken them for.
    std::vector<std::uint32_t> stale_points() {
        const ListTime& as_was = list_time_;
        std::vector<std::uint32_t> changed;
        for (std::size_t v = 0; v < touched_.size(); ++v)
            if (touched_[v])
                for (std::size_t f = fans_.start[v]; f < fans_.start[v + 1]; ++f) changed.push_back(fans_.items[f]);
        std::sort(changed.begin(), changed.end());
        changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
        std::vector<std::uint32_t> stale;
        const std::ptrdiff_t nc = std::ptrdiff_t(changed.size());
#pragma omp parallel if (nc > 64)
        {
            std::vector<std::uint32_t> mine;
#pragma omp for schedule(dynamic, 16)
            for (std::ptrdiff_t i = 0; i < nc; ++i) {
                const std::uint32_t t = changed[i];
                Bound tb;
                for (std::uint32_t v : mesh_.triangles[t]) tb.add_to_box(as_was[v]);
                // Where a point within `within` of the triangle lies, rounding included.
                const double r = slack(slack(within_, tb.lo), tb.hi);
                const Vec3 a{tb.lo[0] - r, tb.lo[1] - r, tb.lo[2] - r}, b{tb.hi[0] + r, tb.hi[1] + r, tb.hi[2] + r};
                points_.for_each_leaf(
                    [&](const PointTree::Node& n) {
                        Bound nb;
                        nb.lo = points_.lo(n);
                        nb.hi = points_.hi(n);
                        return overlap(nb, a, b);
                    },
                    [&](const PointTree::Node& n) {
                        for (std::uint32_t p = n.begin; p < n.end; ++p) {
                            const Vec3 at = points_.point(p);
                            if (!kept_[p] || !inside(at, a, b)) continue;
                            if (triangle_distance(as_was, mesh_, at, t) < within_ &&
                                index_takes(as_was, mesh_, at, t, reach_))
                                mine.push_back(p);
                        }
                    });
            }
#pragma omp critical
            stale.insert(stale.end(), mine.begin(), mine.end());
        }
        std::sort(stale.begin(), stale.end());
        stale.erase(std::unique(stale.begin(), stale.end()), stale.end());
        std::fill(touched_.begin(), touched_.end(), 0);
        return stale;
    }

    // The rows not gathered yet, then each stale point's nearest of its row.
    void renew(const std::vector<std::uint32_t>& stale) {
        std::vector<std::uint32_t> rowless;
        for (std::uint32_t p : stale)
            if (!rows_.count(p)) rowless.push_back(p);
        std::vector<std::vector<std::uint32_t>> gathered(rowless.size());
        const std::ptrdiff_t nr = std::ptrdiff_t(rowless.size());
#pragma omp parallel for schedule(dynamic, 16) if (nr > 256)
        for (std::ptrdiff_t i = 0; i < nr; ++i) gathered[i] = gather_row(rowless[i]);
        for (std::size_t i = 0; i < rowless.size(); ++i) rows_[rowless[i]] = std::move(gathered[i]);
        std::vector<Nearest> renewed(stale.size());
        const std::ptrdiff_t ns = std::ptrdiff_t(stale.size());
#pragma omp parallel for schedule(dynamic, 16) if (ns > 256)
        for (std::ptrdiff_t i = 0; i < ns; ++i) {
            const std::uint32_t p = stale[i];
            const Vec3 at = points_.point(p);
            for (std::uint32_t t : rows_.at(p)) renewed[i].add(triangle_distance(mesh_.vertices, mesh_, at, t), t);
        }
        for (std::size_t i = 0; i < stale.size(); ++i) nearest_[stale[i]] = renewed[i];
    }

    // Point p's row, gathered when first needed (from both cells, as the list saw the mesh).
    std::vector<std::uint32_t> gather_row(std::uint32_t p) const {
        std::vector<std::uint32_t> row;
        const Vec3 at = points_.point(p);
        const auto take = [&](std::uint32_t t) {
            if (triangle_distance(list_time_, mesh_, at, t) < within_ && index_takes(list_time_, mesh_, at, t, reach_))
                row.push_back(t);
        };
        start_cells_.near(list_time_, at, within_, [&](std::uint32_t t, double) {
            if (!moved_tri_[t]) take(t);
        });
        moved_cells_.near(list_time_, at, within_, [&](std::uint32_t t, double) { take(t); });
        std::sort(row.begin(), row.end());
        return row;
    }

    // The move: pushes the nearest triangle of each point shallower than the depth, the
    // last round's pushes undone first; returns the points pushed for (`counted`: those the
    // report counts).
    std::size_t push_shallow(std::size_t& counted) {
        counted = 0;
        for (std::uint32_t v : pushed_) moving_.push_ref(v) = {0, 0, 0};
        pushed_.clear();
        std::size_t shallow_points = 0;
        // In point order: of equal pushes on a vertex, the first point's stays.
        std::vector<std::uint32_t> shallow;
        for (const auto& [i, n] : nearest_)
            if (n.dist < depth_) shallow.push_back(i);
        std::sort(shallow.begin(), shallow.end());
        for (std::uint32_t i : shallow) {
            const double dist = nearest_.at(i).dist;
            const Vec3 p = points_.point(i);
            const auto& t = mesh_.triangles[nearest_.at(i).triangle];
            const Vec3 n = face_vector(mesh_, t);
            if (dot(sub(mesh_.vertices[t[0]], p), n) <= 0) continue;  // the point is not under it
            ++shallow_points;
            counted += counts_point(counted_, i);
            const double by = (depth_ - dist + 0.5 * kMarginVoxels * voxel_) / norm(n);
            for (std::uint32_t v : t)
                if (by * norm(n) > norm(moving_.push_of(v))) {
                    if (!touched_[v]) pushed_.push_back(v), list_time_.save(v);
                    moving_.push_ref(v) = {n[0] * by, n[1] * by, n[2] * by}, touched_[v] = 1;
                }
        }
        return shallow_points;
    }

    Mesh& mesh_;
    const PointTree& points_;
    const std::vector<std::uint8_t>& kept_;
    const VertexLists& fans_;
    const TriangleCells& start_cells_;
    Moving& moving_;
    const double depth_, voxel_, within_;
    const GuardCounted* counted_;
    const std::vector<std::uint8_t> moved_tri_;
    const TriangleCells moved_cells_;
    const double reach_;
    ListTime list_time_;
    std::unordered_map<std::uint32_t, Nearest> nearest_;
    std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> rows_;
    std::vector<std::uint8_t> touched_;  // moved in the last round
    std::vector<std::uint32_t> pushed_;
};

// What other processes found for their points, added to this one's: the pairs of the
// kept points among them, in the order one search of every point gives.
void add_found(StartSearch& found, const GuardFound& theirs, const std::vector<std::uint8_t>& kept) {
    for (const std::uint32_t v : theirs.near_vertices) {
        if (v >= found.near_point.size()) throw Error("the depth guard's search elsewhere named a vertex the mesh lacks");
        found.near_point[v] = 1;
    }
    for (const PointTriangle& c : theirs.close) {
        if (c.point >= kept.size()) throw Error("the depth guard's search elsewhere named a point the cloud lacks");
        if (kept[c.point]) found.close.push_back(c);
    }
    std::sort(found.close.begin(), found.close.end(), [](const PointTriangle& a, const PointTriangle& b) {
        return a.point != b.point ? a.point < b.point : a.triangle < b.triangle;
    });
}

}  // namespace

detail::GuardFound detail::guard_search(const Mesh& mesh, const PointTree& points, double aim, double depth) {
    GuardFound out;
    if (mesh.triangles.empty() || points.size() == 0) return out;
    const TriangleCells cells(mesh, nullptr, aim);
    StartSearch found = search_start(mesh, points, cells, nullptr, aim, depth, points.size());
    for (std::size_t v = 0; v < found.near_point.size(); ++v)
        if (found.near_point[v]) out.near_vertices.push_back(std::uint32_t(v));
    out.close = std::move(found.close);
    return out;
}

DepthGuardReport keep_points_deep(Mesh& mesh, const PointSet& points, double depth, double voxel, double lone) {
    return keep_points_deep(mesh, PointCloud(points), depth, voxel, lone);
}

DepthGuardReport keep_points_deep(Mesh& mesh, const PointCloud& points, double depth, double voxel, double lone) {
    if (!(depth > 0) || !(voxel > 0) || !std::isfinite(depth) || !std::isfinite(voxel))
        throw ParameterError("keep_points_deep: depth and voxel must be positive and finite");
    if (!(lone > 0)) throw ParameterError("keep_points_deep: lone must be positive");
    if (mesh.triangles.empty() || points.empty()) return {};
    for (const auto& t : mesh.triangles)
        for (std::uint32_t v : t)
            if (v >= mesh.vertices.size()) throw InputError("keep_points_deep: a triangle uses a missing vertex");
    VertexLists rings = detail::rings(mesh);
    VertexLists fans;
    fans.start = rings.start;
    fans.fill(mesh, detail::fan_item());
    return detail::keep_points_deep(mesh, detail::tree_of(points), depth, voxel, lone, std::move(rings), fans);
}

// Search (points near the start mesh), lift (the vertices near them, spread and
// untangled), then the repair rounds' test and move.
DepthGuardReport detail::keep_points_deep(Mesh& mesh, const PointTree& points, double depth, double voxel,
                                          double lone, VertexLists rings, const VertexLists& fans,
                                          const GuardElsewhere* elsewhere, const Begun& begun,
                                          const GuardCounted* counted) {
    if (!(depth > 0) || !(voxel > 0) || !std::isfinite(depth) || !std::isfinite(voxel))
        throw ParameterError("keep_points_deep: depth and voxel must be positive and finite");
    if (!(lone > 0)) throw ParameterError("keep_points_deep: lone must be positive");
    DepthGuardReport report;
    if (mesh.triangles.empty() || points.size() == 0) return report;

    const double aim = depth + kMarginVoxels * voxel;
    const double within = depth + 0.25 * voxel;
    if (begun) begun("the depth guard: searching the points near the surface");
    // The others search their points meanwhile, on the same cells of the same mesh.
    if (elsewhere) elsewhere->ask(mesh, aim, depth);
    const std::vector<std::uint8_t> kept = covered_points(points, lone, counted, report);
    const TriangleCells start_cells(mesh, nullptr, aim);
    StartSearch found =
        search_start(mesh, points, start_cells, &kept, aim, depth, elsewhere ? elsewhere->here_end : points.size());
    if (elsewhere) add_found(found, elsewhere->collect(), kept);

    std::vector<std::uint32_t> negative_zero;
    std::vector<double> lift = vertex_lifts(mesh, fans, points, kept, found.near_point, aim, negative_zero);
    std::size_t near = 0;
    for (std::size_t v = 0; v < lift.size(); ++v) {
        near += lift[v] > 0;
        report.near_vertices += lift[v] > 0 && counts_vertex(counted, v);
    }
    if (near == 0) return report;
    if (begun) begun("the depth guard: lifting " + std::to_string(near) + " vertices near points");
    const std::vector<std::uint32_t> region = spread(mesh, rings, fans, lift);
    rings = VertexLists();  // the repairs below walk fans only
    Moving moving(mesh, fans);
    add_lifted(moving, mesh, fans, region, negative_zero, lift);
    untangle(mesh, moving, [](std::uint32_t) {});

    Repairs repairs(mesh, points, kept, fans, start_cells, moving, depth, voxel, aim, within, counted);
    repairs.find_nearest(found.close);
    repairs.run(report, begun);
    for (std::size_t i = 0; i < moving.vertices.size(); ++i)
        report.moved_vertices += dot(moving.shift[i], moving.shift[i]) > 0 && counts_vertex(counted, moving.vertices[i]);
    return report;
}

int detail::guard_reach_planes(double depth, double voxel) {
    // A lift reaches the vertices within the aim of a point (a plane more for the cube a
    // vertex sits in), then spreads a ring (a plane) a step, two steps a round.
    return int(std::ceil((depth + kMarginVoxels * voxel) / voxel)) + 1 + 2 * kSpreadRounds;
}

double detail::guard_point_reach(double depth, double voxel, double lone) {
    // The points within the aim of a vertex (and a voxel's rounding), and the neighbours
    // that decide whether those are lone.
    return depth + (kMarginVoxels + 1) * voxel + (std::isfinite(lone) ? lone : 0);
}

}  // namespace snvr
