#include "solver/solver_memory.hpp"

#include <sstream>
#include <string>

#include "process_limits.hpp"
#include "snvr/error.hpp"

namespace snvr {

namespace {

std::string gib(std::size_t bytes) {
    std::ostringstream s;
    s.precision(4);
    s << double(bytes) / double(1u << 30);
    return s.str();
}

}  // namespace

std::size_t estimate_plan_bytes(const Domain& d) {
    std::size_t bricks = 0;
    for (int l = 0; l < d.levels; ++l) {
        const std::size_t n[3] = {std::size_t(d.nx >> l), std::size_t(d.ny >> l), std::size_t(d.nz >> l)};
        bricks += ((n[0] + kBrick - 1) / kBrick) * ((n[1] + kBrick - 1) / kBrick) * ((n[2] + kBrick - 1) / kBrick);
    }
    return d.cells() / 8 + bricks * sizeof(std::uint32_t);
}

std::size_t band_distance_bytes(std::size_t near_bricks, Precision p) {
    return 2 * near_bricks * kBrickCells * real_size(p);
}

std::size_t layout_bytes(const BrickLayout& layout, Precision p) {
    std::size_t cells = 0;
    for (int l = 0; l < layout.levels(); ++l) cells += (l == 0 ? 4 : 3) * layout.grid(l).storage();
    return cells * real_size(p);
}

void require_memory(std::size_t bytes, const Domain& d, std::size_t held) {
    const std::size_t avail = detail::available_memory() + held;
    if (bytes > avail / 10 * 9) {
        const std::string limit = detail::memory_limit_text();
        throw ResourceError("a " + std::to_string(d.nx) + "x" + std::to_string(d.ny) + "x" + std::to_string(d.nz) +
                            " grid needs about " + gib(bytes) + " GiB but only " + gib(avail) +
                            " GiB of memory is available" + (limit.empty() ? "" : " (" + limit + ")") +
                            (detail::budget_in_force() ? "; give a larger budget, lower the resolution or raise the voxel size"
                                                       : "; lower the resolution or raise the voxel size"));
    }
}

}  // namespace snvr
