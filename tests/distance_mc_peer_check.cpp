// The plain distance + marching cubes peer (bench/peers) that the points benchmark
// measures against: its band holds every cell the offset surface needs, and its shell
// is closed with every vertex at distance l from the points to a small part of a voxel.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "band_cells.hpp"
#include "cli_run.hpp"
#include "distance_mc_shell.hpp"
#include "snvr/mesh_io.hpp"
#include "snvr/point_io.hpp"
#include "snvr/mesh.hpp"
#include "snvr/quality.hpp"
#include "snvr/shapes.hpp"
#include "temp_dir.hpp"

using namespace snvr;

namespace {

bool in_band(const peers::BandCells& band, int i, int j, int k) {
    const std::size_t b = std::size_t(i / 8) + std::size_t(band.bricks_x) * (std::size_t(j / 8) + std::size_t(band.bricks_y) * std::size_t(k / 8));
    if (band.slot[b] == peers::BandCells::kNone) return false;
    const int bit = i % 8 + 8 * (j % 8);
    return (band.masks[band.slot[b]][std::size_t(k % 8)] >> bit) & 1;
}

double nearest(const PointSet& points, const Vec3& q) {
    double best = INFINITY;
    for (const Vec3& p : points) best = std::min(best, std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]));
    return best;
}

}  // namespace

TEST_CASE("the band holds every cell within the reach, and none much beyond it") {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0.3, 0.7);
    PointSet points;
    for (int n = 0; n < 40; ++n) points.push_back({u(rng), u(rng), u(rng)});
    points.push_back({0.3, 0.3, 0.3});  // a cloud's corner: the band meets the grid's edge
    // Reaches under a brick, and over two (the ball spans several bricks).
    for (const double reach_voxels : {2.0, 4.5, 19.0}) {
        CAPTURE(reach_voxels);
        const double h = 0.01, reach = reach_voxels * h;
        const Domain g = peers::distance_grid(points, h, reach);
        const peers::BandCells band = peers::band_cells(points, g, reach);
        std::size_t needed = 0, extra = 0;
        for (int k = 0; k < g.nz; ++k)
            for (int j = 0; j < g.ny; ++j)
                for (int i = 0; i < g.nx; ++i) {
                    const double d = nearest(points, g.cell_center(i, j, k));
                    const bool held = in_band(band, i, j, k);
                    if (d <= reach) {
                        ++needed;
                        CHECK(held);
                    } else if (held) {
                        ++extra;
                        CHECK(d <= reach + std::sqrt(3.0) * h);  // the seed cell's half diagonal, both ways
                    }
                }
        CHECK(band.cells() == needed + extra);
    }
}

TEST_CASE("distance_mc_peer: a sphere's shell is closed, every vertex at l from the points") {
    const testing::TempDir dir("distance-mc");
    const PointSet sphere = shapes::sphere({0.5, 0.5, 0.5}, 0.35, 0.009);
    const std::string points = dir.file("sphere.ply"), out = dir.file("shell.stl");
    write_points(sphere, points);
    // 64 cells on the sphere's width, l = 2.5 voxels (as snvr-cl's defaults would give).
    const double h = 0.7 / 64, l = 2.5 * h;
    char args[256];
    std::snprintf(args, sizeof args, " %s -o %s --voxel %.17g --offset %.17g", points.c_str(), out.c_str(), h, l);
    const cli_testing::Run run = cli_testing::run_command(std::string(SNVR_DISTANCE_MC_PEER) + args);
    CAPTURE(run.output);
    REQUIRE(run.code == 0);
    // One JSON line with the stage seconds.
    for (const char* key : {"\"read\"", "\"index\"", "\"distance\"", "\"mesh\"", "\"write\"", "\"total\"", "\"peak_rss_mib\""})
        CHECK(run.output.find(key) != std::string::npos);
    CHECK(run.output.find('\n') == run.output.size() - 1);

    const Mesh mesh = read_mesh(out);
    const MeshQuality q = measure_quality(mesh, sphere, l, h);
    CHECK(q.closed);
    CHECK(q.manifold);
    CHECK(q.oriented);
    CHECK(q.solids == 1);
    CHECK(q.cavities == 1);  // a hollow ball: the outer and the inner sheet
    CHECK(q.points_inside == sphere.size());
    CHECK(q.offset_max < 0.1);  // in voxels
    CHECK(std::abs(q.offset_mean) < 0.02);
}

TEST_CASE("distance_mc_shell: a lone point's ball, its offset several bricks wide") {
    const PointSet one{{0.1, 0.2, 0.3}};
    const double h = 0.01, l = 12 * h;
    const peers::DistanceShell shell = peers::distance_mc_shell(one, h, l);
    const MeshReport r = check_mesh(shell.mesh);
    CHECK(r.closed());
    CHECK(r.manifold());
    CHECK(r.oriented());
    CHECK(r.components == 1);
    double worst = 0;
    for (const Vec3& v : shell.mesh.vertices) worst = std::max(worst, std::abs(nearest(one, v) - l));
    CHECK(worst < 0.1 * h);
    CHECK(shell.band_cells < std::size_t(shell.grid.nx) * shell.grid.ny * shell.grid.nz);
}

TEST_CASE("distance_mc_peer: usage errors exit 2, unreadable input exits 1") {
    const std::string peer = SNVR_DISTANCE_MC_PEER;
    CHECK(cli_testing::run_command(peer).code == 2);
    CHECK(cli_testing::run_command(peer + " x.ply -o y.stl --voxel 0.1").code == 2);
    CHECK(cli_testing::run_command(peer + " x.ply -o y.stl --voxel -1 --offset 1").code == 2);
    const cli_testing::Run missing = cli_testing::run_command(peer + " /nonexistent/x.ply -o /tmp/never.stl --voxel 0.1 --offset 0.3");
    CHECK(missing.code == 1);
    CHECK(missing.output.find("distance_mc_peer: error:") != std::string::npos);
}
