#!/usr/bin/env bash
# Set up, build, and run every test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
export OMP_WAIT_POLICY=passive
ctest --test-dir build --output-on-failure
