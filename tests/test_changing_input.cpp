// Input that another process changes while it is read (a scanner or a copy still writing
// it, a failing disk): cut short, extended, or an EIO, at a chosen byte through the
// library's test hook SNVR_TEST_READ_FAULT (the real truncation or growth of the file,
// at a place rather than a time). Exit 1 naming the change, nothing written, never a
// signal; the library throws IoError.
#include <doctest/doctest.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "cli_run.hpp"
#include "snvr/error.hpp"
#include "snvr/point_io.hpp"
#include "snvr/shapes.hpp"
#include "test_files.hpp"

using namespace cli_testing;

namespace {

struct Input {
    std::string name, bytes;
};

std::vector<Input> inputs(const TempDir& t) {
    const snvr::PointSet sphere = snvr::shapes::sphere({0.5, 0.5, 0.5}, 0.3, 0.03);
    const std::string ply = (t.path / "made.ply").string(), xyz = (t.path / "made.xyz").string();
    snvr::write_points(sphere, ply);
    snvr::write_points(sphere, xyz);
    const auto bytes_of = [](const std::string& path) {
        std::ifstream in(path, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    return {{"in.ply", bytes_of(ply)},
            {"in.xyz", bytes_of(xyz)},
            {"in.las", snvr::testing::las_file(sphere, 1e-6, 0.0)},
            {"in.xyz.gz", snvr::testing::gzip(bytes_of(xyz))}};
}

// Sets the hook for this process's reads while it lives.
struct Fault {
    explicit Fault(const std::string& spec) { ::setenv("SNVR_TEST_READ_FAULT", spec.c_str(), 1); }
    ~Fault() { ::unsetenv("SNVR_TEST_READ_FAULT"); }
};

}  // namespace

TEST_CASE("snvr-cl: an input cut short, extended or failing while it is read exits 1 naming it") {
    TempDir t;
    for (const Input& in : inputs(t)) {
        const std::size_t size = in.bytes.size();
        // Before the header ends, in the middle, at the last byte.
        for (const std::size_t at : {std::size_t(10), size / 2, size - 1}) {
            const std::string where = std::to_string(at);
            const std::string path = t.file(in.name, in.bytes);
            const std::string args = "reconstruct " + path + " -o " + t.out() + " --resolution 16 --device openmp";
            expect_failure(args, 1,
                           path + ": the file changed while it was read (it shrank from " + std::to_string(size) +
                               " to " + where + " bytes)",
                           t, "SNVR_TEST_READ_FAULT=shrink:" + where);
            t.file(in.name, in.bytes);
            expect_failure(args, 1,
                           path + ": the file changed while it was read (it grew from " + std::to_string(size) +
                               " to " + std::to_string(size + 4096) + " bytes)",
                           t, "SNVR_TEST_READ_FAULT=grow:" + where);
            t.file(in.name, in.bytes);
            expect_failure(args, 1, "cannot read '" + path + "': Input/output error", t,
                           "SNVR_TEST_READ_FAULT=eio:" + where);
        }
    }
    // A gzip file cut short before it was read is refused as before, by its own reason.
    const std::vector<Input> all = inputs(t);
    const std::string cut = t.file("cut.xyz.gz", all.back().bytes.substr(0, all.back().bytes.size() / 2));
    expect_failure("reconstruct " + cut + " -o " + t.out() + " --resolution 16 --device openmp", 1,
                   "the gzip data ends early", t);
}

TEST_CASE("the library: a large file read by the threads, changed in one part, throws IoError") {
    TempDir t;
    // Binary PLY: records read part by part by each thread; text over 16 MiB: read whole
    // by the threads in 4 MiB parts.
    const snvr::PointSet many = snvr::shapes::sphere({0.5, 0.5, 0.5}, 0.3, 0.0008);
    for (const char* name : {"many.ply", "many.xyz"}) {
        CAPTURE(name);
        const std::string path = (t.path / name).string();
        snvr::write_points(many, path);
        std::ifstream in(path, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), {});
        REQUIRE(bytes.size() > (std::size_t(16) << 20));
        for (const char* kind : {"shrink", "grow", "eio"}) {
            CAPTURE(kind);
            t.file(name, bytes);
            const Fault fault(std::string(kind) + ":" + std::to_string(bytes.size() * 2 / 3));
            CHECK_THROWS_AS(snvr::read_point_cloud(path), snvr::IoError);
            t.file(name, bytes);
            CHECK_THROWS_AS(snvr::read_points(path), snvr::IoError);
        }
        t.file(name, bytes);
        CHECK(snvr::read_point_cloud(path).size() == many.size());  // unchanged: read whole
    }
}

TEST_CASE("snvr-cl under address-space limits: a run, or our error naming memory and the limit; never the runtime's") {
    TempDir t;
    const std::string bunny = std::string(SNVR_DATA_DIR) + "/bunny.ply";
    if (!fs::exists(bunny)) return;  // the scans sit beside the checkout
    // From too small for a second thread to too small for the grid, in our words every time.
    for (const long mib : {20L, 30L, 45L, 70L, 100L})
        for (const int resolution : {24, 96}) {
            const std::string command = "prlimit --as=" + std::to_string(mib << 20) + " " + SNVR_CLI + " reconstruct " +
                                        bunny + " -o " + t.out() + " --resolution " + std::to_string(resolution) +
                                        " --device auto --quiet";
            CAPTURE(command);
            const Run r = run_command(command);
            CAPTURE(r.output);
            CHECK((r.code == 0 || r.code == 1));
            CHECK(r.output.find("libgomp") == std::string::npos);
            CHECK(r.output.find("error: Resource temporarily unavailable") == std::string::npos);
            if (r.code == 1) {
                CHECK(r.output.find("memory") != std::string::npos);
                CHECK(r.output.find("limited to") != std::string::npos);
                CHECK(!fs::exists(t.out()));
            }
            // Each note once: the backend is made once, after the planning, under a limit.
            const std::size_t fallback = r.output.find("OpenCL not usable");
            CHECK((fallback == std::string::npos || r.output.find("OpenCL not usable", fallback + 1) == std::string::npos));
            if (r.output.find("running on one thread") != std::string::npos)
                CHECK(r.output.find("limited to") != std::string::npos);
            fs::remove(t.out());
        }
}
