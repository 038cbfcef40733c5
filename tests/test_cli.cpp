// snvr-cl as a user meets it: bad input gets exit 1 (bad usage 2), a message naming
// the problem, and no output file; sane degenerate input gets a result.
#include <doctest/doctest.h>
#include <sys/wait.h>

#include "cli_run.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;
using namespace cli_testing;

TEST_CASE("bad input: a clear error, exit 1, no output") {
    TempDir t;
    const std::string o = " -o " + t.out() + " --quiet";
    expect_failure("reconstruct " + t.path.string() + "/missing.ply" + o, 1, "No such file", t);
    expect_failure("reconstruct " + t.file("empty.xyz", "# nothing\n") + o, 1, "no points", t);
    expect_failure("reconstruct " + t.file("trunc.ply", binary_ply_header(10) + std::string(20, '\0')) + o, 1,
                   "expected 10 vertices", t);
    expect_failure("reconstruct " + t.file("count.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                                        "property float y\nproperty float z\nend_header\n0 0 0\n1 1 1\n") + o,
                   1, "expected 3 vertices", t);
    expect_failure("reconstruct " + t.file("nan.xyz", "0 0 0\n1 nan 1\n") + o, 1, "point 1", t);
    expect_failure("reconstruct " + t.file("inf.xyz", "0 0 0\n1 1 inf\n") + o, 1, "point 1", t);
    expect_failure("reconstruct " + t.file("text.xyz", "0 0 0\n1 abc 1\n") + o, 1, "line 2", t);
    expect_failure("reconstruct " + t.file("one.xyz", "1 2 3\n") + o, 1, "coincide", t);
    const std::string cloud = t.file("cloud.xyz", "0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n");
    expect_failure("reconstruct " + cloud + o + " --offset 0.001", 1, "smaller than one voxel", t);
    expect_failure("reconstruct " + cloud + o + " --voxel 0.0004", 1, "memory", t);
}

TEST_CASE("bad usage: exit 2 and a hint") {
    TempDir t;
    const std::string cloud = t.file("cloud.xyz", "0 0 0\n1 0 0\n0 1 0\n0 0 1\n");
    expect_failure("reconstruct " + cloud, 2, "-o", t);
    expect_failure("reconstruct " + cloud + " -o " + t.out() + " --steps abc", 2, "--steps", t);
    expect_failure("reconstruct " + cloud + " -o " + t.out() + " --offset 1 --thickness 2", 2, "thickness", t);
    expect_failure("reconstruct " + cloud + " -o " + t.out() + " --bogus", 2, "--bogus", t);
    expect_failure("frobnicate", 2, "frobnicate", t);
}

TEST_CASE("the flow in cells by default; the paper's normalised dt and free flow on request") {
    TempDir t;
    std::string sphere;  // points on a sphere of radius 0.3
    for (int i = 0; i < 40; ++i)
        for (int j = 0; j < 80; ++j) {
            const double th = 3.14159265 * (i + 0.5) / 40, ph = 2 * 3.14159265 * j / 80;
            sphere += std::to_string(0.3 * std::sin(th) * std::cos(ph)) + " " + std::to_string(0.3 * std::sin(th) * std::sin(ph)) +
                      " " + std::to_string(0.3 * std::cos(th)) + "\n";
        }
    const std::string cloud = t.file("sphere.xyz", sphere);
    Run r = run("reconstruct " + cloud + " -o " + t.out() + " --resolution 48");
    CAPTURE(r.output);
    CHECK(r.code == 0);
    CHECK(r.output.find("6 steps of dt") != std::string::npos);
    CHECK(r.output.find("(0.25 h^2): time 1.5 h^2; surface kept between") != std::string::npos);
    CHECK(r.output.find("walls            thinnest 1%") != std::string::npos);
    // The mesh stage's first part said, and its lines before the check's.
    const std::size_t mesh_line = r.output.find("mesh: extracting the zero level set\n"),
                      check_line = r.output.find("check: the shell against the points\n");
    CHECK(mesh_line < check_line);
    CHECK(check_line != std::string::npos);
    CHECK(r.output.find("mesh: ", check_line) == std::string::npos);
    // The surface's figures only when asked for: they double the check's time.
    CHECK(r.output.find("surface          genus 0 (distance to the offset and smoothness: --measure)") != std::string::npos);
    fs::remove(t.out());
    r = run("reconstruct " + cloud + " -o " + t.out() + " --resolution 48 --measure");
    CAPTURE(r.output);
    CHECK(r.code == 0);
    CHECK(r.output.find("surface          distance to the points - offset: RMS ") != std::string::npos);
    CHECK(r.output.find("genus 0\n") != std::string::npos);
    fs::remove(t.out());
    r = run("reconstruct " + cloud + " -o " + t.out() + " --resolution 48 --dt 5e-5 --steps 3 --free-flow");
    CAPTURE(r.output);
    CHECK(r.code == 0);
    CHECK(r.output.find("3 steps of dt 5e-05") != std::string::npos);
    CHECK(r.output.find("free flow") != std::string::npos);
    fs::remove(t.out());
    expect_failure("reconstruct " + cloud + " -o " + t.out() + " --dt 1e-5 --dt-cells 0.5", 2, "--dt", t);
    expect_failure("reconstruct " + cloud + " -o " + t.out() + " --tube-inner 1.5", 2, "tube", t);
    expect_failure("reconstruct " + cloud + " -o " + t.out() + " --free-flow --tube-outer 0.5", 2, "free-flow", t);
}

TEST_CASE("degenerate but sane input gets a printable result") {
    TempDir t;
    // A single point with a given offset: a ball.
    Run r = run("reconstruct " + t.file("one.xyz", "1 2 3\n") + " -o " + t.out() + " --offset 0.5 --resolution 32");
    CAPTURE(r.output);
    CHECK(r.code == 0);
    CHECK(r.output.find("closed yes, manifold yes, oriented yes") != std::string::npos);
    CHECK(r.output.find("points enclosed  1 of 1") != std::string::npos);
    fs::remove(t.out());
    // All points on one plane: a closed slab around them.
    std::string plane;
    for (int i = 0; i <= 20; ++i)
        for (int j = 0; j <= 20; ++j) plane += std::to_string(i * 0.05) + " " + std::to_string(j * 0.05) + " 0.5\n";
    r = run("reconstruct " + t.file("plane.xyz", plane) + " -o " + t.out() + " --resolution 48 --volume " +
            (t.path / "phi.vti").string());
    CAPTURE(r.output);
    CHECK(r.code == 0);
    CHECK(r.output.find("closed yes, manifold yes, oriented yes") != std::string::npos);
    CHECK(r.output.find("points enclosed  441 of 441") != std::string::npos);
    CHECK(fs::file_size(t.out()) > 84);
    CHECK(fs::file_size(t.path / "phi.vti") > 48 * 48 * 8);
}

TEST_CASE("devices: both backends listed; without a usable OpenCL device auto falls back, opencl fails") {
    Run r = run("devices");
    CAPTURE(r.output);
    CHECK(r.code == 0);
    CHECK(r.output.find("openmp ") != std::string::npos);
    CHECK(r.output.find("opencl:0:0") != std::string::npos);  // PoCL, which the set-up installs
    CHECK(r.output.find("FP64") != std::string::npos);

    TempDir t;
    const std::string cloud = t.file("cloud.xyz", "0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n");
    const std::string o = " -o " + t.out() + " --resolution 32 --quiet";
    // No OpenCL platform: the ICD loader reads vendors from an empty folder.
    const std::string none = "OCL_ICD_VENDORS=" + t.path.string();
    r = run("devices", none);
    CHECK(r.code == 0);
    CHECK(r.output.find("opencl:") == std::string::npos);
    r = run("reconstruct " + cloud + o, none);
    CAPTURE(r.output);
    CHECK(r.code == 0);
    CHECK(r.output.find("no OpenCL platform") != std::string::npos);
    CHECK(r.output.find("running on the OpenMP reference backend") != std::string::npos);
    fs::remove(t.out());
    expect_failure("reconstruct " + cloud + o + " --device opencl", 1, "no OpenCL platform", t, none);
    // A device that cannot build the program (a bad type forced into the build).
    const std::string broken = "SNVR_OPENCL_OPTIONS=-DREAL=no_such_type";
    r = run("reconstruct " + cloud + o, broken);
    CAPTURE(r.output);
    CHECK(r.code == 0);
    CHECK(r.output.find("program build failed") != std::string::npos);
    CHECK(r.output.find("running on the OpenMP reference backend") != std::string::npos);
    fs::remove(t.out());
    expect_failure("reconstruct " + cloud + o + " --device opencl", 1, "unknown type name 'no_such_type'", t, broken);
    expect_failure("reconstruct " + cloud + o + " --device opencl:3:7", 1, "no such OpenCL platform/device", t);
    expect_failure("reconstruct " + cloud + o + " --device quantum", 1, "unknown device 'quantum'", t);
}

// snvr-cl starts itself again with glibc.malloc.hugetlb=1 (main.cpp): its large arrays
// advised into transparent huge pages, which the report counts; the user's own
// GLIBC_TUNABLES choice stands; the shell the same bytes either way.
TEST_CASE("the large arrays in huge pages unless the user chose otherwise") {
    TempDir t;
    std::ifstream mode_file("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string mode;
    std::getline(mode_file, mode);
    const bool advised_only = mode.find("[madvise]") != std::string::npos;
    const bool possible = advised_only || mode.find("[always]") != std::string::npos;
    const std::string bunny = std::string(SNVR_DATA_DIR) + "/bunny.ply";
    auto huge_bytes = [&](const std::string& env, const std::string& out) {
        const std::string report = (t.path / "r.json").string();
        const Run r = run("reconstruct " + bunny + " -o " + out + " --resolution 256 --report " + report, env);
        CAPTURE(r.output);
        REQUIRE(r.code == 0);
        std::ifstream in(report);
        const std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const std::size_t at = json.find("\"huge_page_bytes\":");
        REQUIRE(at != std::string::npos);
        return std::stoull(json.substr(at + 18));
    };
    const std::string advised = (t.path / "advised.stl").string(), plain = (t.path / "plain.stl").string();
    CAPTURE(mode);
    if (possible)
        CHECK(huge_bytes("env -u GLIBC_TUNABLES", advised) > 0);
    else
        CHECK(huge_bytes("env -u GLIBC_TUNABLES", advised) == 0);
    const unsigned long long declined = huge_bytes("GLIBC_TUNABLES=glibc.malloc.hugetlb=0", plain);
    if (advised_only) CHECK(declined == 0);
    std::ifstream a(advised, std::ios::binary), b(plain, std::ios::binary);
    const std::string bytes_a((std::istreambuf_iterator<char>(a)), std::istreambuf_iterator<char>()),
        bytes_b((std::istreambuf_iterator<char>(b)), std::istreambuf_iterator<char>());
    CHECK(!bytes_a.empty());
    CHECK(bytes_a == bytes_b);
}
