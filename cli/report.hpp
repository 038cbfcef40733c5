// What snvr-cl tells the user on stderr: progress lines, warnings and the summary.
#pragma once
#include <cstddef>
#include <cstdint>
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
    double read = 0, outliers = 0, mesh = 0, write = 0, check = 0;  // measured by the CLI
    double total = 0;    // from the start to the outputs in place
};

// V-cycles over the run's steps.
struct CycleTotals {
    int total = 0, most_in_a_step = 0, not_converged = 0;
};
CycleTotals cycle_totals(const snvr::Result& result);

struct RunSummary {
    const snvr::Result& result;
    const snvr::MeshQuality& quality;  // its report is check_mesh's
    Seconds seconds;
    std::string output, volume;
    snvr::Vec3 shift{};  // subtracted from the points (--origin center, or by default for STL and 3MF)
    snvr::Vec3 size{};   // the shell's box, in millimetres
    std::string units;   // the input's (--units), and
    double to_mm = 1;    // what its lengths were multiplied by (--units, --scale)
    std::string input;
    std::size_t points = 0;
    std::uint64_t output_bytes = 0, volume_bytes = 0;
    std::vector<std::string> warnings;
    std::size_t outliers = 0;       // points dropped as outliers,
    double outlier_link = 0;        // linked within this (0: not looked for),
    std::string outliers_file;      // and where they went
    snvr::PieceReport pieces;       // --min-piece-volume, --keep-largest
    bool shift_by_default = false;  // the shift was not asked for: the format needed it
};

// The extent of the mesh's vertices along x, y and z.
snvr::Vec3 mesh_size(const snvr::Mesh& mesh);
void print_summary(std::ostream& out, const RunSummary& run);

// Everything the summary says, and the warnings, as a JSON document (--report;
// report_json.cpp).
std::string report_json(const RunSummary& run);

// Peak resident set size of this process in bytes (0 if unknown).
std::size_t peak_rss_bytes();

}  // namespace cli
