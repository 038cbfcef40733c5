// What snvr-cl tells the user on stderr: progress lines, warnings and the summary.
#pragma once
#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

#include "snvr/mesh.hpp"
#include "snvr/quality.hpp"
#include "snvr/reconstruct.hpp"

namespace cli {

#if defined(__GNUC__)
#define SNVR_CLI_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define SNVR_CLI_PRINTF(a, b)
#endif

// printf into a std::string.
std::string fmt(const char* format, ...) SNVR_CLI_PRINTF(1, 2);
// 1234567 -> "1,234,567".
std::string grouped(std::size_t n);

// "snvr-cl: warning: ..." on stderr; never silenced by --quiet.
void warn(const std::string& message);

// One line per callback: stage messages and per-step solver statistics.
void print_progress(std::ostream& out, const snvr::Progress& progress);

struct Seconds {
    double read = 0, mesh = 0, write = 0, check = 0;  // measured by the CLI
    double total = 0;    // from the start to the outputs in place
};

struct RunSummary {
    const snvr::Result& result;
    const snvr::MeshQuality& quality;  // its report is check_mesh's
    Seconds seconds;
    std::string output, volume;
    snvr::Vec3 shift{};  // subtracted from the points (--origin center)
};
void print_summary(std::ostream& out, const RunSummary& run);

// Peak resident set size of this process in bytes (0 if unknown).
std::size_t peak_rss_bytes();

}  // namespace cli
