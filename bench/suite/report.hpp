// snvr-bench's outputs from its records: the Markdown tables (with Table 2's observed
// order and Table 1's ratio to the paper) and whitespace-separated .dat files for plots.
#pragma once
#include <string>
#include <vector>

#include "record.hpp"

namespace snvr::bench {

std::string markdown(const std::vector<Record>& records, const std::string& heading);

// Writes scaling.dat, roofline.dat and table2.dat into `dir` (see bench/plots.gp).
void write_plot_data(const std::vector<Record>& records, const std::string& dir);

}  // namespace snvr::bench
