// Whole reconstructions on the OpenCL backend (PoCL in CI) against the OpenMP reference:
// the half sphere (open input) and a real scan, in double and in float.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "backend_compare.hpp"
#include "opencl/runtime.hpp"
#include "snvr/snvr.hpp"
#include "snvr/shapes.hpp"

using namespace snvr;

namespace {

// Both backends compute every operation with the same operations in the same order,
// exp and tanh included (solver/phase_math.hpp): a whole run gives the same bits, in
// either precision, and the same mesh. (Until the shared exp and tanh, float runs
// differed by up to 8.3e-7.)
struct Case {
    const char* name;
    PointSet points;
    int resolution, steps;
};

std::vector<Case> cases() {
    return {{"half sphere", shapes::half_sphere({0.5, 0.5, 0.5}, 0.35, 0.004), 96, 8},
            {"bunny", read_points(std::string(SNVR_DATA_DIR) + "/bunny.ply"), 128, 4}};
}

// Whether the device the runs use has double precision (SNVR_OPENCL_NO_FP64=1 hides it:
// tests/CMakeLists.txt runs this suite so too).
bool device_fp64() { return opencl::choose_device("opencl").fp64; }

void compare_runs(Precision precision) {
    const bool fp64 = device_fp64();
    if (precision == Precision::Double && !fp64) {
        // Refused, naming the device and the remedy.
        Parameters p;
        p.resolution = 32;
        p.precision = precision;
        p.device = "opencl";
        CHECK_THROWS_WITH_AS(reconstruct(shapes::sphere({0.5, 0.5, 0.5}, 0.3, 0.02), p),
                             doctest::Contains("no double precision (fp64); use --precision float"), ParameterError);
        return;
    }
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
        const Mesh ref_mesh = extract_isosurface(ref.phi, ref.domain, 0.0, Interpolation::PhaseField);
        const Mesh dev_mesh = extract_isosurface(dev.phi, dev.domain, 0.0, Interpolation::PhaseField);
        const MeshReport mr = check_mesh(ref_mesh), md = check_mesh(dev_mesh);
        std::printf("%s, %s, %d steps: max |phi difference| %.3g; V-cycles %d / %d; triangles %zu / %zu, components %zu / %zu\n",
                    c.name, precision == Precision::Double ? "double" : "float", c.steps, diff, cycles_ref, cycles_dev,
                    mr.triangles, md.triangles, mr.components, md.components);
        CHECK(diff == 0);
        CHECK(cycles_ref == cycles_dev);
        // Without fp64 the device sums the residual norm in float: the norm (which only
        // decides when to stop cycling) differs in its last digits, the field not at all.
        for (std::size_t s = 0; s < ref.steps.size() && s < dev.steps.size(); ++s)
            if (fp64) CHECK(ref.steps[s].residual == dev.steps[s].residual);
            else CHECK(std::abs(ref.steps[s].residual - dev.steps[s].residual) <= 1e-5 * ref.steps[s].residual);
        // The same mesh, and printable.
        CHECK(ref_mesh.triangles == dev_mesh.triangles);
        CHECK(ref_mesh.vertices == dev_mesh.vertices);
        CHECK(mr.components == md.components);
        CHECK(md.closed());
        CHECK(md.manifold());
        CHECK(md.oriented());
    }
}

}  // namespace

TEST_CASE("whole runs on OpenCL give the reference's bits: double") { compare_runs(Precision::Double); }

TEST_CASE("whole runs on OpenCL give the reference's bits: float") { compare_runs(Precision::Single); }

TEST_CASE("the OpenCL program is built once per device and precision in a process") {
    for (bool single : {false, true}) {
        if (!single && !device_fp64()) continue;
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
