#include "distance_mc_shell.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <nanoflann.hpp>
#include <string>

#include "band_cells.hpp"
#include "snvr/error.hpp"
#include "snvr/field.hpp"
#include "snvr/mesh.hpp"
#include "snvr/stopwatch.hpp"

namespace snvr::peers {

namespace {

// Where the field stops following the distance: |l - d| is clipped to this many
// voxels. A grid cube the surface crosses has every corner within its diagonal
// (sqrt 3 voxels) of the surface, and the distance changes by at most a voxel per
// voxel, so no corner the mesher reads is clipped; beyond it one shared brick stands
// for every cell.
constexpr double kClipVoxels = 2.0;

struct PointsAdaptor {
    const PointSet& points;
    std::size_t kdtree_get_point_count() const { return points.size(); }
    double kdtree_get_pt(std::size_t n, std::size_t axis) const { return points[n][axis]; }
    template <class Box>
    bool kdtree_get_bbox(Box&) const { return false; }
};

using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointsAdaptor>, PointsAdaptor, 3, std::uint32_t>;

// The nearest point's squared distance, if under a bound: farther than l plus the
// clip the field is clipped anyway, and the bound lets the search prune.
class NearestSquared {
public:
    explicit NearestSquared(double bound_squared) : best_(bound_squared) {}
    bool full() const { return true; }
    bool addPoint(double distance_squared, std::uint32_t) {
        best_ = std::min(best_, distance_squared);
        return true;
    }
    double worstDist() const { return best_; }

private:
    double best_;
};

}  // namespace

Domain distance_grid(const PointSet& points, double voxel, double offset) {
    if (points.empty()) throw InputError("the point set is empty");
    if (!(voxel > 0) || !(offset > 0)) throw ParameterError("the voxel and the offset must be positive");
    Vec3 lo = points[0], hi = lo;
    for (const Vec3& p : points)
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
    Domain g;
    g.h = voxel;
    int n[3];
    for (int a = 0; a < 3; ++a) {
        const double cells = (hi[a] - lo[a] + 2 * offset) / voxel + 2 * kDistancePadCells;
        if (!(cells < 65536))  // 2^16 per axis keeps the bricks' index in 32 bits
            throw ParameterError("the grid would have " + std::to_string(cells) + " cells along " + std::string(1, "xyz"[a]) +
                                 ": raise the voxel");
        n[a] = int(std::ceil(cells - 1e-9));
        g.origin[a] = 0.5 * (lo[a] + hi[a]) - 0.5 * n[a] * voxel;
    }
    g.nx = n[0], g.ny = n[1], g.nz = n[2];
    return g;
}

DistanceShell distance_mc_shell(const PointSet& points, double voxel, double offset) {
    DistanceShell shell;
    shell.grid = distance_grid(points, voxel, offset);
    const Domain& g = shell.grid;
    Stopwatch clock;

    const PointsAdaptor adaptor{points};
    const KdTree tree(3, adaptor);
    shell.seconds_index = clock.lap();

    const double clip = kClipVoxels * voxel, reach = offset + clip;
    const BandCells band = band_cells(points, g, reach);
    shell.band_bricks = band.masks.size();
    shell.band_cells = band.cells();
    shell.seconds_band = clock.lap();

    // Stored brick 0 is every brick the band misses; the band's bricks follow it.
    std::vector<std::uint32_t> table(band.slot.size());
    for (std::size_t b = 0; b < band.slot.size(); ++b) table[b] = band.slot[b] == BandCells::kNone ? 0 : band.slot[b] + 1;
    std::vector<float> stored((band.masks.size() + 1) * Field::kBrickCells, float(-clip));
    const std::uint32_t bx = std::uint32_t(band.bricks_x), by = std::uint32_t(band.bricks_y);
#pragma omp parallel for schedule(dynamic, 8)
    for (std::int64_t s = 0; s < std::int64_t(band.masks.size()); ++s) {
        const std::uint32_t b = band.brick[std::size_t(s)];
        const int i0 = int(b % bx) * 8, j0 = int(b / bx % by) * 8, k0 = int(b / bx / by) * 8;
        float* values = &stored[(std::size_t(s) + 1) * Field::kBrickCells];
        for (int z = 0; z < 8; ++z)
            for (std::uint64_t bits = band.masks[std::size_t(s)][std::size_t(z)]; bits; bits &= bits - 1) {
                const int xy = __builtin_ctzll(bits), x = xy % 8, y = xy / 8;
                const Vec3 centre = g.cell_center(i0 + x, j0 + y, k0 + z);
                NearestSquared nearest(reach * reach);
                tree.findNeighbors(nearest, centre.data(), nanoflann::SearchParams());
                values[xy + 64 * z] = float(std::clamp(offset - std::sqrt(nearest.worstDist()), -clip, clip));
            }
    }
    shell.seconds_distance = clock.lap();

    const Field field = Field::from_bricks(g.nx, g.ny, g.nz, std::move(table), std::move(stored));
    shell.mesh = extract_dual_isosurface(field, g, 0.0, Interpolation::Linear);
    shell.seconds_mesh = clock.lap();
    return shell;
}

}  // namespace snvr::peers
