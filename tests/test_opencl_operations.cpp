// Every backend operation on random fields, OpenCL (PoCL in CI) against the OpenMP
// reference, in both precisions: the largest difference in ULP is printed and bounded.
// Stencil operations use the same arithmetic in the same order on both (no FMA), so
// they must agree to the bit; so must tanh and exp, the project's own on both
// (lib/src/solver/phase_math.hpp and kernels/common.cl), not the math libraries'.
#include <doctest/doctest.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "solver/backend.hpp"
#include "backend_compare.hpp"
#include "solver/coarse_inverse.hpp"
#include "solver/hierarchy.hpp"
#include "opencl/opencl_backend.hpp"
#include "opencl/work_groups.hpp"
#include "openmp/openmp_backend.hpp"

using namespace snvr;
using snvr::testing::max_ulps;

namespace {

// Bounds, in ULP of the result: every operation bit-identical.
constexpr double kExactUlps = 0;

struct Case {
    int nx, ny, nz, levels;
};

template <class Real>
struct Pair {
    Hierarchy hier;
    std::unique_ptr<Backend<Real>> ref = make_openmp_backend<Real>();
    std::unique_ptr<Backend<Real>> dev = make_opencl_backend<Real>("opencl");
    std::mt19937 rng{12345};
    std::vector<Real> distance;  // level 0, in [0, 1)

    explicit Pair(const Case& c) {
        Domain d;
        d.nx = c.nx;
        d.ny = c.ny;
        d.nz = c.nz;
        d.levels = c.levels;
        hier = make_levels(d);
        // Random active bricks (about two in three), so neighbours are often inactive.
        const Level& fine = hier.levels[0];
        std::vector<std::uint8_t> mask(fine.brick_count());
        for (auto& m : mask) m = std::uint8_t(rng() % 3 != 0);
        mask[0] = 1;
        set_active_bricks(hier, mask);
        // Level 0's inactive bricks take the sign of l - d at their first cell.
        const std::vector<Real> distance = random(0, Real(0), Real(2), 0);
        const BrickLayout layout = make_layout<Real>(d, mask, distance.data(), Real(1));
        ref->setup(layout);
        dev->setup(layout);
        const std::vector<Real> packed = pack_level0(layout, distance.data());
        ref->init_phase(packed, Real(1), Real(3), Real(0.8));
        dev->init_phase(packed, Real(1), Real(3), Real(0.8));
        this->distance = random(0, Real(0), Real(1), 0);
    }

    std::vector<Real> random(int level, Real lo, Real hi, double zeros) {
        std::uniform_real_distribution<double> u{double(lo), double(hi)};
        std::uniform_real_distribution<double> p(0, 1);
        std::vector<Real> v(hier.levels[std::size_t(level)].cells());
        for (Real& x : v) x = p(rng) < zeros ? Real(0) : Real(u(rng));
        return v;
    }

    // The same random phi and rhs on both backends, on every level, and a random g on
    // level 0 (by default a fifth of it zero) restricted to the others as the solver does.
    void randomize(double g_zeros = 0.2) {
        for (int l = 0; l < int(hier.levels.size()); ++l) {
            const std::vector<Real> phi = random(l, -1, 1, 0), rhs = random(l, -1, 1, 0), g = random(l, 0, 1, g_zeros);
            for (Backend<Real>* b : {ref.get(), dev.get()}) {
                b->upload(l, FieldKind::phi, phi.data());
                b->upload(l, FieldKind::rhs, rhs.data());
                if (l == 0) b->upload(l, FieldKind::g, g.data());
                else b->restrict_coefficient(l - 1);
            }
        }
    }

    double ulps(int level, FieldKind f, Real scale = 0) {
        std::vector<Real> a(hier.levels[std::size_t(level)].cells()), b(a.size());
        ref->download(level, f, a.data());
        dev->download(level, f, b.data());
        return max_ulps(a, b, scale);
    }
};

const Case kCases[] = {
    {20, 28, 36, 3},  // coarse levels 10x14x18 and 5x7x9: partial bricks everywhere
    {16, 16, 16, 4},  // down to 2x2x2
    {48, 8, 24, 2},   // flat
    {34, 18, 10, 2},  // coarse level 17x9x5: odd sizes
    {13, 7, 9, 1},    // odd fine grid, one level
};

template <class Real>
void compare_operations() {
    const char* type = sizeof(Real) == 8 ? "double" : "float";
    const opencl::DeviceEntry device = opencl::choose_device("opencl");
    const opencl::WorkGroups w = opencl::work_groups(device, sizeof(Real));
    std::printf("%s on %s: %s; work-groups of %zu planes, %zu brick rows, %zu rows, %zu bricks, %zu cells, %zu in the "
                "reduction\n",
                type, device.name.c_str(), w.shape == opencl::KernelShape::Rows ? "row kernels" : "plane kernels", w.planes,
                w.brick_rows, w.rows, w.bricks, w.cells, w.reduce);
    int coarse_solves = 0;
    for (const Case& c : kCases) {
        CAPTURE(c.nx);
        CAPTURE(c.ny);
        CAPTURE(c.nz);
        Pair<Real> p(c);
        const int coarsest = c.levels - 1;
        std::printf("%s %dx%dx%d, %d levels, %zu of %zu bricks active:\n", type, c.nx, c.ny, c.nz, c.levels,
                    p.hier.levels[0].bricks.size(), p.hier.levels[0].brick_count());
        const double init_phi = p.ulps(0, FieldKind::phi), init_g = p.ulps(0, FieldKind::g, Real(1));
        std::printf("  init_phase            phi %g ULP, g %g ULP of 1\n", init_phi, init_g);
        CHECK(init_phi <= kExactUlps);
        CHECK(init_g <= kExactUlps);

        p.randomize();
        p.ref->load_rhs();
        p.dev->load_rhs();
        CHECK(p.ulps(0, FieldKind::rhs) == kExactUlps);

        for (int l = 0; l < coarsest; ++l) {
            p.randomize();
            p.ref->restrict_coefficient(l);
            p.dev->restrict_coefficient(l);
            const double u = p.ulps(l + 1, FieldKind::g);
            std::printf("  restrict_coefficient  level %d: %g ULP\n", l, u);
            CHECK(u == kExactUlps);
        }
        for (int l = 0; l <= coarsest; ++l) {
            const Real coef = Real(0.3 + 0.7 * l);
            for (Real omega : {Real(1), Real(1.2)}) {
                p.randomize();
                for (int color : {0, 1, 0}) {
                    p.ref->smooth(l, color, coef, omega);
                    p.dev->smooth(l, color, coef, omega);
                }
                const double u = p.ulps(l, FieldKind::phi);
                std::printf("  smooth                level %d, omega %.1f: %g ULP\n", l, double(omega), u);
                CHECK(u == kExactUlps);
            }
            p.randomize();
            const double a = p.ref->residual_sum_squares(l, coef), b = p.dev->residual_sum_squares(l, coef);
            const double u = std::abs(a - b) / snvr::testing::ulp_of(a);
            std::printf("  residual_sum_squares  level %d: %.17g vs %.17g, %g ULP\n", l, a, b, u);
            CHECK(u == kExactUlps);
            if (l == coarsest) continue;
            p.randomize();
            p.ref->restrict_residual(l, coef);
            p.dev->restrict_residual(l, coef);
            const double ur = p.ulps(l + 1, FieldKind::rhs), up = p.ulps(l + 1, FieldKind::phi);
            std::printf("  restrict_residual     level %d: rhs %g ULP, phi %g ULP\n", l, ur, up);
            CHECK(ur == kExactUlps);
            CHECK(up == kExactUlps);
            for (bool trilinear : {true, false}) {
                p.randomize();
                p.ref->prolong_correct(l, trilinear);
                p.dev->prolong_correct(l, trilinear);
                const double uc = p.ulps(l, FieldKind::phi);
                std::printf("  prolong_correct       level %d, %s: %g ULP\n", l, trilinear ? "trilinear" : "injection", uc);
                CHECK(uc == kExactUlps);
            }
        }
        if (coarsest > 0) {
            // A level where nothing couples has an empty inverse: the solve writes nothing.
            p.randomize();
            for (Backend<Real>* b : {p.ref.get(), p.dev.get()}) {
                b->set_coarse_inverse(coarsest, CoarseInverse{});
                b->coarse_solve(coarsest);
            }
            CHECK(p.ulps(coarsest, FieldKind::phi) == kExactUlps);
            p.randomize(0);  // else nearly every coarsest cell has a child with g = 0
            std::vector<Real> g(p.hier.levels[std::size_t(coarsest)].cells());
            p.ref->download(coarsest, FieldKind::g, g.data());
            const double h = p.hier.levels[std::size_t(coarsest)].h;
            const CoarseInverse inv = coarse_inverse(p.hier.levels[std::size_t(coarsest)], std::vector<double>(g.begin(), g.end()), 2e-4 / (h * h));
            if (inv.size() == 0) {  // more coupled cells than kMaxCoarseInverse
                std::printf("  coarse_solve          level %d: too many coupled cells for an inverse\n", coarsest);
            } else {
            ++coarse_solves;
            p.ref->set_coarse_inverse(coarsest, inv);
            p.dev->set_coarse_inverse(coarsest, inv);
            p.ref->coarse_solve(coarsest);
            p.dev->coarse_solve(coarsest);
            const double u = p.ulps(coarsest, FieldKind::phi);
            std::printf("  coarse_solve          level %d, %zu cells: %g ULP\n", coarsest, inv.size(), u);
            CHECK(u == kExactUlps);
            }
        }
        for (bool tube : {false, true}) {
            p.randomize();
            // Distances in [0, 1) around a tube [0.3, 0.5]: cells below, inside and above it.
            Tube<Real> t;
            if (tube) t = Tube<Real>{Real(0.3), Real(0.5), Real(4)};
            for (Backend<Real>* b : {p.ref.get(), p.dev.get()}) {
                b->upload(0, FieldKind::distance, p.distance.data());
                b->nonlinear(Real(7.5), t);
            }
            const double un = p.ulps(0, FieldKind::phi);
            std::printf("  nonlinear, tube %-3s   %g ULP\n", tube ? "on" : "off", un);
            CHECK(un <= kExactUlps);
        }
    }
    CHECK(coarse_solves >= 3);
}

}  // namespace

TEST_CASE("every operation on the OpenCL backend matches the reference, double") { compare_operations<double>(); }

TEST_CASE("every operation on the OpenCL backend matches the reference, float") { compare_operations<float>(); }

TEST_CASE("work-group sizes: asked, then fitted to the device's limits") {
    // The suite may run under either variable (tests/CMakeLists.txt): put them back after.
    struct Restore {
        std::string name, value;
        bool had;
        explicit Restore(const char* n) : name(n), had(std::getenv(n) != nullptr) {
            if (had) value = std::getenv(n);
        }
        ~Restore() {
            if (had) setenv(name.c_str(), value.c_str(), 1);
            else unsetenv(name.c_str());
        }
    } kernels("SNVR_OPENCL_KERNELS"), group("SNVR_OPENCL_WORK_GROUP");
    unsetenv("SNVR_OPENCL_KERNELS");
    opencl::DeviceEntry d;
    d.name = "small";
    d.max_group = 1024;
    d.local_memory = 48 * 1024;  // a GPU's
    unsetenv("SNVR_OPENCL_WORK_GROUP");
    opencl::WorkGroups w = opencl::work_groups(d, sizeof(double));
    CHECK(w.planes == 64);  // 32 KiB of residuals
    CHECK(w.reduce == 256);
    CHECK(w.build_options() == "-DPLANES_PER_GROUP=64 -DROWS_PER_GROUP=256 -DREDUCE_GROUP=256");
    CHECK(w.shape == opencl::KernelShape::Planes);  // not a GPU
    d.gpu = true;
    CHECK(opencl::work_groups(d, sizeof(double)).shape == opencl::KernelShape::Rows);
    setenv("SNVR_OPENCL_KERNELS", "planes", 1);
    CHECK(opencl::work_groups(d, sizeof(double)).shape == opencl::KernelShape::Planes);
    setenv("SNVR_OPENCL_KERNELS", "cells", 1);
    CHECK_THROWS_WITH_AS(opencl::work_groups(d, sizeof(double)), doctest::Contains("SNVR_OPENCL_KERNELS"), ParameterError);
    setenv("SNVR_OPENCL_KERNELS", "rows", 1);
    d.local_memory = 12 * 1024;
    CHECK(opencl::work_groups(d, sizeof(double)).brick_rows == 128);  // 4 KiB of residuals per 64 rows
    d.local_memory = 48 * 1024;
    setenv("SNVR_OPENCL_WORK_GROUP", "256", 1);
    w = opencl::work_groups(d, sizeof(double));
    CHECK(w.rows == 256);
    CHECK(w.cells == 256);
    CHECK(w.planes == 64);  // 256 planes would need 128 KiB of local memory
    CHECK(opencl::work_groups(d, sizeof(float)).planes == 128);  // 32 KiB of float residuals
    setenv("SNVR_OPENCL_WORK_GROUP", "32", 1);
    CHECK(opencl::work_groups(d, sizeof(float)).brick_rows == 64);  // a brick's rows at least
    d.max_group = 16;  // below the ask: the device's limit
    w = opencl::work_groups(d, sizeof(float));
    CHECK(w.rows == 16);
    CHECK(w.planes == 16);
    CHECK(w.reduce == 16);
    CHECK(w.shape == opencl::KernelShape::Planes);  // no group holds a brick's 64 rows
    unsetenv("SNVR_OPENCL_KERNELS");
    d.local_memory = 1024;  // too little for 8 planes of doubles (4 KiB)
    CHECK_THROWS_WITH_AS(opencl::work_groups(d, sizeof(double)), doctest::Contains("local memory"), ResourceError);
    for (const char* bad : {"12", "4", "2048", "64x", "-8"}) {
        setenv("SNVR_OPENCL_WORK_GROUP", bad, 1);
        CHECK_THROWS_WITH_AS(opencl::work_groups(d, sizeof(float)), doctest::Contains("SNVR_OPENCL_WORK_GROUP"), ParameterError);
    }
    unsetenv("SNVR_OPENCL_WORK_GROUP");
    CHECK(opencl::fit_group(100, 1000) == 64);
    CHECK(opencl::fit_group(256, 200) == 128);
}
