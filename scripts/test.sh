#!/usr/bin/env bash
# Set up, build, and run every test suite.
#   --sanitize: the same suites built with AddressSanitizer and UndefinedBehaviorSanitizer
#               (in build-sanitize/, without the benchmarks); the OpenCL stack's own leaks
#               are suppressed by tests/sanitizers/lsan.supp.
set -euo pipefail
cd "$(dirname "$0")/.."
export OMP_WAIT_POLICY=passive
if [[ "${1:-}" == "--sanitize" ]]; then
  bash scripts/setup.sh --all
  cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSNVR_SANITIZE=ON -DSNVR_BUILD_BENCH=OFF >/dev/null
  cmake --build build-sanitize -j"$(nproc)"
  export POCL_CACHE_DIR="${POCL_CACHE_DIR:-$PWD/build-sanitize/pocl-cache}"
  # use_sigaltstack=0: LLVM inside PoCL installs its own signal stacks, which ASan then
  # fails to unmap when a thread ends ("unable to unmap").
  export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1:use_sigaltstack=0"
  export LSAN_OPTIONS="suppressions=$PWD/tests/sanitizers/lsan.supp:print_suppressions=0"
  export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
  ctest --test-dir build-sanitize --output-on-failure --timeout 1500
  exit
fi
# Open3D only for the Python tests' round trip: the module never needs it. Oclgrind
# checks the kernels (tests/oclgrind_check.sh). OpenMPI: snvr-cl shares tiles among
# processes under mpirun (tests/mpi_tiles_check.sh).
bash scripts/build.sh python3-open3d oclgrind libopenmpi-dev openmpi-bin
# PoCL caches compiled kernels; keep its cache somewhere writable even without a home.
export POCL_CACHE_DIR="${POCL_CACHE_DIR:-$PWD/build/pocl-cache}"
ctest --test-dir build --output-on-failure
