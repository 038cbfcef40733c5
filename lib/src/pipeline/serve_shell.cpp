// serve_shell and serve_input (shell.hpp): what another process does in a make_shell and a
// read_input spread over processes.
#include "pipeline/shared_check.hpp"
#include "pipeline/shared_guard.hpp"
#include "process_limits.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/shell.hpp"
#include "snvr/tiles.hpp"
#include "solver/shared_filing.hpp"
#include "spilled_memory.hpp"

namespace snvr {

void serve_shell(const Parameters& params, TileScheduler& tiles_on) {
    // One budget over both parts (its range of the points, kept for the check's depths
    // since the filing, is in files where they go over it).
    const std::size_t budget = params.max_memory.value_or(0);
    const detail::BudgetScope within(budget, 0);
    const detail::SpillScope spill(budget, 0, params.temp_dir);
    Result run = reconstruct_tiles_of(params, tiles_on);
    const std::shared_ptr<detail::KeptRange> kept = std::move(tiles_on.points_kept);
    detail::answer_guard_search(tiles_on, kept.get());
    Mesh slab = std::move(run.surface);
    run = Result();
    detail::serve_check(tiles_on, std::move(slab), kept.get());
}

void serve_input(const std::string& path, const Parameters& params, TileScheduler& tiles_on) {
    const detail::SpillScope spill(params.max_memory.value_or(0), 0, params.temp_dir);
    if (const std::size_t n = detail::parts_to_read(&tiles_on, path)) {
        tiles_on.points_kept = detail::file_part_for_root(tiles_on, detail::read_my_part(tiles_on, path, n, params.temp_dir), n);
        return;
    }
    tiles_on.points_kept = detail::file_for_root(tiles_on);
}

}  // namespace snvr
