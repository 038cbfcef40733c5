#include "spawn.hpp"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace snvr::bench {

std::string ProgramRun::why() const {
    // The end of the output is where a program says what went wrong.
    constexpr std::size_t kTail = 400;
    std::string tail = output.size() > kTail ? output.substr(output.size() - kTail) : output;
    for (char& c : tail)
        if (c == '\n' || c == '\r') c = ' ';
    while (!tail.empty() && tail.back() == ' ') tail.pop_back();
    return (signal ? "signal " + std::to_string(signal) : "exit " + std::to_string(exit_code)) + ": " + tail;
}

ProgramRun run_program(const std::vector<std::string>& argv) {
    if (argv.empty()) throw std::runtime_error("run_program: no program");
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    int fds[2];
    if (::pipe(fds) != 0) throw std::runtime_error("pipe() failed");
    std::fflush(nullptr);
    const auto start = std::chrono::steady_clock::now();
    const pid_t pid = ::fork();
    if (pid < 0) throw std::runtime_error("fork() failed");
    if (pid == 0) {
        ::dup2(fds[1], 1);
        ::dup2(fds[1], 2);
        ::close(fds[0]);
        ::close(fds[1]);
        ::execv(args[0], args.data());
        std::fprintf(stderr, "cannot run %s: %s\n", args[0], std::strerror(errno));
        ::_exit(127);
    }
    ::close(fds[1]);
    ProgramRun run;
    char buf[4096];
    ssize_t n;
    while ((n = ::read(fds[0], buf, sizeof buf)) > 0 || (n < 0 && errno == EINTR))
        if (n > 0) run.output.append(buf, std::size_t(n));
    ::close(fds[0]);
    int status = 0;
    rusage usage{};
    while (::wait4(pid, &status, 0, &usage) < 0)
        if (errno != EINTR) throw std::runtime_error("wait4() failed");
    run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    run.peak_mib = double(usage.ru_maxrss) / 1024.0;  // KiB on Linux
    const auto seconds_of = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
    run.cpu_seconds = seconds_of(usage.ru_utime) + seconds_of(usage.ru_stime);
    if (WIFEXITED(status)) run.exit_code = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) run.signal = WTERMSIG(status);
    if (run.exit_code == 127 && run.output.rfind("cannot run ", 0) == 0) throw std::runtime_error(run.output);
    return run;
}

}  // namespace snvr::bench
