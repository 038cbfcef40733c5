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

namespace cli {

using snvr::grouped;

// "snvr-cl: warning: ..." on stderr; never silenced by --quiet.
void warn(const std::string& message);

// One line per callback: stage messages and per-step solver statistics.
void print_progress(std::ostream& out, const snvr::Progress& progress);

}  // namespace cli
