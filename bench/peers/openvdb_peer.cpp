// openvdb_peer: the OpenVDB shell of a point set, for side-by-side comparisons.
//   openvdb_peer POINTS -o OUT.stl --voxel H --offset L [--steps 4]
// Prints triangles, mesh checks, seconds per stage and peak resident memory.
// Exit status: 0 success, 1 failure, 2 usage.
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>

#include "host_measures.hpp"
#include "peer_args.hpp"
#include "openvdb_shell.hpp"
#include "snvr/mesh_io.hpp"
#include "snvr/point_io.hpp"
#include "snvr/quality.hpp"
#include "snvr/mesh.hpp"
#include "snvr/stopwatch.hpp"

int main(int argc, char** argv) {
    snvr::peers::PeerArgs args;
    int steps = 4;
    try {
        args = snvr::peers::parse_peer_args(argc, argv, [&](const std::string& flag, const std::string& value) {
            if (flag != "--steps") return false;
            const double s = snvr::peers::parse_number(flag, value);
            if (s != int(s)) throw snvr::peers::UsageError("--steps expects a whole number");
            steps = int(s);
            return true;
        });
    } catch (const snvr::peers::UsageError& e) {
        std::fprintf(stderr, "openvdb_peer: %s\nusage: openvdb_peer POINTS -o OUT.stl --voxel H --offset L [--steps 4]\n",
                     e.what());
        return 2;
    }
    try {
        snvr::Stopwatch io;
        const snvr::PointSet points = snvr::read_points(args.points);
        const double seconds_read = io.lap();
        const auto shell = snvr::peers::openvdb_shell(points, args.voxel, args.offset, steps);
        io.lap();
        snvr::write_mesh(shell.mesh, args.out);
        const double seconds_write = io.lap();
        const snvr::MeshReport r = snvr::check_mesh(shell.mesh);
        std::printf("points %zu, voxel %g, offset %g (%.3g voxels), %d curvature steps\n", points.size(), args.voxel,
                    args.offset, shell.radius_voxels, steps);
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
