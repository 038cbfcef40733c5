// A program run as its own process with a time limit, its stdout thrown away and its
// stderr kept: for the campaigns, which must tell an exit from a signal from a hang.
#pragma once
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

namespace snvr::testing {

struct BoundedRun {
    int code = -2;       // exit status; -1 a signal, -3 killed at the time limit, -2 not started
    std::string stderr_text;
};

// argv[0] is the program's path; `cwd` (when not empty) its working folder; `scratch` a
// file for its stderr, removed afterwards.
inline BoundedRun run_bounded(std::vector<std::string> argv, const std::string& cwd, const std::string& scratch,
                              double seconds) {
    BoundedRun r;
    std::vector<char*> args;
    for (std::string& a : argv) args.push_back(a.data());
    args.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, scratch.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    if (!cwd.empty()) posix_spawn_file_actions_addchdir_np(&actions, cwd.c_str());
    pid_t pid = -1;
    const int failed = posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (failed) return r;
    const auto start = std::chrono::steady_clock::now();
    int status = 0;
    for (;;) {
        if (waitpid(pid, &status, WNOHANG) == pid) break;
        if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > seconds) {
            ::kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            r.code = -3;
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    if (r.code != -3) r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    {
        std::ifstream in(scratch);
        r.stderr_text.assign(std::istreambuf_iterator<char>(in), {});
    }
    std::remove(scratch.c_str());
    return r;
}

}  // namespace snvr::testing
