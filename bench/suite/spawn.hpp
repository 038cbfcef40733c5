// Runs another program as a user would, each in its own process: its exit status,
// its wall-clock and CPU seconds and its peak resident memory (wait4's rusage), and
// what it printed. For the benchmarks that time whole command lines.
#pragma once
#include <string>
#include <vector>

namespace snvr::bench {

struct ProgramRun {
    int exit_code = -1;     // the program's exit status, or -1 when it did not exit (a signal)
    int signal = 0;         // the signal that ended it, when one did
    double seconds = 0;     // wall clock, from before the fork to after its end
    double cpu_seconds = 0; // user + system, all its threads: on a shared machine the steadier figure
    double peak_mib = 0;    // ru_maxrss of the program, MiB
    std::string output;     // stdout and stderr together
    bool ok() const { return exit_code == 0; }
    std::string why() const;  // "exit 1: <last lines of output>" or "signal 9: ..."
};

// argv[0] is the program's path (no PATH lookup). Throws std::runtime_error when
// the program cannot be started at all.
ProgramRun run_program(const std::vector<std::string>& argv);

}  // namespace snvr::bench
