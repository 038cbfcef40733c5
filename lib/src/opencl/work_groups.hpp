// Which variant of the brick kernels a device runs, and how many work-items each kind of
// kernel (kernels/common.cl) runs per work-group: a work-item per plane or per brick on
// CPUs (rows carried in registers along y), a work-item per row on GPUs (neighbouring
// work-items on neighbouring rows); sizes within what the device allows (its largest
// work-group, its local memory). For tests and experiments, on any device:
// SNVR_OPENCL_KERNELS=planes|rows picks the variant, SNVR_OPENCL_WORK_GROUP=N (a power of
// two from 8 to 1024) asks every kernel for groups of N (at least a brick's 64 rows for
// the row variant's).
#pragma once
#include <cstddef>
#include <string>

#include "opencl/runtime.hpp"

namespace snvr::opencl {

enum class KernelShape { Planes, Rows };

struct WorkGroups {
    KernelShape shape = KernelShape::Planes;
    std::size_t brick_rows = 256;  // the row variant's brick kernels: 64 per brick (compiled in as ROWS_PER_GROUP)
    std::size_t planes = 64;   // plane kernels: 8 per brick (compiled in as PLANES_PER_GROUP)
    std::size_t rows = 64;     // row kernels: 64 per brick; and coarse_solve, one per row of its matrix
    std::size_t bricks = 64;   // the red-black sweep: one per brick
    std::size_t cells = 256;   // restrict_coefficient: one per coarse cell
    std::size_t reduce = 256;  // sum_partials' one group, a divisor of 256 (compiled in as REDUCE_GROUP)

    // The -D options that compile the sizes into the program.
    std::string build_options() const;
    // "plane kernels" or "row kernels", and the groups, for reports.
    std::string describe() const;
};

// The local memory a group of `planes` plane work-items uses at most (restrict_residual's
// residuals: 512 cells of a brick per 8 planes), and a group of `rows` row work-items.
std::size_t plane_group_local_bytes(std::size_t planes, std::size_t real_bytes);
std::size_t row_group_local_bytes(std::size_t rows, std::size_t real_bytes);

// The variant (rows on a GPU, planes elsewhere, or as SNVR_OPENCL_KERNELS asks; planes
// where a group of 64 rows does not fit) and the sizes for `device` with fields of
// real_bytes: the defaults above (or the size SNVR_OPENCL_WORK_GROUP asks), each the
// largest power of two at most that which the device's work-group limit and local memory
// allow. Throws ParameterError for a malformed variable, ResourceError for a device that
// allows no group of 8 plane work-items.
WorkGroups work_groups(const DeviceEntry& device, std::size_t real_bytes);

// The largest power of two at most `wanted` and at most `limit` (at least 1).
std::size_t fit_group(std::size_t wanted, std::size_t limit);

}  // namespace snvr::opencl
