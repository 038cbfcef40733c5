// The OpenCL backend: every operation of backend.hpp as a kernel of kernels/, on the
// same sparse brick-major layout as the OpenMP reference (brick_grid.hpp), with the
// same arithmetic, so the two agree to the bit where the math library is not involved.
#pragma once
#include <memory>
#include <string>

#include "solver/backend.hpp"

namespace snvr {

// `spec` as --device takes it ("opencl", "opencl:P:D", a name substring; "auto" picks
// like "opencl"). Throws ParameterError or ResourceError naming the problem.
template <class Real>
std::unique_ptr<Backend<Real>> make_opencl_backend(const std::string& spec);

}  // namespace snvr
