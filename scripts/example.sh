#!/usr/bin/env bash
# Set up, build, and reconstruct the bundled example (the paper's two-headed cone,
# sampled by our own generator, 0.7 units tall) into example-cone.stl, 70 mm tall, with
# a picture of it beside a cut through it in example-cone.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh --cli-only  # snvr-cl alone: no tests, benchmarks or Python module
export OMP_WAIT_POLICY=passive
# PoCL caches compiled kernels; keep its cache somewhere writable even without a home.
export POCL_CACHE_DIR="${POCL_CACHE_DIR:-$PWD/build/pocl-cache}"
./build/cli/snvr-cl sample cone --spacing 0.004 -o build/example-cone.ply
./build/cli/snvr-cl reconstruct build/example-cone.ply -o example-cone.stl --resolution 128 --scale 100 \
  --preview example-cone.png
