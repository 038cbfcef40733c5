#!/usr/bin/env bash
# Set up (packages), configure and build into ./build:
#   bash scripts/build.sh             everything: library, snvr-cl, tests, benchmarks, Python module
#   bash scripts/build.sh --cli-only  the library and snvr-cl alone (the example; a build/ configured
#                                     before keeps its options, the rest is built when asked for)
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ "${1:-}" == "--cli-only" ]]; then
  bash scripts/setup.sh
  parts=(-DSNVR_BUILD_TESTS=OFF -DSNVR_BUILD_BENCH=OFF -DSNVR_BUILD_PYTHON=OFF)
  [ -f build/CMakeCache.txt ] && parts=()
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "${parts[@]}" >/dev/null
  cmake --build build -j"$(nproc)" --target snvr-cl
  exit
fi
bash scripts/setup.sh --all "$@"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DSNVR_BUILD_TESTS=ON -DSNVR_BUILD_BENCH=ON -DSNVR_BUILD_PYTHON=ON >/dev/null
cmake --build build -j"$(nproc)"
