#!/usr/bin/env bash
# Set up (plus gnuplot), build, run the benchmark suite and plot it:
#   bash scripts/bench.sh [snvr-bench options]      e.g. --quick, --precisions double
# Results: bench/latest/results.md (also printed), results.jsonl, *.dat and *.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh gnuplot-nox
bash scripts/build.sh
export OMP_WAIT_POLICY=passive
export POCL_CACHE_DIR="${POCL_CACHE_DIR:-$PWD/build/pocl-cache}"
mkdir -p bench/latest
./build/bench/suite/snvr-bench --out bench/latest "$@"
gnuplot -e "dir='bench/latest'" bench/plots.gp
echo "bench.sh: plots in bench/latest/*.png"
