// distance_mc_peer: the plain distance + marching cubes shell of a point set
// (distance_mc_shell.hpp), the floor a reconstruction's cost is compared with.
//   distance_mc_peer POINTS -o OUT.stl --voxel H --offset L
// Prints one JSON line on stderr: points, grid, band, triangles, seconds per stage
// (read, index, band: finding the band's cells, distance, mesh, write, total) and
// peak resident memory. Exit status: 0 success, 1 failure, 2 usage.
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>

#include "distance_mc_shell.hpp"
#include "host_measures.hpp"
#include "peer_args.hpp"
#include "snvr/mesh_io.hpp"
#include "snvr/point_io.hpp"
#include "snvr/stopwatch.hpp"

int main(int argc, char** argv) {
    snvr::peers::PeerArgs args;
    try {
        args = snvr::peers::parse_peer_args(argc, argv);
    } catch (const snvr::peers::UsageError& e) {
        std::fprintf(stderr, "distance_mc_peer: %s\nusage: distance_mc_peer POINTS -o OUT.stl --voxel H --offset L\n", e.what());
        return 2;
    }
    try {
        snvr::Stopwatch clock;
        const snvr::PointSet points = snvr::read_points(args.points);
        const double seconds_read = clock.lap();
        const snvr::peers::DistanceShell shell = snvr::peers::distance_mc_shell(points, args.voxel, args.offset);
        clock.lap();
        snvr::write_mesh(shell.mesh, args.out);
        const double seconds_write = clock.lap();
        const double total = seconds_read + shell.seconds_index + shell.seconds_band + shell.seconds_distance + shell.seconds_mesh + seconds_write;
        const snvr::Domain& g = shell.grid;
        std::fprintf(stderr,
                     "{\"points\": %zu, \"voxel\": %.17g, \"offset\": %.17g, \"grid\": [%d, %d, %d], \"band_cells\": %zu, "
                     "\"band_bricks\": %zu, \"triangles\": %zu, \"vertices\": %zu, \"seconds\": {\"read\": %.6f, \"index\": %.6f, "
                     "\"band\": %.6f, \"distance\": %.6f, \"mesh\": %.6f, \"write\": %.6f, \"total\": %.6f}, \"peak_rss_mib\": %.1f}\n",
                     points.size(), args.voxel, args.offset, g.nx, g.ny, g.nz, shell.band_cells, shell.band_bricks,
                     shell.mesh.triangles.size(), shell.mesh.vertices.size(), seconds_read, shell.seconds_index, shell.seconds_band,
                     shell.seconds_distance, shell.seconds_mesh, seconds_write, total, snvr::bench::peak_rss_mib());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "distance_mc_peer: error: %s\n", e.what());
        return 1;
    }
}
