// The reference backend: plain OpenMP loops over active bricks, with exactly the
// arithmetic the OpenCL kernels use (same operation order, no FMA contraction).
#pragma once
#include <memory>

#include "solver/backend.hpp"

namespace snvr {

template <class Real>
std::unique_ptr<Backend<Real>> make_openmp_backend();

int openmp_threads();

}  // namespace snvr
