// The measurements snvr-bench makes, each run inside a child process (isolated.hpp):
// whole reconstructions with a warm-up and repetitions, and a device's roofline.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "record.hpp"
#include "snvr/snvr.hpp"

namespace snvr::bench {

struct RunCase {
    std::string section, name;
    std::function<PointSet()> points;  // made or read inside the child
    Parameters params;
    std::string table2_shape;          // set: also measure the Table 2 surface errors
};

// One warm-up, then `repeat` runs: medians per stage, the spread of the total, V-cycles,
// residuals, peak memory, bytes moved and the rate the steps achieved.
Record measure_run(const RunCase& c, int repeat, bool warm_up = true);

// On params.device and precision: a copy over the active bricks (the device's memory
// bandwidth), the smoothing, residual and nonlinear kernels against it, and a whole
// run's time next to its floor (bytes over copy bandwidth). With `host_triad` also the
// OpenMP triad. The case's label goes into every record.
std::vector<Record> measure_roofline(const std::string& label, const std::function<PointSet()>& points, Parameters params,
                                     int repeat, bool host_triad);

// Every device snvr can run on: records with "device" (the --device id), "name", "fp64".
std::vector<Record> list_device_records();

}  // namespace snvr::bench
