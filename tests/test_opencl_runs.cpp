// Whole reconstructions on the OpenCL backend (PoCL in CI) against the OpenMP reference:
// the half sphere (open input) and a real scan, in double and in float.
#include <doctest/doctest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "backend_compare.hpp"
#include "opencl/runtime.hpp"
#include "snvr/snvr.hpp"

using namespace snvr;

namespace {

// Float: both backends run bit-identical stencils; only tanh and exp differ, by up to
// 2 ULP (2.4e-7 near 1; test_opencl_operations). Each step adds such differences; the
// linear step does not amplify them in max norm (A = I - c G Lap is an M-matrix, A^-1 >= 0
// with row sums <= 1) and the nonlinear one only near phi = 0, where few cells are. So
// after n steps about (n + 1) * 2.4e-7 = 2.2e-6 for n = 8. Measured: 8.3e-7 (half sphere,
// 8 steps), 5.4e-7 (bunny, 4 steps). Bound: 4e-6.
constexpr double kDoubleBound = 1e-10, kFloatBound = 4e-6;

struct Case {
    const char* name;
    PointSet points;
    int resolution, steps;
};

std::vector<Case> cases() {
    return {{"half sphere", shapes::half_sphere({0.5, 0.5, 0.5}, 0.35, 0.004), 96, 8},
            {"bunny", read_points(std::string(SNVR_DATA_DIR) + "/bunny.ply"), 128, 4}};
}

void compare_runs(Precision precision, double bound) {
    for (const Case& c : cases()) {
        Parameters p;
        p.resolution = c.resolution;
        p.steps = c.steps;
        p.precision = precision;
        p.device = "openmp";
        const Result ref = reconstruct(c.points, p);
        p.device = "opencl";
        const Result dev = reconstruct(c.points, p);
        CHECK(dev.backend.rfind("opencl", 0) == 0);
        REQUIRE(ref.phi.size() == dev.phi.size());
        std::vector<double> a(ref.phi.size()), b(dev.phi.size());
        for (std::size_t n = 0; n < a.size(); ++n) {
            a[n] = ref.phi[n];
            b[n] = dev.phi[n];
        }
        const double diff = testing::max_abs_difference(a, b);
        int cycles_ref = 0, cycles_dev = 0;
        for (std::size_t s = 0; s < ref.steps.size(); ++s) {
            cycles_ref += ref.steps[s].cycles;
            cycles_dev += dev.steps[s].cycles;
        }
        const MeshReport mr = check_mesh(extract_isosurface(ref.phi, ref.domain, 0.0, Interpolation::PhaseField));
        const MeshReport md = check_mesh(extract_isosurface(dev.phi, dev.domain, 0.0, Interpolation::PhaseField));
        std::printf("%s, %s, %d steps: max |phi difference| %.3g; V-cycles %d / %d; triangles %zu / %zu, components %zu / %zu\n",
                    c.name, precision == Precision::Double ? "double" : "float", c.steps, diff, cycles_ref, cycles_dev,
                    mr.triangles, md.triangles, mr.components, md.components);
        CHECK(diff <= bound);
        CHECK(cycles_ref == cycles_dev);
        // Same topology: same counts of everything, and both printable.
        CHECK(mr.triangles == md.triangles);
        CHECK(mr.vertices == md.vertices);
        CHECK(mr.components == md.components);
        CHECK(mr.solids == md.solids);
        CHECK(md.closed());
        CHECK(md.manifold());
        CHECK(md.oriented());
    }
}

}  // namespace

TEST_CASE("whole runs on OpenCL agree with the reference: double within 1e-10") { compare_runs(Precision::Double, kDoubleBound); }

TEST_CASE("whole runs on OpenCL agree with the reference: float") { compare_runs(Precision::Single, kFloatBound); }

TEST_CASE("the OpenCL program is built once per device and precision in a process") {
    for (bool single : {false, true}) {
        warmup("opencl", single);
        const std::size_t builds = opencl::program_builds();
        Parameters p;
        p.resolution = 32;
        p.steps = 1;
        p.device = "opencl";
        p.precision = single ? Precision::Single : Precision::Double;
        for (int run = 0; run < 2; ++run) CHECK(reconstruct(shapes::sphere({0.5, 0.5, 0.5}, 0.3, 0.02), p).backend.rfind("opencl", 0) == 0);
        CHECK(opencl::program_builds() == builds);
    }
    warmup("openmp");  // nothing to build, and no error
    CHECK_THROWS_AS(warmup("no-such-device"), ParameterError);
}
