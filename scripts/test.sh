#!/usr/bin/env bash
# Set up, build, and run every test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
export OMP_WAIT_POLICY=passive
# PoCL caches compiled kernels; keep its cache somewhere writable even without a home.
export POCL_CACHE_DIR="${POCL_CACHE_DIR:-$PWD/build/pocl-cache}"
ctest --test-dir build --output-on-failure
