// Promises under resource limits, absurd options and hostile files (issue 22): each case
// here broke on the main of 2026-11-26 (an abort, a kill by signal, a wrong result with
// exit 0, a message naming the wrong thing).
#include <doctest/doctest.h>
#include <zlib.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

#include "cli_run.hpp"
#include "test_files.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh_io.hpp"

namespace fs = std::filesystem;
using namespace cli_testing;

namespace {

std::set<std::string> entries(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
    return names;
}

// A small sphere of points as text: enough for a shell at a few dozen cells.
std::string sphere_xyz(int rings = 24) {
    std::string text;
    char line[128];
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < 2 * rings; ++j) {
            const double th = M_PI * (i + 0.5) / rings, ph = M_PI * j / rings;
            std::snprintf(line, sizeof line, "%.9g %.9g %.9g\n", std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph),
                          std::cos(th));
            text += line;
        }
    return text;
}

// A small sphere of points as LAS, at the given scale.
std::string las(double scale) {
    std::vector<std::array<double, 3>> points;
    for (int i = 0; i < 200; ++i) {
        const double th = M_PI * (i / 20 + 0.5) / 10, ph = M_PI * (i % 20) / 10;
        points.push_back({std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)});
    }
    return snvr::testing::las_file(points, scale, 0);
}

}  // namespace

TEST_CASE("memory limits: no abort; OpenCL is not loaded and the reason is named") {
    TempDir t;
    const std::string input = t.file("in.xyz", sphere_xyz());
    // 100 MB of data: PoCL aborted the process here (SIGABRT) as it started.
    for (const std::string& args : {std::string("devices"), "reconstruct " + input + " -o " + t.out() + " --resolution 24"}) {
        CAPTURE(args);
        const Run r = run_command("bash -c 'ulimit -d 100000; " + std::string(SNVR_CLI) + " " + args + "; echo rc=$?'");
        CAPTURE(r.output);
        CHECK(r.output.find("rc=134") == std::string::npos);
        CHECK(r.output.find("Not enough memory to run on this device") == std::string::npos);
        const bool ok = r.output.find("rc=0") != std::string::npos, failed = r.output.find("rc=1\n") != std::string::npos;
        CHECK((ok || failed));
        if (failed) CHECK(r.output.find("memory") != std::string::npos);
        if (args == "devices") CHECK(r.output.find("OpenCL not tried: the process's data size (ulimit -d) is limited") !=
                                     std::string::npos);
        if (failed) CHECK(!fs::exists(t.out()));
        fs::remove(t.out());
    }
    // 400 MB of address space: PoCL cannot load; the fallback names the limit, not a
    // missing platform.
    const Run r = run_command("bash -c 'ulimit -v 400000; " + std::string(SNVR_CLI) + " reconstruct " + input + " -o " +
                              t.out() + " --resolution 24; echo rc=$?'");
    CAPTURE(r.output);
    CHECK(r.output.find("rc=0") != std::string::npos);
    CHECK(r.output.find("no OpenCL platform is installed") == std::string::npos);
    CHECK(r.output.find("address space (ulimit -v) is limited to 390 MiB") != std::string::npos);
    CHECK(fs::exists(t.out()));
}

TEST_CASE("a whole run the memory limit cannot hold goes in tiles by itself, the same solid") {
    TempDir t;
    const std::string bunny = std::string(SNVR_DATA_DIR) + "/bunny.ply";
    const std::string args = " reconstruct " + bunny + " -o " + t.out() +
                             " --resolution 256 --precision double --device openmp --report " + t.file("r.json", "");
    const Run free = run(args);
    REQUIRE(free.code == 0);
    CHECK(free.output.find("tiled to fit") == std::string::npos);
    const std::size_t genus_at = free.output.find("genus ");
    REQUIRE(genus_at != std::string::npos);
    const std::string genus = free.output.substr(genus_at, free.output.find(' ', genus_at + 6) - genus_at);
    // Address space limits from where the whole run fits down to where nothing does: each
    // run ends with the shell or an error that names the memory, never a kill; at least one
    // fits only in tiles, and gives the same solid.
    int tiled = 0;
    for (int kb : {320000, 290000, 270000, 250000, 230000, 210000}) {
        CAPTURE(kb);
        const Run r = run_command("bash -c 'ulimit -v " + std::to_string(kb) + "; " + std::string(SNVR_CLI) + args +
                                  "; echo rc=$?'");
        CAPTURE(r.output);
        const bool ok = r.output.find("rc=0") != std::string::npos;
        CHECK((ok || (r.output.find("rc=1\n") != std::string::npos && r.output.find("memory") != std::string::npos)));
        if (ok && r.output.find("tiled to fit the memory available") != std::string::npos) {
            ++tiled;
            CHECK(r.output.find(genus) != std::string::npos);
        }
    }
    CHECK(tiled > 0);
}

TEST_CASE("a .gz input inflated in the temporary folder: --temp-dir checked, a folder without room named, nothing left") {
    TempDir t;
    std::string text;
    for (int copy = 0; copy < 400; ++copy) text += sphere_xyz();  // about 3 MB, compressed far smaller
    const std::string input = t.file("in.xyz.gz", "");
    {
        gzFile f = gzopen(input.c_str(), "wb");
        REQUIRE(f != nullptr);
        REQUIRE(gzwrite(f, text.data(), unsigned(text.size())) == int(text.size()));
        gzclose(f);
    }
    const std::string run_args = " reconstruct " + input + " -o " + t.out() + " --resolution 24";
    expect_failure(run_args + " --temp-dir " + t.file("absent", "") + "/not-there", 1, "is not a directory", t);
    fs::create_directories(t.path / "tmp");
    // 1 MiB of file size allowed: the inflated file (3 MB) stops there, named.
    const Run r = run_command("bash -c 'ulimit -f 1024; " + std::string(SNVR_CLI) + run_args + " --temp-dir " +
                              (t.path / "tmp").string() + "; echo rc=$?'");
    CAPTURE(r.output);
    CHECK(r.output.find("rc=1\n") != std::string::npos);
    CHECK(r.output.find("cannot inflate") != std::string::npos);
    CHECK(r.output.find((t.path / "tmp").string()) != std::string::npos);
    CHECK(!fs::exists(t.out()));
    CHECK(fs::is_empty(t.path / "tmp"));
    // With room, beside the output by default: the run, and nothing left beside it.
    const Run ok = run(run_args);
    CAPTURE(ok.output);
    CHECK(ok.code == 0);
    std::size_t entries = 0;
    for (const auto& e : fs::directory_iterator(t.path)) entries += e.path().filename() != "tmp";
    CHECK(entries == 3);  // absent's empty file, the input and the output
}

TEST_CASE("file-size and open-file limits, a reader that has gone: a reported failure or a finished run, never a kill") {
    TempDir t;
    const std::string input = t.file("in.xyz", sphere_xyz());
    const std::string cli = SNVR_CLI;
    for (const std::string device : {"openmp", "auto"}) {
        CAPTURE(device);
        // 100 KiB files: the 96^3 volume does not fit. Before, SIGXFSZ killed the run.
        const Run r = run_command("bash -c 'ulimit -f 100; " + cli + " reconstruct " + input + " -o " + t.out() +
                                  " --volume " + (t.path / "v.vti").string() + " --resolution 96 --quiet --device " +
                                  device + "; echo rc=$?'");
        CAPTURE(r.output);
        CHECK(r.output.find("rc=1\n") != std::string::npos);
        CHECK(r.output.find("cannot write") != std::string::npos);
        CHECK(r.output.find("File too large") != std::string::npos);
        CHECK(entries(t.path) == std::set<std::string>{"in.xyz"});
    }
    // Five open files: the report's cannot be opened; nothing is left.
    const Run few = run_command("bash -c 'ulimit -n 5; " + cli + " reconstruct " + input + " -o " + t.out() +
                                " --volume " + (t.path / "v.vti").string() + " --report " + (t.path / "r.json").string() +
                                " --resolution 32 --quiet; echo rc=$?'");
    CAPTURE(few.output);
    CHECK(few.output.find("rc=1\n") != std::string::npos);
    CHECK(few.output.find("Too many open files") != std::string::npos);
    CHECK(entries(t.path) == std::set<std::string>{"in.xyz"});
    // Progress to a pipe whose reader has gone: before, SIGPIPE killed the run.
    const Run r = run_command("bash -c '" + cli + " reconstruct " + input + " -o " + t.out() +
                              " --resolution 48 2>&1 | head -c 0; echo rc=${PIPESTATUS[0]}'");
    CAPTURE(r.output);
    CHECK(r.output.find("rc=0") != std::string::npos);
    CHECK(entries(t.path) == std::set<std::string>{"in.xyz", "out.stl"});
}

TEST_CASE("two outputs naming one file are refused before the run") {
    TempDir t;
    const std::string input = t.file("in.xyz", sphere_xyz());
    fs::create_directories(t.path / "sub");
    const std::string same = (t.path / "same.ply").string(), other = (t.path / "sub" / ".." / "same.ply").string();
    for (const std::string& args : {"-o " + same + " --outliers " + same, "-o " + same + " --outliers " + other,
                                    "-o " + t.out() + " --report " + (t.path / "r.json").string() + " --outliers " +
                                        t.out() + ".xyz --preview " + (t.path / "p.png").string() + " --volume " +
                                        (t.path / "sub" / ".." / "v.vti").string() + " --keep-largest 1"}) {
        CAPTURE(args);
        const Run r = run("reconstruct " + input + " " + args + " --resolution 32");
        CAPTURE(r.output);
        if (args.find("--keep-largest") != std::string::npos) {  // distinct files: it runs
            CHECK(r.code == 0);
            continue;
        }
        CHECK(r.code == 2);
        CHECK(r.output.find("name one file") != std::string::npos);
        CHECK(!fs::exists(same));
    }
}

TEST_CASE("all outputs or none: a folder gone before the renames leaves every target as it was") {
    TempDir t;
    fs::create_directories(t.path / "a");
    fs::create_directories(t.path / "b");
    {
        snvr::OutputFiles out;
        out.add_bytes("mesh", (t.path / "a" / "o.stl").string());
        out.add_bytes("volume", (t.path / "b" / "v.vti").string());
        fs::remove_all(t.path / "b");  // its unnamed temporary has no name to keep it
        CHECK_THROWS_AS(out.commit(), snvr::IoError);
    }
    CHECK(entries(t.path / "a").empty());
}

TEST_CASE("counts, ranges and lengths: each absurd value refused at once, naming its option and the range") {
    TempDir t;
    const std::string input = t.file("in.xyz", sphere_xyz());
    const std::string o = " -o " + t.out() + " --quiet";
    struct Refusal {
        const char* options;
        int code;
        const char* words;
    };
    const Refusal refusals[] = {
        // Usage: the option, the value and the range, before anything is read.
        {"--fairing=2147483647", 2, "--fairing"},
        {"--fairing 100000000", 2, "0 to 100 passes"},
        {"--smoothing 1e5", 2, "(--smoothing) must be at least 0 and at most 1000"},
        {"--xi-cells 1e5", 2, "(--xi-cells) must be above 0 and at most 100 cells"},
        {"--eps-cells 1e5", 2, "(--eps-cells)"},
        {"--dt-cells 1e308", 2, "(--dt-cells)"},
        {"--scale 1e308", 2, "--scale: expected a factor from 1e-6 to 1e6"},
        {"--scale 1e-300", 2, "--scale"},
        {"--resolution 100000", 2, "(--resolution) must be at least 16"},
        // Derived from the points: named too, with the bound.
        {"--xi 1e5", 1, "xi (--xi) 1e+05 is more than 1000 times"},
        {"--xi 1.9 --resolution 32", 1, "xi (--xi) 1.9 is 103 cells"},
        {"--thickness 1e308", 1, "the thickness (--thickness) 1e+308"},
        {"--dt 1e308", 1, "dt (--dt) 1e+308 is"},
        {"--smoothing 1000 --dt-cells 0.001", 1, "(--smoothing)"},
        {"--min-piece-volume 1e5", 1, "is smaller than the least volume kept, 100000 (--min-piece-volume)"},
    };
    for (const Refusal& r : refusals) expect_failure("reconstruct " + input + o + " " + r.options, r.code, r.words, t);
    expect_failure("reconstruct -" + o, 2, "standard input", t);
}

TEST_CASE("hostile files: cut, contradictory or inflated, each named") {
    TempDir t;
    const std::string o = " -o " + t.out() + " --quiet";
    const std::string facet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
    expect_failure("reconstruct " + t.file("cut.stl", "solid x\n" + facet + facet + "facet normal 0 0 1\nouter loop\n") + o,
                   1, "ends inside a facet", t);
    expect_failure("reconstruct " + t.file("cut2.stl", "solid x\n" + facet + "facet normal 0 0 1\n") + o, 1,
                   "ends inside a facet", t);
    expect_failure("reconstruct " + t.file("neg.off", "OFF\n4 -1 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n") + o, 1,
                   "expected the vertex and face counts", t);
    std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                      "property float z\nelement face 4294967295\nproperty list uchar int vertex_indices\nend_header\n";
    ply += std::string(36, '\0');
    const std::string claims = t.file("claims.ply", ply);
    expect_failure("reconstruct " + claims + o, 1, claims + ": the header's element 'face' claims 4294967295 records", t);
    expect_failure("reconstruct " + t.file("far.obj", "v 0 0 0\nv 1 0 0\nv 0 1 1e308\nf 1 2 3\n") + o, 1,
                   "vertex 2 (0, 1, 1e+308) lies beyond 32-bit float range", t);
    const std::string tiny = t.file("tiny.las", las(1e-320));
    expect_failure("reconstruct " + tiny + o, 1, tiny + ": the header's x scale 1e-320", t);
    const Run fine = run("reconstruct " + t.file("fine.las", las(1e-4)) + o);
    CHECK(fine.code == 0);
    fs::remove(t.out());
    // 64 MiB of zeros as .xyz.gz: refused on its first inflated bytes.
    const std::string bomb = t.file("bomb.xyz.gz", snvr::testing::gzip(std::string(std::size_t(64) << 20, '\0')));
    expect_failure("reconstruct " + bomb + o, 1, "does not start as text", t);
}

TEST_CASE("control characters never reach the terminal, C1 ones included") {
    TempDir t;
    const std::string input = t.file("in.xyz", sphere_xyz());
    for (const std::string name : {"o\x1b[31m.stl", "o\xc2\x9b" "31m.stl", "o\xc2\x85.stl"}) {
        const std::string out = (t.path / name).string();
        const Run r = run("reconstruct " + input + " -o '" + out + "' --resolution 32");
        CAPTURE(r.output);
        CHECK(r.code == 0);
        CHECK(r.output.find('\x1b') == std::string::npos);
        CHECK(r.output.find("\xc2\x9b") == std::string::npos);
        CHECK(r.output.find("\xc2\x85") == std::string::npos);
        CHECK(r.output.find("wrote") != std::string::npos);
        CHECK(fs::exists(out));
    }
}
