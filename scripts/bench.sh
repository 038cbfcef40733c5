#!/usr/bin/env bash
# Set up (plus gnuplot), build, run the benchmark suite and plot it:
#   bash scripts/bench.sh [snvr-bench options]      e.g. --quick, --precisions double
# Results: bench/latest/results.md (also printed), results.jsonl, *.dat and *.png;
# a --quick run goes to build/bench-quick, leaving the published figures alone, and
# --out DIR anywhere (plotted there too): run one section into a scratch folder, e.g.
#   bash scripts/bench.sh --sections points --out /tmp/points, then copy what is wanted.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh gnuplot-nox libopenvdb-dev libboost-dev  # OpenVDB peer (its headers need Boost)
export OMP_WAIT_POLICY=passive
export POCL_CACHE_DIR="${POCL_CACHE_DIR:-$PWD/build/pocl-cache}"
out=bench/latest
[[ " $* " == *" --quick "* ]] && out=build/bench-quick
args=("$@")
for ((i = 0; i + 1 < ${#args[@]}; i++)); do
  [[ "${args[i]}" == --out ]] && out="${args[i + 1]}"  # the suite takes the last --out too
done
mkdir -p "$out"
./build/bench/suite/snvr-bench --out "$out" "$@"
# (series without the paper's values, e.g. at 512^3, have no points to draw: not a problem)
gnuplot -e "dir='$out'" bench/plots.gp 2>&1 | { grep -v "no valid points" || true; } >&2
echo "bench.sh: plots in $out/*.png"
