// openvdb_peer: the OpenVDB shell of a point set, for side-by-side comparisons.
//   openvdb_peer POINTS -o OUT.stl --voxel H --offset L [--steps 4]
// Prints triangles, mesh checks, seconds per stage and peak resident memory.
// Exit status: 0 success, 1 failure, 2 usage.
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>

#include "host_measures.hpp"
#include "openvdb_shell.hpp"
#include "snvr/io.hpp"
#include "snvr/mesh.hpp"
#include "snvr/stopwatch.hpp"

namespace {

struct Args {
    std::string points, out;
    double voxel = 0, offset = 0;
    int steps = 4;
};

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

double parse_number(const std::string& flag, const std::string& text) {
    try {
        size_t used = 0;
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
        else if (arg == "--steps") {
            const double s = parse_number(arg, value());
            if (s != int(s)) throw UsageError("--steps expects a whole number");
            a.steps = int(s);
        } else if (!arg.empty() && arg[0] == '-') throw UsageError("unknown option " + arg);
        else if (a.points.empty()) a.points = arg;
        else throw UsageError("more than one input file");
    }
    if (a.points.empty() || a.out.empty()) throw UsageError("an input file and -o OUT are required");
    if (a.voxel <= 0 || a.offset <= 0) throw UsageError("--voxel and --offset are required and positive");
    return a;
}

}  // namespace

int main(int argc, char** argv) {
    Args args;
    try {
        args = parse(argc, argv);
    } catch (const UsageError& e) {
        std::fprintf(stderr, "openvdb_peer: %s\nusage: openvdb_peer POINTS -o OUT.stl --voxel H --offset L [--steps 4]\n",
                     e.what());
        return 2;
    }
    try {
        snvr::Stopwatch io;
        const snvr::PointSet points = snvr::read_points(args.points);
        const double seconds_read = io.lap();
        const auto shell = snvr::peers::openvdb_shell(points, args.voxel, args.offset, args.steps);
        io.lap();
        snvr::write_mesh(shell.mesh, args.out);
        const double seconds_write = io.lap();
        const snvr::MeshReport r = snvr::check_mesh(shell.mesh);
        std::printf("points %zu, voxel %g, offset %g (%.3g voxels), %d curvature steps\n", points.size(), args.voxel,
                    args.offset, shell.radius_voxels, args.steps);
        std::printf("triangles %zu, vertices %zu, closed %s, manifold %s, oriented %s, components %zu, volume %g\n",
                    r.triangles, r.vertices, r.closed() ? "yes" : "no", r.manifold() ? "yes" : "no",
                    r.oriented() ? "yes" : "no", r.components, r.volume);
        std::printf("seconds: level set %.3f, filter %.3f, mesh %.3f, total %.3f (read %.3f, write %.3f)\n",
                    shell.seconds_level_set, shell.seconds_filter, shell.seconds_mesh, shell.seconds_total,
                    seconds_read, seconds_write);
        std::printf("peak RSS %.1f MiB\n", snvr::bench::peak_rss_mib());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "openvdb_peer: error: %s\n", e.what());
        return 1;
    }
}
