// bench_read FILE [--repeat N]: how fast the point readers read a file, as
// read_float_points (floats about an origin) does, whole and in one process. Prints the
// points, MB/s (the file's bytes over the best of N reads) and the process's peak RSS.
// Run it with the file in the page cache (a first read puts it there) to time parsing,
// not the disk.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

#include "io/point_readers.hpp"
#include "snvr/error.hpp"

namespace {

int usage() {
    std::fprintf(stderr, "usage: bench_read FILE [--repeat N]\n");
    return 2;
}

double peak_rss_mb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) * 1024 / 1e6;  // Linux gives KiB; MB like the file's
}

}  // namespace

int main(int argc, char** argv) {
    std::string path;
    int repeat = 3;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--repeat" && i + 1 < argc) {
            repeat = std::max(1, std::atoi(argv[++i]));
        } else if (path.empty() && arg.rfind("--", 0) != 0) {
            path = arg;
        } else {
            return usage();
        }
    }
    if (path.empty()) return usage();
    try {
        double best = 1e300;
        std::size_t points = 0;
        snvr::Vec3 origin{};
        for (int r = 0; r < repeat; ++r) {
            const auto start = std::chrono::steady_clock::now();
            const snvr::detail::FloatPoints read = snvr::detail::read_float_points(path);
            best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
            points = read.xyz.size();
            origin = read.origin;
        }
        const double bytes = double(std::filesystem::file_size(path));  // read: it is a file
        std::printf("%s: %zu points, origin (%g %g %g), %.1f MB/s (best of %d: %.3f s for %.1f MB), peak RSS %.1f MB\n",
                    path.c_str(), points, origin[0], origin[1], origin[2], bytes / 1e6 / best, repeat, best,
                    bytes / 1e6, peak_rss_mb());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_read: %s\n", e.what());
        return 1;
    }
    return 0;
}
