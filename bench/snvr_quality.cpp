// Judges a shell mesh (ours or another program's) against the points it was built
// from: prints measure_quality's block, then the same figures as one JSON line.
//
//   snvr_quality MESH POINTS --offset L --voxel H [--exact sphere:cx,cy,cz,R,l] [--shell]
//
// --shell measures as make_shell's check does (measure_shell: no surface figures), to
// time that check alone.
// --exact sphere:... compares the vertices with the exact offset surfaces of a
// sphere of centre c and radius R: the spheres of radii R + l and R - l, i.e. the
// error at p is | |p - c| - R | - l.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "snvr/snvr.hpp"
#include "snvr/stopwatch.hpp"

namespace {

void usage(const char* argv0) {
    std::fprintf(stderr, "usage: %s MESH POINTS --offset L --voxel H [--exact sphere:cx,cy,cz,R,l] [--shell]\n", argv0);
}

bool parse_positive(const std::string& text, double& out) {
    char* end = nullptr;
    out = std::strtod(text.c_str(), &end);
    return end != text.c_str() && *end == '\0' && std::isfinite(out) && out > 0;
}

// "sphere:cx,cy,cz,R,l" -> the distance to the two offset spheres.
bool parse_exact(const std::string& spec, std::function<double(const snvr::Vec3&)>& exact) {
    const std::string prefix = "sphere:";
    if (spec.compare(0, prefix.size(), prefix) != 0) return false;
    std::vector<double> v;
    std::stringstream in(spec.substr(prefix.size()));
    std::string item;
    while (std::getline(in, item, ',')) {
        char* end = nullptr;
        v.push_back(std::strtod(item.c_str(), &end));
        if (end == item.c_str() || *end != '\0' || !std::isfinite(v.back())) return false;
    }
    if (v.size() != 5 || v[3] <= 0 || v[4] <= 0) return false;
    const snvr::Vec3 c{v[0], v[1], v[2]};
    const double r = v[3], l = v[4];
    exact = [c, r, l](const snvr::Vec3& p) {
        const double d = std::sqrt((p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) +
                                   (p[2] - c[2]) * (p[2] - c[2]));
        return std::fabs(std::fabs(d - r) - l);
    };
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> files;
    double offset = 0, voxel = 0;
    std::function<double(const snvr::Vec3&)> exact;
    bool shell = false;
    for (int a = 1; a < argc; ++a) {
        const std::string arg = argv[a];
        if (arg == "--help" || arg == "-h") {
            usage(argv[0]);
            return 0;
        }
        if (arg == "--shell") {
            shell = true;
            continue;
        }
        if (arg.rfind("--", 0) != 0) {
            files.push_back(arg);
            continue;
        }
        if (a + 1 >= argc) {
            std::fprintf(stderr, "%s needs a value\n", arg.c_str());
            return 2;
        }
        const std::string value = argv[++a];
        const bool ok = arg == "--offset"  ? parse_positive(value, offset)
                        : arg == "--voxel" ? parse_positive(value, voxel)
                        : arg == "--exact" ? parse_exact(value, exact)
                                           : (std::fprintf(stderr, "unknown option %s\n", arg.c_str()), false);
        if (!ok) {
            std::fprintf(stderr, "bad value '%s' for %s\n", value.c_str(), arg.c_str());
            usage(argv[0]);
            return 2;
        }
    }
    if (files.size() != 2 || offset <= 0 || voxel <= 0) {
        usage(argv[0]);
        return 2;
    }
    try {
        snvr::Stopwatch clock;
        const snvr::Mesh mesh = snvr::read_mesh(files[0]);
        const snvr::PointSet points = snvr::read_points(files[1]);
        const double read_s = clock.lap();
        const snvr::PointCloud cloud(points);
        const snvr::MeshQuality q = shell ? snvr::measure_shell(mesh, cloud, offset, voxel)
                                          : snvr::measure_quality(mesh, cloud, offset, voxel, exact);
        std::printf("%s against %s\n%s", files[0].c_str(), files[1].c_str(), snvr::format_quality(q).c_str());
        std::printf("read %.2f s, measured %.2f s\n", read_s, q.seconds);
        std::printf("%s\n", snvr::quality_json(q).c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    return 0;
}
