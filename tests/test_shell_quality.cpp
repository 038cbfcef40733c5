// The shell at the default settings, judged as a printer user would: pieces, cavities,
// points inside and their depth, walls, distance from the offset and roughness, on cases
// where the paper's defaults failed (fused sheets with trapped cavities, beads shrinking
// away from undersampled points, grid terraces on a real scan at a finer grid).
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

#include "snvr/snvr.hpp"
#include "snvr/shapes.hpp"

using namespace snvr;

namespace {

// Bounds below hold at the defaults with some room (the figures are printed); the
// paper's fixed dt (terraces, fused sheets, shrunk beads) fails them.
MeshQuality shell_quality(const char* name, const PointSet& points, double voxel, double offset,
                          const std::function<double(const Vec3&)>& exact = {}, int steps = -1) {
    Parameters p;
    p.voxel = voxel;
    p.offset = offset;
    p.device = "openmp";
    if (steps >= 0) p.steps = steps;
    const Result r = reconstruct(points, p);
    // Judged as an STL holds it: float32 coordinates.
    const MeshQuality q = measure_quality(as_written(shell_mesh(r, points), "shell.stl"), points, offset, voxel, exact);
    std::printf("%s: grid %dx%dx%d, %zu steps\n%s", name, r.domain.nx, r.domain.ny, r.domain.nz, r.steps.size(),
                format_quality(q).c_str());
    CHECK(q.closed);
    CHECK(q.manifold);
    CHECK(q.oriented);
    CHECK(q.report.zero_area_triangles == 0);  // slicers report them as errors
    return q;
}

}  // namespace

TEST_CASE("two sheets 3l apart stay two slabs without cavities") {
    // h = 1/128, l = 2.5 h: the paper's 8 steps fused them into one solid holding 133 cavities.
    const double h = 1.0 / 128, l = 2.5 * h;
    const PointSet points = shapes::parallel_sheets({0.5, 0.5, 0.5}, 0.5, 3 * l, h / 2);
    const MeshQuality q = shell_quality("sheets", points, h, l);
    CHECK(q.solids == 2);
    CHECK(q.cavities == 0);
    CHECK(q.genus == 0);
    CHECK(q.points_inside == points.size());
    CHECK(q.depth_min >= 0.8);
    CHECK(q.depth_p01 >= 0.8);
    CHECK(q.wall_p01_2l >= 0.8);
    CHECK(q.dihedral_rms <= 5.5);
    CHECK(q.normal_noise <= 1.4);
}

TEST_CASE("an undersampled closed scan keeps every point inside") {
    // Torus sampled at 1.7 l: each point's bead is a third of the shell; the free flow
    // shrank them away (98% of the points outside).
    const double l = 0.02, spacing = 1.7 * l;
    const PointSet points = shapes::torus({0.5, 0.5, 0.5}, 0.3, 0.12, spacing);
    const MeshQuality q = shell_quality("undersampled torus", points, 0.9 / 96, l);
    CHECK(q.solids == 1);
    CHECK(q.genus == 2);  // the torus's outer and inner sheets
    CHECK(q.points_inside == points.size());
    CHECK(q.depth_min >= 0.65);  // the offset is below the gap: l - 0.8 l would not cover the beads' gaps anyway
    CHECK(q.dihedral_rms <= 9.5);
}

TEST_CASE("an open non-orientable strip is one slab") {
    const double h = 1.0 / 96, l = 2.5 * h;
    const PointSet points = shapes::mobius_strip({0.5, 0.5, 0.5}, 0.3, 0.25, h / 2);
    const MeshQuality q = shell_quality("mobius", points, h, l);
    CHECK(q.solids == 1);
    CHECK(q.cavities == 0);
    CHECK(q.points_inside == points.size());
    CHECK(q.depth_min >= 0.8);
    CHECK(q.depth_p01 >= 0.8);
    CHECK(q.dihedral_rms <= 6.5);
    CHECK(q.normal_noise <= 1.5);
}

TEST_CASE("a noisy sphere comes out smooth and no farther from the exact offset") {
    // Gaussian noise of 0.3 voxels, l = 6.4 voxels (the case). The union of balls
    // around noisy points sits outside the exact offset by about the noise's local
    // maximum (0.5 h here, for any tool that starts from it); the flow must smooth the
    // surface without moving it farther.
    const double h = 1.0 / 96, l = 6.4 * h, r = 0.3;
    const PointSet points = shapes::noisy_sphere({0.5, 0.5, 0.5}, r, h / 2, 0.3 * h);
    const auto exact = [=](const Vec3& v) { return std::abs(std::abs(shapes::sphere_distance(v, {0.5, 0.5, 0.5}, r)) - l); };
    const MeshQuality q = shell_quality("noisy sphere", points, h, l, exact);
    const MeshQuality raw = shell_quality("noisy sphere, initial field", points, h, l, exact, 0);
    CHECK(q.solids == 1);
    CHECK(q.cavities == 1);
    CHECK(q.points_inside == points.size());
    CHECK(q.exact_rms <= 1.05 * raw.exact_rms);
    CHECK(q.dihedral_rms <= 0.5 * raw.dihedral_rms);
    CHECK(q.normal_noise <= 0.5 * raw.normal_noise);
}

TEST_CASE("ordinary outputs: an open half sphere and the cactus scan at 96 cells") {
    // Issue 10 found 4 zero-area triangles in each of these STL files (an earlier mesher).
    const PointSet half = shapes::half_sphere({0.5, 0.5, 0.5}, 0.3, 0.005);
    const double h = 0.7 / 96;
    const MeshQuality hq = shell_quality("half sphere at 96", half, h, 2.5 * h);
    CHECK(hq.points_inside == half.size());
    const PointSet cactus = read_points(std::string(SNVR_DATA_DIR) + "/cactus.ply");
    Parameters p;
    p.resolution = 96;
    p.device = "openmp";
    const Result r = reconstruct(cactus, p);
    const MeshQuality cq =
        measure_shell(as_written(shell_mesh(r, cactus), "cactus.stl"), cactus, r.offset, r.domain.h);
    CHECK(cq.closed);
    CHECK(cq.manifold);
    CHECK(cq.report.zero_area_triangles == 0);
}

TEST_CASE("the bunny scan: the same quality per voxel at two resolutions") {
    // Offset 2.5 voxels at each grid: the paper's fixed dt gave terraces at the finer one.
    const PointSet points = read_points(std::string(SNVR_DATA_DIR) + "/bunny.ply");
    for (int cells : {96, 160}) {
        CAPTURE(cells);
        const double h = 0.155699 / cells, l = 2.5 * h;
        const MeshQuality q = shell_quality(("bunny at " + std::to_string(cells)).c_str(), points, h, l);
        CHECK(q.solids == 1);
        CHECK(q.points_inside == points.size());
        CHECK(q.depth_min >= 0.8);  // the tube's inner wall, kept by the mesh too (keep_points_deep)
        CHECK(q.depth_p01 >= 0.8);
        CHECK(q.wall_p01_2l >= 0.8);
        CHECK(std::abs(q.offset_mean) <= 0.05);
        CHECK(q.dihedral_rms <= (cells < 128 ? 6.0 : 4.6));
        CHECK(q.normal_noise <= (cells < 128 ? 2.3 : 1.7));
    }
}

TEST_CASE("the horse scan: lifted patches keep every point deep without folding the surface") {
    // Voxel = extent / 256, l = 2.5 voxels: lifts of a few hundredths of a voxel along
    // neighbouring normals turned slivers over (thinnest wall 0.0005 x 2l) before the
    // lifts were untangled.
    const PointSet points = read_points(std::string(SNVR_DATA_DIR) + "/horse.ply");
    const double h = 0.000716176, l = 2.5 * h;
    const MeshQuality q = shell_quality("horse at 256", points, h, l);
    CHECK(q.solids == 1);
    CHECK(q.points_inside == points.size());
    CHECK(q.depth_min >= 0.8);
    CHECK(q.wall_min_2l >= 0.1);
    CHECK(q.wall_p01_2l >= 0.8);
}
