// What snvr-cl tells the user on stderr as the run goes: progress lines and warnings (the
// summary is the library's report_summary).
#pragma once
#include <cstddef>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "snvr/reconstruct.hpp"
#include "snvr/report.hpp"
#include "snvr/stopwatch.hpp"

namespace cli {

using snvr::grouped;

// "snvr-cl: warning: ..." on stderr; never silenced by --quiet.
void warn(const std::string& message);

// One line per callback: stage messages and per-step solver statistics.
void print_progress(std::ostream& out, const snvr::Progress& progress);

// Which progress lines are printed: every step and tile, and what a stage did, always; a
// stage's parts and how far it has come, its first always, then at most every few seconds.
class ProgressPace {
public:
    static constexpr double kEverySeconds = 2;
    bool due(const snvr::Progress& progress);

private:
    std::string stage_;  // of the last line printed
    double quiet_ = 0;   // seconds since
    snvr::Stopwatch clock_;
};

}  // namespace cli
