// serve_shell (shell.hpp): what another process does in a make_shell spread over processes.
#include "process_limits.hpp"
#include "snvr/quality.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/shell.hpp"
#include "snvr/tiles.hpp"
#include "spilled_memory.hpp"

namespace snvr {

void serve_shell(const Parameters& params, TileScheduler& tiles_on) {
    // One budget over both parts: the check's points are filed after the tiles' are gone.
    const std::size_t budget = params.max_memory.value_or(0);
    const detail::BudgetScope within(budget, 0);
    const detail::SpillScope spill(budget, 0, params.temp_dir);
    reconstruct_tiles_of(params, tiles_on);
    tiles_on.send_check(measure_check_share(tiles_on.check_share()));
}

}  // namespace snvr
