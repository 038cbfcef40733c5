// The subcommands of snvr-cl. Each returns the exit status; usage mistakes throw
// cli::UsageError, failures throw (snvr::Error or std::exception) to main.
#pragma once
#include <string>
#include <vector>

namespace cli {

int run_reconstruct(const std::vector<std::string>& args);
int run_devices(const std::vector<std::string>& args);
int run_sample(const std::vector<std::string>& args);

}  // namespace cli
