// snvr-bench's outputs from its records: the Markdown tables (with Table 2's observed
// order and Table 1's ratio to the paper; the points section's from points_report.hpp)
// and whitespace-separated .dat files for plots.
#pragma once
#include <string>
#include <vector>

#include "record.hpp"

namespace snvr::bench {

std::string markdown(const std::vector<Record>& records, const std::string& heading);

// Writes scaling.dat, roofline.dat, table2.dat and points.dat into `dir` (see bench/plots.gp).
void write_plot_data(const std::vector<Record>& records, const std::string& dir);

}  // namespace snvr::bench
