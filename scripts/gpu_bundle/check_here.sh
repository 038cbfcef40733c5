#!/usr/bin/env bash
# The bundle on this machine, with PoCL standing in for a GPU driver, where the system's
# OpenCL packages cannot be seen: a private mount namespace (root) hides the ICD files
# and the ICD loader, and the libraries the bundle carries (lib3mf, libpng, libzip,
# OpenMP), so that only what the bundle holds, the "driver" and the C library can load.
# Small grids; fails unless the GPU stand-in and OpenMP write the same bytes.
#   sudo bash scripts/gpu_bundle/check_here.sh [OUT]     (default build/gpu-bundle-check)
set -euo pipefail
cd "$(dirname "$0")/../.."
out=$(realpath -m "${1:-build/gpu-bundle-check}")
bash scripts/gpu_bundle.sh build/gpu-bundle
rm -rf "$out"
driver=$(find /usr/lib/x86_64-linux-gnu -name 'libpocl.so.2' | head -1)
[ -n "$driver" ] || { echo "check_here: PoCL (libpocl.so.2) is not installed"; exit 1; }
unshare -m bash -euo pipefail -c '
  empty=$(mktemp -d)
  mount --bind "$empty" /etc/OpenCL/vendors
  for lib in libOpenCL.so.1 lib3MF.so.1 libpng16.so.16 libzip.so.4 libgomp.so.1; do
    f=/usr/lib/x86_64-linux-gnu/$lib
    if [ -e "$f" ]; then mount --bind /dev/null "$f"; fi
  done
  env -i PATH=/usr/bin:/bin HOME=/tmp SNVR_RUN_GRIDS=256 SNVR_RUN_OPENMP_GRIDS=256 SNVR_RUN_ROOFLINE=128 SNVR_RUN_SPHERE_SPACING=0.004 \
    build/gpu-bundle/run.sh "$1" "$2"' check "$out" "$driver"
cat "$out/same_bytes.txt"
! grep -q different "$out/same_bytes.txt"
