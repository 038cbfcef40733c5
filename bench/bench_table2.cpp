// The paper's Table 2: cube, sphere, cylinder (size 0.35 in the unit cube, l = 0.05,
// eps = 0.005), grown and shrunk surface errors (RMS over mesh vertices of distance to
// the exact surface minus l) beside the paper's, at the given resolutions and step
// counts, with the observed order of convergence between consecutive resolutions.
//
//   bench_table2 [--resolutions 128,256] [--steps 4,8] [--dt-scaling fixed|h2] [--device D]
//   --steps -1 is the default flow (dt and steps from the defaults in cells).
//                [--coarse exact|sweeps] [--precision double|float]
//   --dt-scaling h2 keeps dt / h^2 at its 128^3 value (dt = 5e-5 (128 / N)^2).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "snvr/snvr.hpp"
#include "table2.hpp"
#include "snvr/shapes.hpp"

namespace {

std::vector<int> int_list(const std::string& s) {
    std::vector<int> v;
    std::stringstream in(s);
    std::string item;
    while (std::getline(in, item, ',')) v.push_back(std::atoi(item.c_str()));
    return v;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<int> resolutions{128, 256}, steps{-1, 4};
    bool scale_dt = false;
    std::string device = "auto";
    bool exact_coarse = snvr::Parameters{}.exact_coarse;
    snvr::Precision precision = snvr::Parameters{}.precision;
    for (int a = 1; a + 1 < argc; a += 2) {
        const std::string opt = argv[a], val = argv[a + 1];
        if (opt == "--resolutions") resolutions = int_list(val);
        else if (opt == "--steps") steps = int_list(val);
        else if (opt == "--dt-scaling") scale_dt = val == "h2";
        else if (opt == "--device") device = val;
        else if (opt == "--coarse") exact_coarse = val != "sweeps";
        else if (opt == "--precision") precision = val == "float" ? snvr::Precision::Single : snvr::Precision::Double;
        else {
            std::fprintf(stderr, "unknown option %s\n", opt.c_str());
            return 2;
        }
    }
    std::printf("| shape | grid | steps | dt | grown | paper | shrunk | paper | order (grown, shrunk) | V-cycles/step | seconds |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (const snvr::table2::Shape& shape : snvr::table2::shapes())
        for (int nt : steps) {
            double prev_g = 0, prev_s = 0;
            int prev_n = 0;
            for (int n : resolutions) {
                const snvr::PointSet points = snvr::shapes::by_name(shape.name, 0.5 / n);
                snvr::Parameters p = snvr::table2::parameters(n, nt);
                if (scale_dt) p.dt = 5e-5 * (128.0 / n) * (128.0 / n);
                p.device = device;
                p.exact_coarse = exact_coarse;
                p.precision = precision;
                const snvr::Result r = snvr::reconstruct(points, p);
                const snvr::Mesh mesh = snvr::extract_isosurface(r.phi, r.domain, 0.0, snvr::Interpolation::PhaseField);
                const snvr::table2::Errors e = snvr::table2::surface_errors(mesh, shape, 0.05);
                int cycles = 0;
                for (const auto& s : r.steps) cycles = std::max(cycles, s.cycles);
                const bool has_paper = n == 128 || n == 256;
                const double pg = n == 128 ? shape.paper_grown_128 : shape.paper_grown_256;
                const double ps = n == 128 ? shape.paper_shrunk_128 : shape.paper_shrunk_256;
                std::string order = "-";
                if (prev_n) {
                    const double f = std::log(double(n) / prev_n);
                    char buf[64];
                    std::snprintf(buf, sizeof buf, "%.2f, %.2f", std::log(prev_g / e.grown) / f, std::log(prev_s / e.shrunk) / f);
                    order = buf;
                }
                auto paper = [&](double v) {
                    char buf[32];
                    std::snprintf(buf, sizeof buf, "%.3e", v);
                    return has_paper ? std::string(buf) : std::string("-");
                };
                std::printf("| %s | %d^3 | %zu | %.3g | %.3e | %s | %.3e | %s | %s | %d | %.1f |\n", shape.name.c_str(), n, r.steps.size(), r.dt,
                            e.grown, paper(pg).c_str(), e.shrunk, paper(ps).c_str(), order.c_str(), cycles, r.seconds.total);
                std::fflush(stdout);
                prev_g = e.grown, prev_s = e.shrunk, prev_n = n;
            }
        }
    return 0;
}
