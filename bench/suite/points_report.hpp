// The points section's outputs: its Markdown tables (whole runs beside the peers, then
// our stages) and points.dat for bench/plots.gp.
#pragma once
#include <string>
#include <vector>

#include "record.hpp"

namespace snvr::bench {

// "" when no record is of the points section.
std::string points_markdown(const std::vector<Record>& records);

// points.dat in `dir`: one line per program, grid and cloud (see bench/plots.gp).
void write_points_data(const std::vector<Record>& records, const std::string& dir);

}  // namespace snvr::bench
