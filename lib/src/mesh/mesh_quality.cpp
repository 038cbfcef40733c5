// measure_quality: the shell's figures against its points, l and h (see quality.hpp
// for what each one means), and their text and JSON forms.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <omp.h>

#include "io/io_common.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh.hpp"
#include "snvr/quality.hpp"
#include "mesh/cell_rings.hpp"
#include "mesh/mesh_adjacency.hpp"
#include "mesh/threads_here.hpp"
#include "mesh/triangle_grid.hpp"
#include "geometry/vec3_math.hpp"

namespace snvr {

namespace {

using detail::threads_here;

using Tri = std::array<std::uint32_t, 3>;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kDegrees = 180 / 3.14159265358979323846;
// Below this many items a loop is not worth waking threads for.
constexpr std::ptrdiff_t kParallel = 4096;

// Robust for nearly parallel vectors, unlike acos of the dot product.
double angle(const Vec3& a, const Vec3& b) { return std::atan2(norm(cross(a, b)), dot(a, b)); }

void check_indices(const Mesh& mesh, const char* who) {
    // The largest index first (a loop without branches): there is rarely anything to report.
    std::uint32_t top = 0;
    for (const Tri& t : mesh.triangles) top = std::max(top, std::max(t[0], std::max(t[1], t[2])));
    if (mesh.triangles.empty() || top < mesh.vertices.size()) return;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (std::uint32_t v : mesh.triangles[t])
            if (v >= mesh.vertices.size())
                throw InputError(std::string(who) + ": triangle " + std::to_string(t) + " uses vertex " +
                                 std::to_string(v) + " of " + std::to_string(mesh.vertices.size()));
}

// vertex_normals(m, faces) without the array of faces, and in parallel: each
// thread sums, in triangle order as vertex_normals does, into its own range of
// vertices, so that every normal comes out the same to the last bit.
std::vector<Vec3> unit_normals(const Mesh& m) {
    const auto& T = m.triangles;
    const std::size_t nv = m.vertices.size();
    std::vector<Vec3> n(nv, Vec3{0, 0, 0});
    const bool parallel = std::ptrdiff_t(T.size()) > kParallel;
    const int parts = parallel ? std::max(1, threads_here()) : 1;
#pragma omp parallel for schedule(static, 1) if (parts > 1)
    for (int k = 0; k < parts; ++k) {
        const std::size_t lo = nv * std::size_t(k) / std::size_t(parts), hi = nv * std::size_t(k + 1) / std::size_t(parts);
        for (const Tri& t : T) {
            if ((t[0] < lo || t[0] >= hi) && (t[1] < lo || t[1] >= hi) && (t[2] < lo || t[2] >= hi)) continue;
            const Vec3 f = face_vector(m, t);
            for (std::uint32_t v : t)
                if (v >= lo && v < hi)
                    for (int d = 0; d < 3; ++d) n[v][d] += f[d];
        }
    }
#pragma omp parallel for schedule(static) if (parallel)
    for (std::ptrdiff_t v = 0; v < std::ptrdiff_t(nv); ++v) {
        const double len = norm(n[v]);
        if (len > 0)
            for (double& x : n[v]) x /= len;
    }
    return n;
}

// A ray's t_min for the walls: far below any wall, far above the rounding of a
// hit at the ray's own start.
double wall_epsilon(const Mesh& m) {
    Vec3 lo{kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf};
    for (const Vec3& p : m.vertices)
        for (int d = 0; d < 3; ++d) {
            lo[d] = std::min(lo[d], p[d]);
            hi[d] = std::max(hi[d], p[d]);
        }
    return m.vertices.empty() ? 0 : 1e-9 * norm({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
}

// wall[v], v in [first, last): the distance from vertex v along its inward
// normal to the first triangle met, ignoring the vertex's own triangles;
// infinity when nothing is met.
void wall_thickness(const Mesh& m, const TriangleGrid& grid, const std::vector<Vec3>& normals, double eps,
                    std::size_t first, std::size_t last, std::vector<double>& wall) {
    for (std::size_t v = first; v < last; ++v) {
        const Vec3& n = normals[v];
        if (dot(n, n) == 0) continue;
        wall[v] = grid.first_hit(m.vertices[v], {-n[0], -n[1], -n[2]}, eps, std::uint32_t(v)).t;
    }
}

// Vertices per piece of the walls, handed out one piece at a time.
constexpr std::size_t kWallChunk = 4096;

// The nearest-rank 1st percentile of the values (NaN for none); reorders them.
double percentile_01(std::vector<double>& values) {
    if (values.empty()) return kNaN;
    const auto k = std::ptrdiff_t(0.01 * double(values.size() - 1));
    std::nth_element(values.begin(), values.begin() + k, values.end());
    return values[k];
}

// Calls compute(first, last, out) on chunks of [0, n), in parallel, each filling
// its own buffer, then consume(buffer) chunk by chunk in order: sums taken in
// consume come out as from one thread (the same figure for any number of
// threads), while the costly part runs in parallel and no buffer outgrows a chunk.
template <class T, class Compute, class Consume>
void ordered_chunks(std::size_t n, [[maybe_unused]] bool parallel, const Compute& compute, const Consume& consume) {
    constexpr std::size_t kChunk = 8192;
    const std::ptrdiff_t chunks = std::ptrdiff_t((n + kChunk - 1) / kChunk);
#pragma omp parallel if (parallel)
    {
        std::vector<T> buffer;
#pragma omp for ordered schedule(static, 1)
        for (std::ptrdiff_t c = 0; c < chunks; ++c) {
            buffer.clear();
            compute(std::size_t(c) * kChunk, std::min(n, std::size_t(c + 1) * kChunk), buffer);
#pragma omp ordered
            { consume(buffer); }
        }
    }
}

// The half-edges of the proper triangles grouped by their lower vertex v, each as
// (upper vertex << 32 | triangle), sorted: runs of one upper vertex are one edge.
struct EdgeBuckets {
    std::vector<std::size_t> start;
    std::vector<std::uint64_t> items;
    void swap(EdgeBuckets& o) {
        start.swap(o.start);
        items.swap(o.items);
    }
};

std::uint32_t upper(std::uint64_t item) { return std::uint32_t(item >> 32); }
std::uint32_t triangle(std::uint64_t item) { return std::uint32_t(item); }

// Genus summed over the closed components; the open ones are counted apart.
// piece[t]: triangle t's component as check_mesh found it (its smallest triangle;
// none for a degenerate triangle).
void measure_topology(const Mesh& m, const EdgeBuckets& edges, const std::vector<std::uint32_t>& piece, MeshQuality& q) {
    const auto& T = m.triangles;
    const std::size_t nv = m.vertices.size(), nt = T.size();
    constexpr std::uint32_t none = std::uint32_t(-1);
    std::vector<std::uint32_t> id(nt, none);  // compact component of each proper triangle
    std::uint32_t n_comp = 0;
    for (std::size_t t = 0; t < nt; ++t)
        if (piece[t] != none) {
            const std::uint32_t root = piece[t];
            if (id[root] == none) id[root] = n_comp++;
            id[t] = id[root];
        }
    // chi = V - E + F per component; a vertex shared by two components counts in each.
    std::vector<long> chi(n_comp, 0);
    std::vector<char> open(n_comp, 0);
    for (std::size_t t = 0; t < nt; ++t)
        if (id[t] != none) ++chi[id[t]];
    for (std::size_t v = 0; v < nv; ++v)
        for (std::size_t k = edges.start[v]; k < edges.start[v + 1]; ++k) {
            const bool first = k == edges.start[v] || upper(edges.items[k]) != upper(edges.items[k - 1]);
            if (!first) continue;
            const std::uint32_t c = id[triangle(edges.items[k])];
            --chi[c];
            const bool last = k + 1 == edges.start[v + 1] || upper(edges.items[k + 1]) != upper(edges.items[k]);
            if (last) open[c] = 1;  // an edge with one triangle
        }
    std::vector<std::uint32_t> vertex_comp(nv, none);
    std::vector<std::uint64_t> extra;  // (vertex << 32 | component) beyond a vertex's first
    for (std::size_t t = 0; t < nt; ++t) {
        if (id[t] == none) continue;
        for (std::uint32_t v : T[t]) {
            if (vertex_comp[v] == none) {
                vertex_comp[v] = id[t];
                ++chi[id[t]];
            } else if (vertex_comp[v] != id[t]) {
                extra.push_back(std::uint64_t(v) << 32 | id[t]);
            }
        }
    }
    std::sort(extra.begin(), extra.end());
    extra.erase(std::unique(extra.begin(), extra.end()), extra.end());
    for (std::uint64_t e : extra) ++chi[std::uint32_t(e)];
    q.genus = 0;
    q.open_components = 0;
    for (std::uint32_t c = 0; c < n_comp; ++c) {
        if (open[c])
            ++q.open_components;
        else
            q.genus += (2 - chi[c]) / 2;
    }
}

// Dihedral RMS and the count of interior edges. Each edge is weighted by the sum
// of its two triangles' areas, so that the figure does not depend on how finely
// a flat or smoothly curved region happens to be cut.
void measure_dihedral(const Mesh& m, const EdgeBuckets& edges, MeshQuality& q) {
    const std::size_t nv = edges.start.size() - 1;
    double sum = 0, weight = 0;
    std::size_t interior = 0;
    ordered_chunks<std::array<double, 2>>(
        nv, std::ptrdiff_t(nv) > kParallel,
        [&](std::size_t first_v, std::size_t last_v, std::vector<std::array<double, 2>>& terms) {
            for (std::size_t v = first_v; v < last_v; ++v) {
                const std::uint64_t* it = edges.items.data() + edges.start[v];
                const std::uint64_t* last = edges.items.data() + edges.start[v + 1];
                while (it != last) {
                    const std::uint64_t* run = it;
                    while (it != last && upper(*it) == upper(*run)) ++it;
                    if (it - run != 2) continue;
                    const Vec3 a = face_vector(m, m.triangles[triangle(run[0])]);
                    const Vec3 b = face_vector(m, m.triangles[triangle(run[1])]);
                    const double w = 0.5 * (norm(a) + norm(b));
                    if (w == 0) continue;
                    const double theta = angle(a, b) * kDegrees;
                    terms.push_back({w * theta * theta, w});
                }
            }
        },
        [&](const std::vector<std::array<double, 2>>& terms) {
            for (const auto& t : terms) {
                sum += t[0];
                weight += t[1];
            }
            interior += terms.size();
        });
    q.interior_edges = interior;
    q.dihedral_rms = weight > 0 ? std::sqrt(sum / weight) : kNaN;
}

// RMS over vertices of the angle between a vertex's normal and the mean of its
// neighbours' normals: high where the normals jitter from vertex to vertex.
void measure_normal_noise(const std::vector<Vec3>& normals, const EdgeBuckets& edges, MeshQuality& q) {
    const std::size_t nv = normals.size();
    std::vector<Vec3> ring(nv, Vec3{0, 0, 0});
    for (std::size_t v = 0; v < nv; ++v)
        for (std::size_t k = edges.start[v]; k < edges.start[v + 1]; ++k) {
            const std::uint32_t u = upper(edges.items[k]);
            if (k > edges.start[v] && u == upper(edges.items[k - 1])) continue;  // each edge once
            for (int d = 0; d < 3; ++d) {
                ring[v][d] += normals[u][d];
                ring[u][d] += normals[v][d];
            }
        }
    // Angles in parallel, summed in vertex order: the same figure for any number
    // of threads (and no waiting on each other, as ordered chunks would).
    std::vector<double> theta_sq(nv, -1.0);  // -1: no angle at this vertex
#pragma omp parallel for schedule(static) if (std::ptrdiff_t(nv) > kParallel)
    for (std::ptrdiff_t v = 0; v < std::ptrdiff_t(nv); ++v) {
        if (dot(normals[v], normals[v]) == 0 || dot(ring[v], ring[v]) == 0) continue;
        const double theta = angle(normals[v], ring[v]) * kDegrees;
        theta_sq[v] = theta * theta;
    }
    double sum = 0;
    std::size_t count = 0;
    for (double t : theta_sq)
        if (t >= 0) {
            sum += t;
            ++count;
        }
    q.normal_noise = count ? std::sqrt(sum / double(count)) : kNaN;
}

// The points bucketed by a uniform grid, for the nearest point to each vertex.
// With a good bound (a neighbouring vertex's nearest point) a query looks at a
// few cells. It finds what a search of all points would, with the squared
// distance summed as PointIndex sums it: (dx^2 + dy^2) + dz^2.
class PointGrid {
public:
    static constexpr std::uint32_t none = std::uint32_t(-1);
    struct Hit {
        double dist_sq;       // infinity when nothing was found
        std::uint32_t index;  // none when nothing was found
    };

    // cell_size: the edge length to aim for (about the distances queries span).
    PointGrid(const PointSet& points, double cell_size) {
        lo_ = {kInf, kInf, kInf};
        Vec3 hi{-kInf, -kInf, -kInf};
        std::size_t n = 0;
        for (const Vec3& p : points)
            if (finite(p)) {  // a point with a coordinate not finite is never the nearer one
                ++n;
                for (int d = 0; d < 3; ++d) {
                    lo_[d] = std::min(lo_[d], p[d]);
                    hi[d] = std::max(hi[d], p[d]);
                }
            }
        if (n == 0) return;
        const Vec3 span = sub(hi, lo_);
        size_ = std::max({cell_size, 1e-9 * norm(span), std::numeric_limits<double>::min()});
        for (;;) {  // at most a few cells per point
            double cells = 1;
            for (int d = 0; d < 3; ++d) {
                n_[d] = std::max(1, int(std::min(1e9, std::ceil(span[d] / size_))));
                cells *= n_[d];
            }
            if (cells <= 8.0 * double(n) + 4096) break;
            size_ *= 1.25;
        }
        const std::size_t n_cells = std::size_t(n_[0]) * std::size_t(n_[1]) * std::size_t(n_[2]);
        start_.assign(n_cells + 1, 0);
        std::vector<std::uint32_t> cell_of(points.size(), none);
        for (std::size_t k = 0; k < points.size(); ++k)
            if (finite(points[k])) {
                const Vec3& p = points[k];
                cell_of[k] = std::uint32_t(index(cell(0, p[0]), cell(1, p[1]), cell(2, p[2])));
                ++start_[cell_of[k] + 1];
            }
        for (std::size_t c = 0; c < n_cells; ++c) start_[c + 1] += start_[c];
        items_.resize(n);
        std::vector<std::uint32_t> next(start_.begin(), start_.end() - 1);
        for (std::size_t k = 0; k < points.size(); ++k)
            if (cell_of[k] != none) items_[next[cell_of[k]]++] = {points[k], std::uint32_t(k)};
    }

    // The nearest point to q if its squared distance is below bound_sq.
    Hit nearest(const Vec3& q, double bound_sq) const {
        Hit best{bound_sq, none};
        if (items_.empty()) return {kInf, none};
        if (bound_sq <= size_ * size_) {
            // A small ball: only the cells that meet its box (three a side at most,
            // as r <= size_, a fourth allowed for rounding), each with its squared
            // gap to q summed from the gaps along each axis.
            const double r = std::sqrt(bound_sq);
            std::array<int, 3> c0, c1;
            std::array<std::array<double, 4>, 3> gap;
            for (int d = 0; d < 3; ++d) {
                c0[d] = cell(d, q[d] - r);
                c1[d] = std::min(cell(d, q[d] + r), c0[d] + 3);
                for (int k = 0; k <= c1[d] - c0[d]; ++k) {
                    const double lo = lo_[d] + (c0[d] + k) * size_;
                    const double g = std::max(0.0, std::max(lo - q[d], q[d] - (lo + size_)));
                    gap[d][k] = g * g;
                }
            }
            for (int z = c0[2]; z <= c1[2]; ++z)
                for (int y = c0[1]; y <= c1[1]; ++y)
                    for (int x = c0[0]; x <= c1[0]; ++x) {
                        const double gap_sq = gap[0][x - c0[0]] + gap[1][y - c0[1]] + gap[2][z - c0[2]];
                        if (!beyond(gap_sq, best.dist_sq)) scan_points(q, index(x, y, z), best);
                    }
        } else {
            // Growing rings of cells around q's, nearest first, until the rest lie
            // beyond the best (or the bound).
            const std::array<int, 3> c{cell(0, q[0]), cell(1, q[1]), cell(2, q[2])};
            for (int r = 0;; ++r) {
                detail::for_ring(c, r, n_, [&](int x, int y, int z) { scan(q, x, y, z, best); });
                const double bound = detail::beyond_ring(lo_, size_, n_, c, r, q);  // to the cells not visited yet
                if (bound == kInf || beyond(bound * bound, best.dist_sq)) break;
            }
        }
        return best.index == none ? Hit{kInf, none} : best;
    }

private:
    struct Item {
        Vec3 p;
        std::uint32_t index;
    };
    static bool finite(const Vec3& p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }
    // True when points at squared distance lower_sq (rounded) cannot come out nearer than best_sq.
    static bool beyond(double lower_sq, double best_sq) { return lower_sq > best_sq * (1 + 1e-9); }
    int cell(int d, double v) const {
        const double x = (v - lo_[d]) / size_;
        if (!(x > 0)) return 0;
        if (x >= n_[d] - 1) return n_[d] - 1;
        return int(x);
    }
    std::size_t index(int x, int y, int z) const {
        return std::size_t(x) + std::size_t(n_[0]) * (std::size_t(y) + std::size_t(n_[1]) * std::size_t(z));
    }
    void scan(const Vec3& q, int x, int y, int z, Hit& best) const {
        const double gap_sq = detail::cell_gap_sq(lo_, size_, {x, y, z}, q);
        if (!beyond(gap_sq, best.dist_sq)) scan_points(q, index(x, y, z), best);
    }
    void scan_points(const Vec3& q, std::size_t i, Hit& best) const {
        for (std::uint32_t k = start_[i]; k < start_[i + 1]; ++k) {
            const Vec3 e = sub(q, items_[k].p);
            const double d = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
            if (d < best.dist_sq) best = {d, items_[k].index};
        }
    }

    Vec3 lo_{0, 0, 0};
    double size_ = 1;
    std::array<int, 3> n_{1, 1, 1};
    std::vector<std::uint32_t> start_;
    std::vector<Item> items_;  // in cell order, ascending index within a cell
};

// e = (distance from a vertex to the nearest point) - l, in h. Also returns, for
// each point, the smallest squared distance to a vertex whose nearest point it is
// (infinity for none): an upper bound on the point's distance to the surface.
// fan_start, fan_tri: the triangles around each vertex (detail::vertex_fans).
std::vector<double> measure_offset(const Mesh& m, const PointSet& points, const std::vector<std::size_t>& fan_start,
                                   const std::vector<std::uint32_t>& fan_tri, MeshQuality& q) {
    std::vector<double> near_vertex(points.size(), kInf);
    if (points.empty() || m.vertices.empty()) {
        q.offset_rms = q.offset_mean = q.offset_max = kNaN;
        return near_vertex;
    }
    // Cells of about l: the vertices lie about l from their nearest points.
    const PointGrid grid(points, q.offset);
    const std::size_t nv = m.vertices.size();
    std::vector<std::uint32_t> nearest(nv, PointGrid::none);  // each vertex's nearest point
    // Neighbouring vertices have nearby nearest points: the nearest points found
    // for the vertex's neighbours earlier in its run bound its search (any point
    // no farther than the bound is found, so the result is the same).
    constexpr std::size_t kRun = 2048;
    const std::ptrdiff_t runs = std::ptrdiff_t((nv + kRun - 1) / kRun);
    const auto& T = m.triangles;
#pragma omp parallel for schedule(dynamic, 1) if (std::ptrdiff_t(nv) > kParallel)
    for (std::ptrdiff_t r = 0; r < runs; ++r) {
        const std::size_t first = std::size_t(r) * kRun, last = std::min(nv, std::size_t(r + 1) * kRun);
        for (std::size_t v = first; v < last; ++v) {
            const Vec3& x = m.vertices[v];
            // The first neighbour met that has its nearest point will do: they all
            // lie within an edge of each other.
            double bound = kInf;
            for (std::size_t k = fan_start[v]; k < fan_start[v + 1] && bound == kInf; ++k)
                for (std::uint32_t u : T[fan_tri[k]])
                    if (u >= first && u < v && nearest[u] != PointGrid::none) {
                        const Vec3 d = sub(x, points[nearest[u]]);
                        bound = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                        break;
                    }
            // A little above the bound, so that the point that gave it is found again.
            bound += std::max(bound * 0x1p-50, std::numeric_limits<double>::denorm_min());
            PointGrid::Hit hit = grid.nearest(x, bound);
            if (hit.index == PointGrid::none && bound < kInf) hit = grid.nearest(x, kInf);
            nearest[v] = hit.index;
        }
    }
    // Summed in vertex order: the same figures for any number of threads.
    double sum = 0, sum_sq = 0, max_abs = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        double dist_sq = kInf;  // none only when no point or vertex is finite
        if (nearest[v] != PointGrid::none) {
            // The same sum as the search made.
            const Vec3 e = sub(m.vertices[v], points[nearest[v]]);
            dist_sq = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
            double& bound = near_vertex[nearest[v]];
            bound = std::min(bound, dist_sq);
        }
        const double e = (std::sqrt(dist_sq) - q.offset) / q.voxel;
        sum += e;
        sum_sq += e * e;
        max_abs = std::max(max_abs, std::fabs(e));
    }
    q.offset_mean = sum / double(nv);
    q.offset_rms = std::sqrt(sum_sq / double(nv));
    q.offset_max = max_abs;
    return near_vertex;
}

// The points' indices in Morton order of their position, so that queries in a row
// touch the same part of a spatial structure (far fewer cache misses).
std::vector<std::uint32_t> spatial_order(const PointSet& points) {
    Vec3 lo{kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf};
    for (const Vec3& p : points)
        for (int d = 0; d < 3; ++d) {
            lo[d] = std::min(lo[d], p[d]);
            hi[d] = std::max(hi[d], p[d]);
        }
    std::vector<std::uint64_t> keyed(points.size());
    const std::ptrdiff_t np = std::ptrdiff_t(points.size());
#pragma omp parallel for schedule(static) if (np > kParallel)
    for (std::ptrdiff_t n = 0; n < np; ++n) {
        std::uint32_t code = 0;
        for (int d = 0; d < 3; ++d) {
            const double x = hi[d] > lo[d] ? (points[n][d] - lo[d]) / (hi[d] - lo[d]) * 1024 : 0;
            const auto c = std::uint32_t(std::clamp(x, 0.0, 1023.0));  // NaN: 0 or 1023, still valid
            for (int b = 0; b < 10; ++b) code |= ((c >> b) & 1u) << (3 * b + d);
        }
        keyed[n] = std::uint64_t(code) << 32 | std::uint64_t(n);
    }
    std::sort(keyed.begin(), keyed.end());
    std::vector<std::uint32_t> order(points.size());
    for (std::size_t k = 0; k < keyed.size(); ++k) order[k] = std::uint32_t(keyed[k]);
    return order;
}

// The signed depth of the points below the surface, by the parity of a ray's
// crossings, in pieces of kPointChunk points (in the order of spatial_order, so
// that a piece's queries touch the same part of the grid).
class PointDepths {
public:
    static constexpr std::size_t kPointChunk = 256;
    struct Piece {
        double depth_min = kInf;        // the least depth among the points inside
        std::size_t parity_inside = 0;  // points inside by the parity of crossings
    };

    PointDepths(const Mesh& m, const PointSet& points) : mesh_(m), points_(points), order_(spatial_order(points)) {
        for (const Vec3& v : m.vertices)
            for (int d = 0; d < 3; ++d) {
                lo_[d] = std::min(lo_[d], v[d]);
                hi_[d] = std::max(hi_[d], v[d]);
            }
    }
    std::size_t pieces() const { return (points_.size() + kPointChunk - 1) / kPointChunk; }

    // depth[n] for the points of piece c. near_vertex[n] bounds point n's squared
    // distance to the surface (see measure_offset) or guesses it. Inside or not
    // by the side of its nearest triangle when `by_nearest_face` and the nearest point
    // lies inside that triangle's face (see face_side), else by a ray of its own.
    Piece measure(std::size_t c, const TriangleGrid& grid, const std::vector<double>& near_vertex,
                  bool by_nearest_face, std::vector<double>& depth) const {
        // Inside or not by the parity of crossings along a ray in a direction that no
        // grid-aligned edge of a marching-cubes mesh is parallel to.
        // Each ray heads for the nearer face of the mesh's box on every axis, to cut the walk short.
        const Vec3 dir = [] {
            const Vec3 d{0.5377, 0.3019, 0.7877};
            const double n = norm(d);
            return Vec3{d[0] / n, d[1] / n, d[2] / n};
        }();
        Piece piece;
        for (std::size_t k = c * kPointChunk; k < std::min(points_.size(), (c + 1) * kPointChunk); ++k) {
            const std::uint32_t n = order_[k];
            const Vec3& p = points_[n];
            // The vertex bound, widened far beyond the rounding of either distance.
            TriangleGrid::Closest near = grid.closest(p, near_vertex[n] * (1 + 1e-6));
            if (near.triangle == TriangleGrid::none) near = grid.closest(p);
            const double d = std::sqrt(near.dist_sq);
            Vec3 toward = dir;
            for (int a = 0; a < 3; ++a)
                if (p[a] - lo_[a] < hi_[a] - p[a]) toward[a] = -toward[a];
            const int side = by_nearest_face && near.triangle != TriangleGrid::none
                                 ? face_side(p, mesh_.vertices[mesh_.triangles[near.triangle][0]],
                                             mesh_.vertices[mesh_.triangles[near.triangle][1]],
                                             mesh_.vertices[mesh_.triangles[near.triangle][2]])
                                 : 0;
            const bool inside = side != 0 ? side < 0 : grid.count_crossings(p, toward) % 2 == 1;
            depth[n] = inside ? d : -d;
            if (inside) {
                piece.depth_min = std::min(piece.depth_min, d);
                ++piece.parity_inside;
            }
        }
        return piece;
    }

private:
    const Mesh& mesh_;
    const PointSet& points_;
    std::vector<std::uint32_t> order_;
    Vec3 lo_{kInf, kInf, kInf}, hi_{-kInf, -kInf, -kInf};  // the mesh's box
};

// The point figures from the pieces of PointDepths and, when given, count_points_inside
// (the pieces' own count is then the second opinion).
void measure_points(const std::vector<PointDepths::Piece>& pieces, std::vector<double>& depth,
                    std::optional<std::size_t> counted_inside, MeshQuality& q) {
    double depth_min = kInf;  // a minimum and a count: the same in any order
    std::size_t parity_inside = 0;
    for (const PointDepths::Piece& p : pieces) {
        depth_min = std::min(depth_min, p.depth_min);
        parity_inside += p.parity_inside;
    }
    const std::size_t points_inside = counted_inside.value_or(parity_inside);
    q.points_inside = points_inside;
    q.points_outside = q.points - q.points_inside;
    q.inside_fraction = q.points == 0 ? kNaN : double(q.points_inside) / double(q.points);
    q.inside_disagreements = parity_inside > q.points_inside ? parity_inside - q.points_inside
                                                             : q.points_inside - parity_inside;
    q.depth_min = depth_min < kInf ? depth_min / q.offset : kNaN;
    q.depth_p01 = percentile_01(depth) / q.offset;
}

// The wall figures from every vertex's wall (reordered).
void measure_walls(std::vector<double>& wall, MeshQuality& q) {
    const auto hits_end = std::partition(wall.begin(), wall.end(), [](double w) { return w < kInf; });
    q.wall_misses = std::size_t(wall.end() - hits_end);
    wall.erase(hits_end, wall.end());
    q.wall_min = wall.empty() ? kNaN : *std::min_element(wall.begin(), wall.end()) / q.voxel;
    q.wall_p01 = percentile_01(wall) / q.voxel;
    q.wall_min_2l = q.wall_min * q.voxel / (2 * q.offset);
    q.wall_p01_2l = q.wall_p01 * q.voxel / (2 * q.offset);
}

void measure_exact(const Mesh& m, const std::function<double(const Vec3&)>& exact, MeshQuality& q) {
    const std::ptrdiff_t nv = std::ptrdiff_t(m.vertices.size());
    std::vector<double> error(m.vertices.size());
#pragma omp parallel for schedule(dynamic, 1024) if (nv > kParallel)
    for (std::ptrdiff_t v = 0; v < nv; ++v) error[v] = std::fabs(exact(m.vertices[v])) / q.voxel;
    // Summed in vertex order: the same figures for any number of threads.
    double sum_sq = 0, max_abs = 0;
    for (double e : error) {
        sum_sq += e * e;
        max_abs = std::max(max_abs, e);
    }
    q.has_exact = true;
    q.exact_rms = nv ? std::sqrt(sum_sq / double(nv)) : kNaN;
    q.exact_max = nv ? max_abs : kNaN;
}

// The figures of measure_quality; the surface's (offset error, smoothness, the
// second inside test) only when `surface` is set.
MeshQuality measure(const char* who, const Mesh& mesh, const PointSet& points, double offset, double voxel,
                    bool surface, const std::function<double(const Vec3&)>& exact) {
    const auto started = std::chrono::steady_clock::now();
    if (!(offset > 0) || !(voxel > 0) || !std::isfinite(offset) || !std::isfinite(voxel))
        throw ParameterError(std::string(who) + ": offset and voxel must be positive (got " +
                             detail::format_number(offset) + " and " + detail::format_number(voxel) + ")");
    check_indices(mesh, who);
    MeshQuality q;
    q.vertices = mesh.vertices.size();
    q.triangles = mesh.triangles.size();
    q.points = points.size();
    q.offset = offset;
    q.voxel = voxel;
    q.has_surface = surface;
    if (!surface) q.offset_rms = q.offset_mean = q.offset_max = q.dihedral_rms = q.normal_noise = kNaN;

    if (mesh.triangles.size() > std::numeric_limits<std::uint32_t>::max())
        throw ResourceError(std::string(who) + ": more than 2^32 triangles");
    // Tasks on the team's threads, each part on one thread (their loops run
    // serially inside a task): the mesh's own figures (A) on one, the grid and
    // what needs no more (B) on the other, then the walls, which need only B,
    // and the depths of the points, which need A too, in pieces taken by
    // whichever thread is free. Every part is parallel in places only, or bound by
    // memory, so side by side they go faster than each with both threads. The
    // figures are the same either way: pieces write their own slots, and what
    // they add up is added up in a fixed order afterwards.
    // Without the surface figures (offset error, smoothness: about 0.3 of the
    // thread time on the bunny) the points' depth searches start from a guess
    // (twice the offset; a miss searches again without bound), and a point is
    // inside by its nearest triangle's side (a ray only where that is unclear):
    // one inside test, not two.
    const std::size_t nv = mesh.vertices.size();
    std::vector<double> near_vertex, wall(nv, kInf), depth(points.size());
    EdgeBuckets edges;
    std::optional<TriangleGrid> grid;
    std::optional<PointDepths> depths;
    std::vector<PointDepths::Piece> pieces;
    std::vector<Vec3> normals;
    std::size_t points_inside = 0;
    std::exception_ptr failed[3];  // A, B and the pieces: an exception may not leave a task
    const auto guarded = [&](std::exception_ptr& slot, auto&& part) {
        try {
            part();
        } catch (...) {
#pragma omp critical(snvr_measure_quality_failed)
            slot = std::current_exception();
        }
    };
#pragma omp parallel if (mesh.triangles.size() > 20000)
#pragma omp single
    {
#pragma omp task depend(out : near_vertex)
        guarded(failed[0], [&] {
            std::vector<std::uint32_t> piece;
            {
                std::vector<std::size_t> fan_start;
                std::vector<std::uint32_t> fan_tri;
                detail::vertex_fans(mesh, fan_start, fan_tri);
                detail::lower_edges(mesh, edges.start, edges.items);
                q.report = detail::check_mesh_unchecked(mesh, fan_start, fan_tri, edges.start, edges.items, &piece);
                if (surface)
                    near_vertex = measure_offset(mesh, points, fan_start, fan_tri, q);
                else
                    near_vertex.assign(points.size(), 4 * offset * offset);
            }
            measure_topology(mesh, edges, piece, q);
            if (surface) measure_dihedral(mesh, edges, q);
        });
        guarded(failed[1], [&] {
            grid.emplace(mesh);
            normals = unit_normals(mesh);
            if (surface && !points.empty()) points_inside = count_points_inside(mesh, points);
            depths.emplace(mesh, points);
            pieces.resize(depths->pieces());
        });
        if (!failed[1]) {
            const double eps = wall_epsilon(mesh);
            for (std::size_t first = 0; first < nv; first += kWallChunk)
#pragma omp task firstprivate(first)
                guarded(failed[2], [&] {
                    wall_thickness(mesh, *grid, normals, eps, first, std::min(nv, first + kWallChunk), wall);
                });
            for (std::size_t c = 0; c < pieces.size(); ++c)
#pragma omp task firstprivate(c) depend(in : near_vertex)
                guarded(failed[2], [&] {
                    if (!failed[0])
                        pieces[c] = depths->measure(c, *grid, near_vertex, !surface, depth);
                });
        }
#pragma omp taskwait
    }
    for (const std::exception_ptr& e : failed)
        if (e) std::rethrow_exception(e);
    const MeshReport& report = q.report;
    q.components = report.components;
    q.solids = report.solids;
    q.cavities = report.components - std::min(report.components, report.solids);
    q.closed = report.closed();
    q.manifold = report.manifold();
    q.oriented = report.oriented();
    if (surface) measure_normal_noise(normals, edges, q);
    EdgeBuckets().swap(edges);
    measure_points(pieces, depth, surface ? std::optional<std::size_t>(points_inside) : std::nullopt, q);
    measure_walls(wall, q);
    if (exact) measure_exact(mesh, exact, q);
    q.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return q;
}

}  // namespace

MeshQuality measure_quality(const Mesh& mesh, const PointSet& points, double offset, double voxel,
                            const std::function<double(const Vec3&)>& exact) {
    return measure("measure_quality", mesh, points, offset, voxel, true, exact);
}

MeshQuality measure_shell(const Mesh& mesh, const PointSet& points, double offset, double voxel) {
    return measure("measure_shell", mesh, points, offset, voxel, false, {});
}

double thinnest_wall(const Mesh& mesh) {
    check_indices(mesh, "thinnest_wall");
    const TriangleGrid grid(mesh);
    const std::vector<Vec3> normals = unit_normals(mesh);
    const double eps = wall_epsilon(mesh);
    const std::size_t nv = mesh.vertices.size();
    std::vector<double> wall(nv, kInf);
#pragma omp parallel for schedule(dynamic, 1) if (std::ptrdiff_t(nv) > kParallel)
    for (std::ptrdiff_t c = 0; c < std::ptrdiff_t((nv + kWallChunk - 1) / kWallChunk); ++c)
        wall_thickness(mesh, grid, normals, eps, std::size_t(c) * kWallChunk,
                       std::min(nv, std::size_t(c + 1) * kWallChunk), wall);
    return wall.empty() ? kInf : *std::min_element(wall.begin(), wall.end());
}

namespace {

std::string fixed(double v, int digits = 3) {
    if (std::isnan(v)) return "n/a";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    return buf;
}

const char* yes_no(bool b) { return b ? "yes" : "no"; }

}  // namespace

std::string format_quality(const MeshQuality& q) {
    std::string s;
    s += "mesh:        " + std::to_string(q.vertices) + " vertices, " + std::to_string(q.triangles) +
         " triangles; closed " + yes_no(q.closed) + ", manifold " + yes_no(q.manifold) + ", oriented " +
         yes_no(q.oriented) + "\n";
    s += "pieces:      " + std::to_string(q.solids) + " solid, " + std::to_string(q.cavities) + " cavities (" +
         std::to_string(q.components) + " components); genus " + std::to_string(q.genus);
    if (q.open_components) s += " (" + std::to_string(q.open_components) + " open components left out)";
    s += "\n";
    s += "points:      " + std::to_string(q.points_inside) + " of " + std::to_string(q.points) + " inside (" +
         fixed(100 * q.inside_fraction, 2) + "%), " + std::to_string(q.points_outside) + " outside\n";
    s += "depth:       min " + fixed(q.depth_min) + " l (inside points), 1st percentile " + fixed(q.depth_p01) +
         " l (all, signed)";
    if (q.inside_disagreements) s += "; inside tests disagree on " + std::to_string(q.inside_disagreements);
    s += "\n";
    if (q.has_surface) {
        s += "offset err:  RMS " + fixed(q.offset_rms) + " h, mean " + fixed(q.offset_mean) + " h, max |e| " +
             fixed(q.offset_max) + " h   (l = " + detail::format_number(q.offset) +
             ", h = " + detail::format_number(q.voxel) + ")\n";
        s += "smoothness:  dihedral RMS " + fixed(q.dihedral_rms, 2) + " deg (" + std::to_string(q.interior_edges) +
             " interior edges), normal noise " + fixed(q.normal_noise, 2) + " deg\n";
    }
    s += "walls:       min " + fixed(q.wall_min) + " h = " + fixed(q.wall_min_2l) + " x 2l, 1st percentile " +
         fixed(q.wall_p01) + " h = " + fixed(q.wall_p01_2l) + " x 2l";
    if (q.wall_misses) s += "; " + std::to_string(q.wall_misses) + " rays met nothing";
    s += "\n";
    if (q.has_exact) s += "exact error: RMS " + fixed(q.exact_rms, 4) + " h, max " + fixed(q.exact_max, 4) + " h\n";
    s += "measured in " + fixed(q.seconds, 2) + " s\n";
    return s;
}

std::string quality_json(const MeshQuality& q) {
    std::string s = "{";
    const auto key = [&](const char* name) {
        if (s.size() > 1) s += ',';
        s += '"';
        s += name;
        s += "\":";
    };
    const auto count = [&](const char* name, std::size_t v) {
        key(name);
        s += std::to_string(v);
    };
    const auto number = [&](const char* name, double v) {
        key(name);
        if (std::isfinite(v))
            detail::append_number(s, v);
        else
            s += "null";
    };
    const auto flag = [&](const char* name, bool v) {
        key(name);
        s += v ? "true" : "false";
    };
    count("vertices", q.vertices);
    count("triangles", q.triangles);
    count("points", q.points);
    number("offset", q.offset);
    number("voxel", q.voxel);
    count("components", q.components);
    count("solids", q.solids);
    count("cavities", q.cavities);
    flag("closed", q.closed);
    flag("manifold", q.manifold);
    flag("oriented", q.oriented);
    key("genus");
    s += std::to_string(q.genus);
    count("open_components", q.open_components);
    count("points_inside", q.points_inside);
    count("points_outside", q.points_outside);
    number("inside_fraction", q.inside_fraction);
    number("depth_min_l", q.depth_min);
    number("depth_p01_l", q.depth_p01);
    if (q.has_surface) {
        count("inside_disagreements", q.inside_disagreements);
        number("offset_rms_h", q.offset_rms);
        number("offset_mean_h", q.offset_mean);
        number("offset_max_h", q.offset_max);
        number("dihedral_rms_deg", q.dihedral_rms);
        count("interior_edges", q.interior_edges);
        number("normal_noise_deg", q.normal_noise);
    }
    number("wall_min_h", q.wall_min);
    number("wall_p01_h", q.wall_p01);
    number("wall_min_2l", q.wall_min_2l);
    number("wall_p01_2l", q.wall_p01_2l);
    count("wall_misses", q.wall_misses);
    if (q.has_exact) {
        number("exact_rms_h", q.exact_rms);
        number("exact_max_h", q.exact_max);
    }
    number("seconds", q.seconds);
    s += '}';
    return s;
}

}  // namespace snvr
