// One process (snvr-cl built without MPI): refuses to be one of several.
#include <string>

#include "processes.hpp"
#include "snvr/error.hpp"

namespace cli {

void start_processes(int&, char**&) {
    if (launched_size() > 1)
        throw snvr::Error("this snvr-cl was built without MPI, but a launcher started " +
                          std::to_string(launched_size()) +
                          " copies of it, which would all write one output: run it alone, or build it where "
                          "libopenmpi-dev is installed");
}
void end_processes(bool) {}
int process_count() { return 1; }
int process_rank() { return 0; }
std::shared_ptr<snvr::TileScheduler> process_tiles() { return nullptr; }

}  // namespace cli
