// Where the check's walls are measured: a fixed rule on the device the run's solver used,
// never a timing (so the figures cannot depend on the hour; they are the same to the bit
// either way: tests/test_device_walls.cpp). An OpenCL GPU with double precision casts the
// rays (kernels/wall_rays.cl); every other device leaves them to the host, whose rays are
// as fast as PoCL's on the same cores. SNVR_CHECK_WALLS=device casts them on any OpenCL
// device with double precision (PoCL in the tests), =host on none.
#pragma once
#include <string>

#include "check/walls.hpp"

namespace snvr::detail {

// The rays for a run whose backend is `backend` (Result::backend: "opencl:P:D (...)" or
// "openmp ..."), or none (the host). A device that cannot hold them or build them leaves
// them to the host (the report names where they were cast).
WallRays wall_rays_for(const std::string& backend);

}  // namespace snvr::detail
