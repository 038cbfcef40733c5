// Runs a measurement in a child process, so each case's peak memory is its own and a
// crash or out-of-memory in one case cannot take the others down. The parent never
// touches OpenCL or OpenMP, so forking it is safe.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "record.hpp"

namespace snvr::bench {

// The records `measure` returns, or one record with "error" set when it threw or died.
std::vector<Record> run_isolated(const std::function<std::vector<Record>()>& measure);

}  // namespace snvr::bench
