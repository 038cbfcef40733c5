// A uniform grid over a mesh's triangles for the two queries the quality measures
// need: the closest point of the surface to a point, and where a ray meets the
// surface. Each cell lists the triangles whose bounding box meets it.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
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
    // The triangle nearest to p (p may lie anywhere, inside the grid or not).
    Closest closest(const Vec3& p) const;

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

private:
    // Walks the cells the ray passes, in order, calling visit(first, last, t_exit)
    // for each cell's triangle list; stops when visit returns false.
    template <class Visit>
    void walk(const Vec3& origin, const Vec3& dir, const Visit& visit) const;

    int cell(int d, double v) const;
    std::size_t index(int x, int y, int z) const {
        return std::size_t(x) + std::size_t(n_[0]) * (std::size_t(y) + std::size_t(n_[1]) * std::size_t(z));
    }

    const Mesh& mesh_;
    Vec3 lo_{0, 0, 0}, hi_{0, 0, 0};
    double size_ = 1;  // cell edge length
    std::array<int, 3> n_{0, 0, 0};
    std::vector<std::uint32_t> start_;  // cell c lists items_[start_[c] .. start_[c + 1])
    std::vector<std::uint32_t> items_;
};

// Distance squared from p to the triangle (a, b, c), degenerate triangles included.
double point_triangle_dist_sq(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace snvr
