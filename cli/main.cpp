// snvr-cl: the command-line front end of libsnvr. Dispatches the subcommand and
// turns exceptions into messages and exit codes (0 ok, 1 failure, 2 usage).
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>

#include <cstdlib>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "commands.hpp"
#include "options.hpp"
#include "processes.hpp"
#include "snvr/error.hpp"
#include "snvr/mesh_io.hpp"

#ifndef SNVR_VERSION
#define SNVR_VERSION "unknown"
#endif

namespace {

constexpr int kFailure = 1;
constexpr int kUsage = 2;

int dispatch(const std::string& command, const std::vector<std::string>& rest) {
    if (command == "reconstruct") return cli::run_reconstruct(rest);
    if (command == "devices") return cli::run_devices(rest);
    if (command == "sample") return cli::run_sample(rest);
    throw cli::UsageError("unknown subcommand '" + command + "' (known: reconstruct, devices, sample)");
}

bool is_subcommand(const std::string& s) { return s == "reconstruct" || s == "devices" || s == "sample"; }

// Settings that the C and OpenMP runtimes read once as the process loads, before main:
// where the user has not chosen them, they are set and the program started again
// (once: the second start finds them chosen).
// - OMP_WAIT_POLICY=passive: OpenMP's default spinning wait made a 64^3 linear step
//   take 15x longer on a shared 2-core machine.
// - glibc.malloc.hugetlb=1 (GLIBC_TUNABLES): the large arrays (the fields, PoCL's
//   buffers, the mesh and its check) advised into transparent huge pages. On a VM
//   (bench/RESULTS.md, "Huge pages") a fresh 4 KiB page cost so much that the bunny
//   at 1024 cells took 35 s with them and 18 s without; peak memory the same. Not
//   under a limit of address space or data: glibc then rounds its heap's growth to 2 MiB,
//   and a tight limit met that in libgomp's start, which aborts, before ours could say so.
bool memory_limited() {
    for (const int resource : {RLIMIT_AS, RLIMIT_DATA}) {
        rlimit limit{};
        if (::getrlimit(resource, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) return true;
    }
    return false;
}

void start_with_runtime_settings(char** argv) {
    bool changed = false;
    if (std::getenv("OMP_WAIT_POLICY") == nullptr) {
        ::setenv("OMP_WAIT_POLICY", "passive", 1);
        changed = true;
    }
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    const std::string chosen = tunables ? tunables : "";
    if (chosen.find("glibc.malloc.hugetlb") == std::string::npos && !memory_limited()) {
        ::setenv("GLIBC_TUNABLES", (chosen.empty() ? "" : chosen + ":").append("glibc.malloc.hugetlb=1").c_str(), 1);
        changed = true;
    }
    if (changed) ::execv("/proc/self/exe", argv);  // returns only on failure: carry on as started
}

// Ctrl-C, a terminal closing or a SIGTERM while a temporary has a name (briefly before
// its rename, or throughout where the file system has no unnamed files) removes it,
// then ends the process by the same signal, as the caller expects.
extern "C" void remove_temporaries_and_stop(int sig) {
    snvr::remove_temporary_files();
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

void remove_temporaries_on_signals() {
    for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
        struct sigaction old {};
        if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;  // nohup and the like
        struct sigaction action {};
        action.sa_handler = remove_temporaries_and_stop;
        sigemptyset(&action.sa_mask);
        ::sigaction(sig, &action, nullptr);
    }
}

// A reader that has gone (a closed stderr pipe) or a file-size limit would otherwise
// kill the run by SIGPIPE or SIGXFSZ, between a temporary's creation and its rename:
// ignored, they make the write fail instead, which the run reports (or, for messages,
// drops) and cleans up after like any other failed write.
void writes_fail_rather_than_kill() {
    std::signal(SIGPIPE, SIG_IGN);
    std::signal(SIGXFSZ, SIG_IGN);
}

// Under MPI a message says which process it is from (a failure may be one process's).
std::string who() {
    return cli::process_count() > 1 ? " (process " + std::to_string(cli::process_rank()) + " of " +
                                          std::to_string(cli::process_count()) + ")"
                                    : "";
}

// A message to stderr in one write: unit-buffered, each << was a write of its own, and
// under MPI the launcher's lines came in between (a failure's "snvr-cl: error" and its
// "(process 1 of 2): tile 1 ..." parted by MPI_ABORT's notice).
void tell(const std::string& message) { std::cerr << message << std::flush; }

int run(const std::vector<std::string>& args, const std::string& command) {
    try {
        if (command.empty()) throw cli::UsageError("no subcommand given");
        if (command == "-h" || command == "--help") {
            cli::print_main_help(std::cout);
            return 0;
        }
        if (command == "--version") {
            std::cout << "snvr-cl " << SNVR_VERSION << '\n';
            return 0;
        }
        return dispatch(command, std::vector<std::string>(args.begin() + 1, args.end()));
    } catch (const cli::UsageError& e) {
        // Every process reads the same command line: the first says so.
        if (cli::process_rank() == 0)
            tell("snvr-cl: error: " + snvr::printable(e.what()) + "\nRun 'snvr-cl " +
                 (is_subcommand(command) ? command + " " : std::string()) + "--help' for usage.\n");
        return kUsage;
    } catch (const std::bad_alloc&) {
        tell("snvr-cl: error" + who() + ": out of memory\n");
        return kFailure;
    } catch (const std::exception& e) {
        tell("snvr-cl: error" + who() + ": " + snvr::printable(e.what()) + "\n");
        return kFailure;
    }
}

}  // namespace

int main(int argc, char** argv) {
    start_with_runtime_settings(argv);
    remove_temporaries_on_signals();
    writes_fail_rather_than_kill();
    try {
        cli::start_processes(argc, argv);
    } catch (const std::exception& e) {
        tell("snvr-cl: error: " + snvr::printable(e.what()) + "\n");
        return kFailure;
    }
    const std::vector<std::string> args(argv + 1, argv + argc);
    const int status = run(args, args.empty() ? "" : args[0]);
    cli::end_processes(status == kFailure);
    return status;
}
