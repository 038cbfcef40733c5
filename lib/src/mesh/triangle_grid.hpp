// A uniform grid over a mesh's triangles for the two queries the quality measures
// need: the closest point of the surface to a point, and where a ray meets the
// surface. Each cell lists the triangles whose bounding box meets it, each with the
// part of that box near the cell beside it in bytes, so that four candidates at a time
// are dismissed before the exact test; every query still returns what testing all
// triangles would.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "snvr/geometry.hpp"

namespace snvr {

class TriangleGrid {
public:
    // Keeps a reference to mesh; its indices must be valid (callers check).
    explicit TriangleGrid(const Mesh& mesh);

    static constexpr std::uint32_t none = std::uint32_t(-1);

    struct Closest {
        double dist_sq;          // infinity when the mesh has no triangles
        std::uint32_t triangle;  // none when the mesh has no triangles
    };
    // The triangle nearest to p (p may lie anywhere, inside the grid or not; of several at
    // one distance the lowest numbered) if its squared distance is below bound_sq, else
    // {infinity, none}. A tight bound (say
    // the distance to a vertex known to be near) spares most of the search.
    Closest closest(const Vec3& p, double bound_sq = std::numeric_limits<double>::infinity()) const;

    // The triangles whose box may come within r of p (every triangle within r, and a
    // few more), each once, into `out`. seen: a bit a triangle, every one clear (and so
    // again on return), kept by the caller from call to call: made afresh for each, it
    // cost a page fault per 32 K triangles every time.
    void near(const Vec3& p, double r, std::vector<std::uint32_t>& out, std::vector<std::uint64_t>& seen) const;

    struct Hit {
        double t;                // ray parameter of the hit (distance for a unit dir)
        std::uint32_t triangle;  // none when the ray meets nothing
    };
    // The first triangle met by origin + t dir with t > t_min, ignoring the triangles
    // that use vertex `skip_vertex` (pass none to ignore none).
    Hit first_hit(const Vec3& origin, const Vec3& dir, double t_min, std::uint32_t skip_vertex = none) const;

    // How many distinct triangles the ray origin + t dir, t > 0, crosses. A ray
    // through an edge may count it 0 or 2 times: pick a direction no edge is likely
    // to be parallel to. (first_hit widens triangles by a sliver instead.)
    std::size_t count_crossings(const Vec3& origin, const Vec3& dir) const;

    // The grid as plain arrays, for a device that walks it as first_hit does
    // (kernels/wall_rays.cl): cell (x, y, z), c = x + n0 (y + n1 z), lists items start[c]
    // .. start[c + 1]; item k is triangle items[k], its box near the cell the six bytes
    // boxes[j stride + k] (lo x y z, hi x y z; see plane()). No cells where the mesh has
    // no triangles.
    struct Cells {
        Vec3 lo{0, 0, 0};
        double size = 1, inv_size = 1, margin = 0;
        std::array<int, 3> n{0, 0, 0};
        const std::uint32_t* start = nullptr;  // cells + 1 entries
        std::size_t cells = 0;
        const std::uint32_t* items = nullptr;
        const std::uint8_t* boxes = nullptr;
        std::size_t stride = 0;  // items, and the padding after them
    };
    Cells cells() const;

private:
    // The construction's steps: the box, cell size and margins; each cell's triangles.
    void size_cells();
    void fill_cells();
    template <class Visit>
    void for_box_cells(std::size_t t, int z_lo, int z_hi, Visit&& visit) const;
    class RayBoxes;
    class PointBoxes;

    // Walks the cells the ray passes, in order, calling visit(first, last, t_exit, cell)
    // with each nonempty cell's item range and coordinates; stops when visit returns false.
    // inv: 1 / dir on each axis.
    template <class Visit>
    void walk(const Vec3& origin, const Vec3& dir, const std::array<double, 3>& inv, const Visit& visit) const;

    // Tests the triangles of cell (x, y, z) against p, keeping the nearest in best.
    void scan_cell(const Vec3& p, PointBoxes& boxes, int x, int y, int z, Closest& best) const;
    // Squared distance from p to cell (x, y, z).
    double cell_gap_sq(const Vec3& p, int x, int y, int z) const;
    // True when something at squared distance lower_sq (a lower bound, rounded)
    // cannot come out nearer than best_sq once computed exactly.
    bool beyond(double lower_sq, double best_sq) const { return lower_sq > best_sq * (1 + 1e-9) + tiny_sq_; }

    int cell(int d, double v) const;
    std::size_t index(int x, int y, int z) const {
        return std::size_t(x) + std::size_t(n_[0]) * (std::size_t(y) + std::size_t(n_[1]) * std::size_t(z));
    }
    // Box coordinate k (0-2 lo x y z, 3-5 hi) of every item: the part of the triangle's
    // box near the item's cell, in steps of 1 / kBoxSteps cell from kBoxLow steps below
    // the cell's low corner (box_step() rounds it outwards).
    const std::uint8_t* plane(int k) const { return item_boxes_.get() + std::size_t(k) * stride_; }

    const Mesh& mesh_;
    Vec3 lo_{0, 0, 0}, hi_{0, 0, 0};
    double size_ = 1, inv_size_ = 1;  // cell edge length and its inverse
    double margin_ = 0;               // boxes count as this much larger in ray tests (cells)
    double tiny_sq_ = 0;              // absolute slack of the distance pruning
    std::array<int, 3> n_{0, 0, 0};
    std::vector<std::uint32_t> start_;  // cell c lists items [start_[c], start_[c + 1])
    // Each item's triangle (ascending within a cell), and the six planes of stride_
    // bytes of plane(): 10 bytes an item. Plain new[]: the arrays are large, and every
    // slot is written once (a zeroing pass would cost as much again).
    std::unique_ptr<std::uint32_t[]> items_;
    std::unique_ptr<std::uint8_t[]> item_boxes_;
    std::size_t stride_ = 0;
};

// Distance squared from p to the triangle (a, b, c), degenerate triangles included.
double point_triangle_dist_sq(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// Which side of the triangle (a, b, c) p lies on, when p's nearest point on it lies
// inside the face, clear of its edges and corners: +1 on the side its normal
// (counter-clockwise a, b, c) points to, -1 on the other; 0 when the nearest point
// is on or near an edge or corner, p (nearly) in the plane, or the triangle degenerate.
// For the triangle nearest to p in a closed, oriented mesh, +1 means outside.
int face_side(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace snvr
