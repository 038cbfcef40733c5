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
#include "snvr/io.hpp"
#include "snvr/stopwatch.hpp"

namespace {

struct Args {
    std::string points, out;
    double voxel = 0, offset = 0;
};

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

double parse_number(const std::string& flag, const std::string& text) {
    try {
        std::size_t used = 0;
        const double v = std::stod(text, &used);
        if (used == text.size()) return v;
    } catch (const std::exception&) {
    }
    throw UsageError(flag + " expects a number, got '" + text + "'");
}

Args parse(int argc, char** argv) {
    Args a;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        const auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw UsageError(arg + " needs a value");
            return argv[++i];
        };
        if (arg == "-o") a.out = value();
        else if (arg == "--voxel") a.voxel = parse_number(arg, value());
        else if (arg == "--offset") a.offset = parse_number(arg, value());
        else if (!arg.empty() && arg[0] == '-') throw UsageError("unknown option " + arg);
        else if (a.points.empty()) a.points = arg;
        else throw UsageError("more than one input file");
    }
    if (a.points.empty() || a.out.empty()) throw UsageError("an input file and -o OUT are required");
    if (!(a.voxel > 0) || !(a.offset > 0)) throw UsageError("--voxel and --offset are required and positive");
    return a;
}

}  // namespace

int main(int argc, char** argv) {
    Args args;
    try {
        args = parse(argc, argv);
    } catch (const UsageError& e) {
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
