// Running snvr-cl as a user does, for the CLI suites: its exit code and what it
// printed, in a scratch directory of its own.
#pragma once
#include <doctest/doctest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace cli_testing {

namespace fs = std::filesystem;

struct Run {
    int code;
    std::string output;  // stdout and stderr together
};

// A shell command line, stderr joined to stdout.
inline Run run_command(const std::string& command) {
    const std::string cmd = command + " 2>&1";
    Run r{-1, {}};
    FILE* p = popen(cmd.c_str(), "r");
    REQUIRE(p != nullptr);
    char buf[4096];
    std::size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
    const int status = pclose(p);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

// `env`: variable assignments for the command, e.g. "OCL_ICD_VENDORS=/x".
inline Run run(const std::string& args, const std::string& env = "") {
    return run_command(env + " " + std::string(SNVR_CLI) + " " + args);
}

struct TempDir {
    fs::path path = fs::temp_directory_path() / ("snvr-cli-" + std::to_string(::getpid()));
    TempDir() { fs::create_directories(path); }
    ~TempDir() { fs::remove_all(path); }
    std::string file(const std::string& name, const std::string& bytes) const {
        const fs::path f = path / name;
        std::ofstream(f, std::ios::binary) << bytes;
        return f.string();
    }
    std::string out() const { return (path / "out.stl").string(); }
};

inline std::string binary_ply_header(int count) {
    return "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(count) +
           "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
}

inline void expect_failure(const std::string& args, int code, const std::string& words, const TempDir& t,
                    const std::string& env = "") {
    CAPTURE(args);
    CAPTURE(env);
    const Run r = run(args, env);
    CAPTURE(r.output);
    CHECK(r.code == code);
    CHECK(r.output.find(words) != std::string::npos);
    CHECK(!fs::exists(t.out()));
}


}  // namespace cli_testing
