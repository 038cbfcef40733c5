// An options campaign: every value-taking option of `snvr-cl reconstruct` with values a
// user may push on it (0, negative, NaN, inf, 1e308, beyond int, empty, garbage, tiny),
// and outputs a user may aim wrongly (a device file, a missing or read-only folder, two
// outputs at one file). None may crash or hang; a usage error (exit 2) names its option;
// any failure leaves no output and no temporary. Seeded order, two runs at a time.
#include <doctest/doctest.h>
#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "bounded_run.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;

namespace {

constexpr double kTimeLimit = 60;  // seconds a run may take (a healthy one takes a tenth)

// The options that take a number or a word, as the help lists them.
const char* const kOptions[] = {"--units",     "--scale",     "--min-piece-volume", "--keep-largest", "--origin",
                                "--offset",    "--offset-cells", "--thickness", "--resolution",       "--voxel",        "--smoothing",
                                "--dt-cells",  "--dt",        "--steps",            "--tube-inner",   "--tube-outer",
                                "--eps-cells", "--eps",       "--xi-cells",         "--xi",           "--tol",
                                "--max-cycles", "--precision", "--device",          "--fairing"};
const char* const kValues[] = {"0",     "-1",          "nan",  "inf", "-inf",  "1e308",   "-1e308", "1e-308",
                               "2147483648", "99999999999999999999", "", "garbage", "0.5", "1e5", "16384", "0x10"};

struct Case {
    std::vector<std::string> args;  // after the input
    std::string option;             // the option under test, for the tally
};

struct Outcome {
    int code = -2;  // exit status; -1 a signal, -3 a timeout
    std::string message;
    std::vector<std::string> left;  // the folder's entries afterwards, the input aside
};

Outcome run_one(const fs::path& dir, const std::string& input, const std::vector<std::string>& args) {
    std::vector<std::string> argv{SNVR_CLI, "reconstruct", input};
    argv.insert(argv.end(), args.begin(), args.end());
    const snvr::testing::BoundedRun r =
        snvr::testing::run_bounded(argv, dir.string(), (dir.parent_path() / (dir.filename().string() + ".stderr")).string(),
                                   kTimeLimit);
    Outcome o;
    o.code = r.code;
    o.message = r.stderr_text;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        const std::string name = fs::relative(e.path(), dir).string();
        if (name != "in.xyz" && !e.is_directory()) o.left.push_back(name);
    }
    return o;
}

}  // namespace

TEST_CASE("options campaign: every option's absurd values and misaimed outputs, no crash, no hang, nothing left") {
    std::vector<Case> cases;
    for (const std::string option : kOptions)
        for (const char* value : kValues) {
            // A small grid, unless the grid is what is under test.
            std::vector<std::string> args{"-o", "out.stl", option, value};
            if (option != "--resolution" && option != "--voxel") args.insert(args.end(), {"--resolution", "24"});
            cases.push_back({args, option});
        }
    // Outputs aimed wrongly.
    for (const std::vector<std::string>& args :
         {std::vector<std::string>{"-o", "/dev/full.stl"}, {"-o", "/dev/null"}, {"-o", "missing/out.stl"},
          {"-o", "locked/out.stl"}, {"-o", "out.stl", "--volume", "out.stl"}, {"-o", "out.stl", "--report", "./out.stl"},
          {"-o", "out.stl", "--outliers", "sub/../out.ply"}, {"-o", "out.ply", "--outliers", "sub/../out.ply"},
          {"-o", "in.xyz.stl", "--volume", "locked/v.vti"}, {"-o", ""}, {"-o", "sub"}, {"-o", "out.stl", "--preview", ""}}) {
        std::vector<std::string> with = args;
        with.insert(with.end(), {"--resolution", "24"});
        cases.push_back({with, "output path"});
    }
    std::mt19937_64 order(20261126);
    std::shuffle(cases.begin(), cases.end(), order);

    snvr::testing::TempDir root("options");
    std::string points;
    char line[96];
    for (int i = 0; i < 12; ++i)
        for (int j = 0; j < 24; ++j) {
            const double th = M_PI * (i + 0.5) / 12, ph = M_PI * j / 12;
            std::snprintf(line, sizeof line, "%.6f %.6f %.6f\n", std::sin(th) * std::cos(ph),
                          std::sin(th) * std::sin(ph), std::cos(th));
            points += line;
        }
    std::vector<Outcome> outcomes(cases.size());
    std::atomic<std::size_t> next{0};
    std::vector<std::thread> workers;
    for (int w = 0; w < 2; ++w)
        workers.emplace_back([&, w] {
            const fs::path dir = root.path / ("w" + std::to_string(w));
            for (std::size_t i; (i = next++) < cases.size();) {
                fs::create_directories(dir / "sub");
                fs::create_directories(dir / "locked");
                std::ofstream(dir / "in.xyz") << points;
                ::chmod((dir / "locked").c_str(), 0500);
                outcomes[i] = run_one(dir, (dir / "in.xyz").string(), cases[i].args);
                ::chmod((dir / "locked").c_str(), 0700);
                fs::remove_all(dir);
            }
        });
    for (auto& t : workers) t.join();

    std::map<std::string, std::array<int, 3>> tally;  // option: {ran, usage, failed}
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const Outcome& o = outcomes[i];
        std::string args;
        for (const std::string& a : cases[i].args) args += "'" + a + "' ";
        CAPTURE(args);
        CAPTURE(o.message);
        REQUIRE(o.code >= 0);  // no signal, no hang, spawned
        CHECK((o.code == 0 || o.code == 1 || o.code == 2));
        if (o.code == 0) {
            ++tally[cases[i].option][0];
            continue;
        }
        ++tally[cases[i].option][o.code == 2 ? 1 : 2];
        CHECK(o.left.empty());  // no output, no temporary
        CHECK(o.message.find("snvr-cl: error: ") != std::string::npos);
        if (o.code == 2 && cases[i].option != "output path") CHECK(o.message.find(cases[i].option) != std::string::npos);
        for (const char* wrong : {"inf cells", "-2147483648", "not positive definite", "Aborted"})
            CHECK(o.message.find(wrong) == std::string::npos);
    }
    for (const auto& [option, counts] : tally)
        MESSAGE(option << ": " << counts[0] << " ran, " << counts[1] << " usage errors, " << counts[2] << " failures");
}
