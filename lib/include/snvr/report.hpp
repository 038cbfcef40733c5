// The run's report: one structure, built once from the shell and what the caller did
// around it (the file read, the files written), and its views: the summary snvr-cl
// prints, the JSON of --report, and (in Python) the dict of that JSON.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "snvr/shell.hpp"

namespace snvr {

// What the caller did around make_shell (all of it optional).
struct RunFiles {
    std::string input;                    // the points' file
    double read_seconds = 0;              // reading it
    struct Output {
        std::string path, kind;           // kind: "mesh" or "volume"
        std::uint64_t bytes = 0;
    };
    std::vector<Output> outputs;          // the files written, in order
    std::string outliers_file;            // where the outliers went
    double write_seconds = 0;
    double total_seconds = 0;             // 0: the read, the shell's total and the write
};

// V-cycles over the run's steps.
struct CycleTotals {
    int total = 0, most_in_a_step = 0, not_converged = 0;
};

// The run as its views see it: the shell (held by reference: it must outlive the
// report), the files around it, and what is taken once for every view.
struct RunReport {
    const Shell& shell;
    RunFiles files;
    CycleTotals cycles;                   // over shell.run.steps
    std::size_t peak_rss_bytes = 0;       // this process's, when the report was made
    std::size_t huge_page_bytes = 0;      // of its memory then, what lies in transparent huge pages
    double total_seconds = 0;             // files.total_seconds, or the read, the shell and the write
};

RunReport make_report(const Shell& shell, const RunFiles& files = {});

// A stage's cost by the unit of work it grows with, beside the bytes it must touch at the
// least (each once): at a machine's stream rate those bytes are a floor the stage cannot go
// below (snvr-bench's stages section sets the two side by side). The distance and the
// initialisation go by band cell, the steps by band cell and step, the mesh stage, the
// check and the write by triangle of the shell.
struct StageUnit {
    std::string stage;        // as the report's seconds name it
    std::string unit;         // "band cell", "band cell a step", "triangle"
    double units = 0;         // how many
    double ns = 0;            // nanoseconds a unit (0 where there are none)
    double floor_bytes = 0;   // bytes the stage must read or write at the least
};
std::vector<StageUnit> stage_units(const RunReport& report);
CycleTotals cycle_totals(const std::vector<StepStats>& steps);

// The summary's rows, "  key  value" a line (values printable: control bytes escaped).
std::string report_summary(const RunReport& report);
// Everything the summary says, and the warnings, as a JSON document (lengths in mm).
std::string report_json(const RunReport& report);

// Peak resident set size of this process in bytes (0 if unknown).
std::size_t peak_rss_bytes();
// This process's anonymous memory in transparent huge pages now, in bytes (0 if unknown).
std::size_t huge_page_bytes();
// 1234567 -> "1,234,567".
std::string grouped(std::size_t n);
// printf into a std::string (the summary's rows, and messages about a run).
std::string format_text(const char* format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace snvr
