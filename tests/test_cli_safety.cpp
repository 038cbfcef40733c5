// Nothing of the user's is overwritten or lost, whatever happens to a run: the input is
// never an output, a failed output leaves every target as it was, a signal leaves no
// temporary, input that is not a regular file is refused at once, and messages name the
// problem in printable text.
#include <doctest/doctest.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "cli_run.hpp"
#include "snvr/error.hpp"
#include "snvr/reconstruct.hpp"

namespace fs = std::filesystem;
using namespace cli_testing;

namespace {

std::string read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

std::set<std::string> entries(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
    return names;
}

// Points on a sphere of radius r around c, as text.
std::string sphere_points(double r, double cx, double cy, double cz, int rings = 30) {
    std::string text;
    char line[160];
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < 2 * rings; ++j) {
            const double th = M_PI * (i + 0.5) / rings, ph = M_PI * j / rings;
            std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", cx + r * std::sin(th) * std::cos(ph),
                          cy + r * std::sin(th) * std::sin(ph), cz + r * std::cos(th));
            text += line;
        }
    return text;
}

// snvr-cl with these arguments, its output thrown away; returns its pid.
pid_t spawn_cli(const std::vector<std::string>& args) {
    std::vector<char*> argv{const_cast<char*>(SNVR_CLI)};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
    pid_t pid = -1;
    const int failed = posix_spawn(&pid, SNVR_CLI, &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    REQUIRE(failed == 0);
    return pid;
}

bool unnamed_files_work(const fs::path& dir) {
#ifdef O_TMPFILE
    const int fd = ::open(dir.c_str(), O_TMPFILE | O_WRONLY, 0600);
    if (fd < 0) return false;
    ::close(fd);
    return true;
#else
    (void)dir;
    return false;
#endif
}

}  // namespace

TEST_CASE("the input is never an output: same path, ./path, symbolic and hard links") {
    TempDir t;
    const std::string input = t.file("scan.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                                                 "property float y\nproperty float z\nend_header\n"
                                                 "0 0 0\n1 0 0\n0 1 0\n0 0 1\n");
    const std::string before = read_bytes(input);
    fs::create_symlink(input, t.path / "link.ply");
    fs::create_hard_link(input, t.path / "hard.ply");
    fs::create_symlink(input, t.path / "phi.vti");
    const std::string dir = t.path.string();
    for (const std::string& args : {"reconstruct " + input + " -o " + input,
                                    "reconstruct " + input + " -o " + dir + "/./scan.ply",
                                    "reconstruct " + input + " -o " + dir + "/link.ply",
                                    "reconstruct " + dir + "/hard.ply -o " + input,
                                    "reconstruct " + input + " -o " + t.out() + " --volume " + dir + "/phi.vti"}) {
        CAPTURE(args);
        const Run r = run(args + " --resolution 32");
        CAPTURE(r.output);
        CHECK(r.code == 1);
        CHECK(r.output.find("it is the input") != std::string::npos);
        CHECK(read_bytes(input) == before);
        CHECK(!fs::exists(t.out()));
    }
}

TEST_CASE("a failed output leaves every target as it was, and exit 1 means nothing was written") {
    TempDir t;
    const std::string input = t.file("sphere.xyz", sphere_points(0.3, 0, 0, 0));
    const std::string mesh = t.file("old.ply", "old mesh"), volume = (t.path / "phi.vti").string();
    // Files of at most ~900 KiB: the mesh (~0.7 MB) fits, the 64^3 volume (1 MB) does not.
    const Run r = run_command("bash -c \"trap '' XFSZ; ulimit -f 900; " + std::string(SNVR_CLI) + " reconstruct " +
                              input + " -o " + mesh + " --volume " + volume +
                              " --resolution 64 --device openmp --quiet\"");
    CAPTURE(r.output);
    CHECK(r.code == 1);
    CHECK(r.output.find("cannot write '" + volume + "'") != std::string::npos);
    CHECK(read_bytes(mesh) == "old mesh");
    CHECK(entries(t.path) == std::set<std::string>{"sphere.xyz", "old.ply"});
}

TEST_CASE("SIGINT, SIGTERM or SIGKILL at any moment leaves no temporary and no partial output") {
    TempDir t;
    const std::string input = t.file("sphere.xyz", sphere_points(0.3, 0, 0, 0));
    const std::string mesh = (t.path / "shell.stl").string(), volume = (t.path / "phi.nrrd").string();
    const std::vector<std::string> args{"reconstruct", input, "-o", mesh, "--volume", volume,
                                        "--resolution", "96", "--device", "openmp", "--quiet"};
    const auto started = std::chrono::steady_clock::now();
    int status = 0;
    waitpid(spawn_cli(args), &status, 0);
    const double whole = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    REQUIRE((WIFEXITED(status) && WEXITSTATUS(status) == 0));
    fs::remove(mesh);
    fs::remove(volume);
    std::vector<int> signals{SIGINT, SIGTERM};
    // Where the temporary has no name (O_TMPFILE), even a kill leaves nothing.
    if (unnamed_files_work(t.path)) signals.push_back(SIGKILL);
    else MESSAGE("no unnamed files in " << t.path << ": SIGKILL not tried");
    int stopped = 0;
    for (const int sig : signals)
        for (const double at : {0.3, 0.6, 0.8, 0.9, 0.95, 0.99}) {
            CAPTURE(sig);
            CAPTURE(at);
            const pid_t pid = spawn_cli(args);
            std::this_thread::sleep_for(std::chrono::duration<double>(at * whole));
            ::kill(pid, sig);
            waitpid(pid, &status, 0);
            const bool finished = WIFEXITED(status) && WEXITSTATUS(status) == 0;
            if (!finished) {
                CHECK(WIFSIGNALED(status));
                CHECK(WTERMSIG(status) == sig);  // ended by the signal, as the caller expects
                ++stopped;
            }
            // Either both outputs complete, or neither there; never anything else.
            std::set<std::string> expected{"sphere.xyz"};
            if (fs::exists(mesh) || fs::exists(volume)) expected.insert({"shell.stl", "phi.nrrd"});
            CHECK(entries(t.path) == expected);
            fs::remove(mesh);
            fs::remove(volume);
        }
    CHECK(stopped > 0);  // at least some signals landed during the run
}

TEST_CASE("input that is not a regular file is refused at once") {
    TempDir t;
    const std::string o = " -o " + t.out() + " --quiet";
    const std::string fifo = (t.path / "pipe.ply").string();
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    fs::create_directories(t.path / "folder.ply");
    // `timeout`: a reader that waited for a writer or read forever would fail here, not hang.
    const std::string cli = "timeout 20 " + std::string(SNVR_CLI);
    for (const auto& [input, words] : std::vector<std::pair<std::string, std::string>>{
             {fifo, "it is a named pipe, not a regular file"},
             {"/dev/zero", "it is a character device, not a regular file"},
             {(t.path / "folder.ply").string(), "it is a directory, not a regular file"}}) {
        const Run r = run_command(cli + " reconstruct " + input + o);
        CAPTURE(r.output);
        CHECK(r.code == 1);
        CHECK(r.output.find(words) != std::string::npos);
        CHECK(r.output.find(input) != std::string::npos);
        CHECK(!fs::exists(t.out()));
    }
    // An element of zero-byte items with a count of 2^64 - 1 before the vertices.
    const std::string empty_items =
        t.file("empty_items.ply", "ply\nformat binary_little_endian 1.0\nelement face 18446744073709551615\n"
                                  "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                                  "end_header\n" + std::string(48, '\0'));
    const Run r = run_command(cli + " reconstruct " + empty_items + o);
    CAPTURE(r.output);
    CHECK(r.code == 1);  // read at once (four points at one place), no endless loop
    CHECK(r.output.find("coincide") != std::string::npos);
    // Too many fixed-size items for the bytes that follow.
    expect_failure("reconstruct " +
                       t.file("short_items.ply", "ply\nformat binary_little_endian 1.0\nelement face 1000000\n"
                                                 "property int a\nelement vertex 1\nproperty float x\n"
                                                 "property float y\nproperty float z\nend_header\n" +
                                                     std::string(40, '\0')) + o,
                   1, "expected 1000000 'face' items, file ends after 10", t);
}

TEST_CASE("numbers beyond a double's range, and messages in printable text") {
    TempDir t;
    const std::string o = " -o " + t.out() + " --quiet --resolution 32";
    // 1e-400 is a number (it rounds to 0), not a parse error.
    const Run r = run("reconstruct " + t.file("tiny.xyz", "0 0 0\n1 0 0\n0 1 0\n1e-400 0 1\n") + o);
    CAPTURE(r.output);
    CHECK(r.code == 0);
    fs::remove(t.out());
    expect_failure("reconstruct " + t.file("over.xyz", "0 0 0\n1 0 0\n1e400 1 1\n") + o, 1,
                   "point 2 has a non-finite coordinate (inf 1 1)", t);
    // Points read as floats about one origin: a span of 2e308 fits no origin, refused as read.
    expect_failure("reconstruct " + t.file("span.xyz", "0 0 0\n1 1 1\n1e308 0 0\n-1e308 0 0\n") + o, 1,
                   "span.xyz: point 2 (1e+308 0 0) lies beyond 32-bit float range", t);
    // Points given in memory become a cloud of floats about one origin, which names the two.
    try {
        snvr::plan_domain(snvr::PointSet{{0, 0, 0}, {1, 1, 1}, {1e308, 0, 0}, {-1e308, 0, 0}}, snvr::Parameters{});
        FAIL("a span beyond a float's range was planned");
    } catch (const snvr::InputError& e) {
        CHECK(std::string(e.what()).find("span more than float coordinates can hold along x: point 3 at x = -1e+308 "
                                         "and point 2 at x = 1e+308") != std::string::npos);
    }
    // Control bytes, an escape sequence and a NUL in a bad token are escaped, not printed raw.
    static const char control[] = "0 0 0\n1 \x01\x1b[31mab\0c 1\n";
    const Run bad = run("reconstruct " + t.file("ctl.xyz", std::string(control, sizeof control - 1)) + o);
    CAPTURE(bad.output);
    CHECK(bad.code == 1);
    CHECK(bad.output.find("line 2: expected a number, found '\\x01\\x1b[31mab\\x00c'") != std::string::npos);
    CHECK(bad.output.find('\x1b') == std::string::npos);
}

TEST_CASE("far coordinates: a print format shifted by default, refused when kept, shifted on request") {
    TempDir t;
    // A sphere of radius 3.5 m at x = 500000, y = 4000000, as survey data comes.
    const std::string input = t.file("survey.xyz", sphere_points(3.5, 500000, 4000000, 2));
    const std::string o = " -o " + t.out() + " --resolution 64";
    expect_failure("reconstruct " + input + o + " --origin keep", 1,
                   "stores 32-bit floats, which at coordinates up to 4e+06 move", t);
    // PLY is no print format: kept as read, and refused the same way.
    const std::string ply = (t.path / "survey.ply").string();
    const Run kept = run("reconstruct " + input + " -o " + ply + " --resolution 64");
    CHECK(kept.code == 1);
    CHECK(!fs::exists(ply));
    for (const std::string origin : {"", " --origin center"}) {
        const Run r = run("reconstruct " + input + o + origin + " --report " + (t.path / "r.json").string());
        CAPTURE(r.output);
        CHECK(r.code == 0);
        CHECK(r.output.find("origin           shifted by (-500000, -4000000, -2)") != std::string::npos);
        CHECK((r.output.find("--origin keep keeps the coordinates") != std::string::npos) == origin.empty());
        CHECK(r.output.find("closed yes, manifold yes, oriented yes\n") != std::string::npos);
        CHECK(read_bytes((t.path / "r.json").string()).find(origin.empty() ? "far from the origin (default)"
                                                                         : "\"--origin center\"") != std::string::npos);
        fs::remove(t.out());
    }
    // Near the origin the default keeps the coordinates (no shift, no row).
    const std::string near = t.file("near.xyz", sphere_points(3.5, 5, 4, 2));
    const Run n = run("reconstruct " + near + o);
    CHECK(n.code == 0);
    CHECK(n.output.find("origin ") == std::string::npos);
    fs::remove(t.out());
    // OBJ keeps every digit: no shift needed.
    const std::string obj = (t.path / "survey.obj").string();
    const Run exact = run("reconstruct " + input + " -o " + obj + " --resolution 64");
    CAPTURE(exact.output);
    CHECK(exact.code == 0);
    CHECK(exact.output.find("closed yes, manifold yes, oriented yes\n") != std::string::npos);
}
