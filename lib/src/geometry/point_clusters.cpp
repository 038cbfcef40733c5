// How many pieces the points themselves suggest: a shell of offset l joins points
// closer than 2l, so clusters linked at that distance bound the pieces a correct
// result can have (two sheets per closed piece, one per open piece).
#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <vector>

#include "geometry/point_clusters.hpp"
#include "snvr/reconstruct.hpp"

namespace snvr {

namespace {

std::size_t find_root(std::vector<std::size_t>& parent, std::size_t n) {
    while (parent[n] != n) n = parent[n] = parent[parent[n]];
    return n;
}

bool finite(const Vec3& p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

}  // namespace

// Points are linked when (dx^2 + dy^2) + dz^2 < link_distance^2, the test and the
// sum PointIndex::for_each_within make. A uniform grid of cells about
// link_distance / sqrt(3) wide, so that the points of a cell are usually all
// linked to each other (checked on the box they span) and join as one set without
// a look at their pairs; two cells then need a look only while they are in
// different sets, and only until one linked pair is found. Dense scans have
// hundreds of points within a link: looking at every pair cost more than the
// reconstruction.
std::vector<std::size_t> point_cluster_labels(const PointSet& points, double link_distance) {
    if (points.empty()) return {};
    const double link_sq = link_distance * link_distance;
    std::vector<std::size_t> parent(points.size());
    std::iota(parent.begin(), parent.end(), std::size_t(0));
    const auto unite = [&](std::size_t a, std::size_t b) {
        a = find_root(parent, a);
        b = find_root(parent, b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    };
    // Points with a coordinate that is not finite are never linked (their squared
    // distances are not finite); nor is anything when link_sq is not above 0.
    Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
    std::size_t n = 0;
    for (const Vec3& p : points)
        if (finite(p)) {
            ++n;
            for (int d = 0; d < 3; ++d) {
                lo[d] = std::min(lo[d], p[d]);
                hi[d] = std::max(hi[d], p[d]);
            }
        }
    if (n > 1 && link_sq > 0) {
        // Not many more cells than points: a sparse cloud gets wider cells, whose
        // points are then not all linked, and links reach more than two cells less often.
        double size = std::max(std::sqrt(link_sq / 3), 1e-9 * std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]));
        std::array<int, 3> cells{1, 1, 1};
        for (;;) {
            double total = 1;
            for (int d = 0; d < 3; ++d) {
                cells[d] = std::max(1, int(std::min(1e9, std::ceil((hi[d] - lo[d]) / size))));
                total *= cells[d];
            }
            if (!(size < INFINITY) || total <= 8.0 * double(n) + 4096) break;
            size *= 1.25;
        }
        // Linked points lie at most `reach` cells apart along each axis, 2 or 1 as
        // size >= link / sqrt(3) (the 1e-9: the rounding of a cell index).
        const int reach = int(std::ceil(std::sqrt(link_sq) * (1 + 1e-9) / size));
        const auto cell = [&](int d, double v) {
            const double x = (v - lo[d]) / size;
            return !(x > 0) ? 0 : x >= cells[d] - 1 ? cells[d] - 1 : int(x);
        };
        const std::size_t n_cells = std::size_t(cells[0]) * std::size_t(cells[1]) * std::size_t(cells[2]);
        const auto index = [&](int x, int y, int z) {
            return std::size_t(x) + std::size_t(cells[0]) * (std::size_t(y) + std::size_t(cells[1]) * std::size_t(z));
        };
        // The points by cell (coordinates beside their indices, for locality).
        constexpr std::size_t none = std::size_t(-1);
        std::vector<std::size_t> start(n_cells + 1, 0), cell_of(points.size(), none);
        for (std::size_t k = 0; k < points.size(); ++k)
            if (finite(points[k])) {
                cell_of[k] = index(cell(0, points[k][0]), cell(1, points[k][1]), cell(2, points[k][2]));
                ++start[cell_of[k] + 1];
            }
        for (std::size_t c = 0; c < n_cells; ++c) start[c + 1] += start[c];
        struct Item {
            Vec3 p;
            std::size_t index;
        };
        std::vector<Item> items(n);
        {
            std::vector<std::size_t> next(start.begin(), start.end() - 1);
            for (std::size_t k = 0; k < points.size(); ++k)
                if (cell_of[k] != none) items[next[cell_of[k]]++] = {points[k], k};
        }
        const auto dist_sq = [](const Vec3& a, const Vec3& b) {
            const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
            return dx * dx + dy * dy + dz * dz;
        };
        // Each cell's box (of its points) and whether its points are all one set, at
        // the cell's first item: a slot per point, not per cell (a sparse cloud has
        // up to 8 cells a point).
        struct Box {
            Vec3 lo, hi;
        };
        std::vector<Box> box(n);
        std::vector<char> one_set(n, 0);
        for (std::size_t c = 0; c < n_cells; ++c) {
            if (start[c] == start[c + 1]) continue;
            Box b{items[start[c]].p, items[start[c]].p};
            for (std::size_t i = start[c]; i < start[c + 1]; ++i)
                for (int d = 0; d < 3; ++d) {
                    b.lo[d] = std::min(b.lo[d], items[i].p[d]);
                    b.hi[d] = std::max(b.hi[d], items[i].p[d]);
                }
            box[start[c]] = b;
            // Far below the link by more than any rounding of a pair's distance:
            // every pair in the box is linked.
            if (dist_sq(b.lo, b.hi) < link_sq * (1 - 1e-9)) {
                one_set[start[c]] = 1;
                for (std::size_t i = start[c] + 1; i < start[c + 1]; ++i) unite(items[start[c]].index, items[i].index);
            } else {
                for (std::size_t i = start[c]; i < start[c + 1]; ++i)
                    for (std::size_t j = i + 1; j < start[c + 1]; ++j)
                        if (dist_sq(items[i].p, items[j].p) < link_sq) unite(items[i].index, items[j].index);
            }
        }
        // The squared gap between two boxes, shrunk far beyond rounding: no pair
        // across them is linked when it is at least link_sq.
        const auto gap_sq = [](const Box& a, const Box& b) {
            double g = 0;
            for (int d = 0; d < 3; ++d) {
                const double e = std::max({0.0, a.lo[d] - b.hi[d], b.lo[d] - a.hi[d]});
                g += e * e;
            }
            return g * (1 - 1e-9);
        };
        for (int z = 0; z < cells[2]; ++z)
            for (int y = 0; y < cells[1]; ++y)
                for (int x = 0; x < cells[0]; ++x) {
                    const std::size_t c = index(x, y, z);
                    if (start[c] == start[c + 1]) continue;
                    // With the neighbours that come after it in (z, y, x) order.
                    for (int dz = 0; dz <= reach; ++dz)
                        for (int dy = -reach; dy <= reach; ++dy)
                            for (int dx = -reach; dx <= reach; ++dx) {
                                if (dz == 0 && (dy < 0 || (dy == 0 && dx <= 0))) continue;
                                const int nx = x + dx, ny = y + dy, nz = z + dz;
                                if (nx < 0 || ny < 0 || nx >= cells[0] || ny >= cells[1] || nz >= cells[2]) continue;
                                const std::size_t o = index(nx, ny, nz);
                                if (start[o] == start[o + 1] || gap_sq(box[start[c]], box[start[o]]) >= link_sq) continue;
                                // Two cells of one set each: one link joins them, and
                                // once joined nothing between them can change.
                                const bool whole = one_set[start[c]] && one_set[start[o]];
                                if (whole && find_root(parent, items[start[c]].index) ==
                                                 find_root(parent, items[start[o]].index))
                                    continue;
                                bool joined = false;
                                for (std::size_t i = start[c]; i < start[c + 1] && !joined; ++i)
                                    for (std::size_t j = start[o]; j < start[o + 1]; ++j)
                                        if (dist_sq(items[i].p, items[j].p) < link_sq) {
                                            unite(items[i].index, items[j].index);
                                            if (whole) {
                                                joined = true;
                                                break;
                                            }
                                        }
                            }
                }
    }
    for (std::size_t k = 0; k < points.size(); ++k) parent[k] = find_root(parent, k);
    return parent;
}

std::size_t count_point_clusters(const PointSet& points, double link_distance) {
    const std::vector<std::size_t> label = point_cluster_labels(points, link_distance);
    std::size_t roots = 0;
    for (std::size_t k = 0; k < label.size(); ++k) roots += label[k] == k;
    return roots;
}

}  // namespace snvr
