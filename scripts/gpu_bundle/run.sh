#!/usr/bin/env bash
# The GPU run in one call, on a machine with only a GPU driver (no OpenCL packages, no
# network): finds the driver's OpenCL library, points the bundled ICD loader at it in a
# vendors folder of its own, and writes into FOLDER: devices.txt; the bunny at 128 cells
# on the GPU and on OpenMP, float and double (same_bytes.txt: are the STLs the same
# bytes?); the bunny
# at 256, 1024 and 2048 cells on the GPU (and at 256 and 1024 on OpenMP), each run's
# --report with its seconds per stage; every kernel's GB/s against the device's copy
# (roofline/, and roofline_planes/ for the CPU variant of the kernels); run.log. Under 5 minutes on a 16-core machine with one GPU.
#   ./run.sh FOLDER [DRIVER_LIBRARY]      (or SNVR_OPENCL_DRIVER=path ./run.sh FOLDER)
# Smaller runs (a CPU "driver" such as PoCL's, for a test of the bundle):
# SNVR_RUN_GRIDS="256 1024 2048", SNVR_RUN_OPENMP_GRIDS="256 1024", SNVR_RUN_ROOFLINE=1024.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=${1:?usage: run.sh FOLDER [DRIVER_LIBRARY]}
driver=${2:-${SNVR_OPENCL_DRIVER:-}}
mkdir -p "$out/icd"
out=$(cd "$out" && pwd)
exec > >(tee "$out/run.log") 2>&1
started=$(date +%s)
say() { echo "[run.sh $(( $(date +%s) - started )) s] $*"; }

# The driver's OpenCL library: where NVIDIA's container runtimes and packages put it.
if [ -z "$driver" ]; then
  for dir in /usr/local/nvidia/lib64 /usr/local/nvidia/lib /usr/lib/x86_64-linux-gnu /usr/lib64 /lib64 /usr/lib \
             /usr/lib/wsl/lib /run/nvidia/driver/usr/lib/x86_64-linux-gnu /usr/local/cuda/compat; do
    for f in "$dir"/libnvidia-opencl.so.1 "$dir"/libnvidia-opencl.so.*; do
      if [ -f "$f" ]; then driver=$f; break 2; fi
    done
  done
fi
[ -n "$driver" ] || driver=$(ldconfig -p 2>/dev/null | awk '/libnvidia-opencl\.so/ {print $NF; exit}')
[ -n "$driver" ] || driver=$(find / -xdev \( -path /proc -o -path /sys \) -prune -o -name 'libnvidia-opencl.so*' -print 2>/dev/null | head -1)
rm -f "$out"/icd/*.icd
if [ -n "$driver" ] && [ -f "$driver" ]; then
  echo "$driver" > "$out/icd/driver.icd"
  export SNVR_DRIVER_DIR
  SNVR_DRIVER_DIR=$(dirname "$driver")
  say "OpenCL driver: $driver"
else
  say "no OpenCL driver library found (libnvidia-opencl.so.1): OpenMP only"
fi
export OCL_ICD_VENDORS="$out/icd"
unset OPENCL_VENDOR_PATH
export POCL_CACHE_DIR="$out/kernel-cache"
cli="$here/bin/snvr-cl"
bench="$here/bin/snvr-bench"
bunny="$here/data/bunny.ply"
cat "$here/VERSION" > "$out/version.txt"
{ uname -a; nproc; command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm,clocks.max.mem --format=csv; } > "$out/machine.txt" 2>&1

say "devices"
"$cli" devices | tee "$out/devices.txt"
# The first GPU, else the first OpenCL device of any kind.
gpu=$(awk '$1 ~ /^opencl:/ && $2 == "gpu" {print $1; exit}' "$out/devices.txt")
[ -n "$gpu" ] || gpu=$(awk '$1 ~ /^opencl:/ {print $1; exit}' "$out/devices.txt")

# A run: device, resolution, tag, more options; the mesh is kept only where it is
# compared. At most 150 s each, so that one stuck run cannot take the whole lease.
run() {
  local device=$1 n=$2 tag=$3
  shift 3
  say "bunny at $n on $device"
  rm -f "$out/$tag.stl" "$out/$tag.json"
  local timer=()
  [ -x /usr/bin/time ] && timer=(/usr/bin/time -v)
  local t0=$SECONDS
  timeout 150 "${timer[@]}" "$cli" reconstruct "$bunny" -o "$out/$tag.stl" --resolution "$n" --device "$device" \
    --report "$out/$tag.json" --quiet "$@" 2> "$out/$tag.time" || say "failed: $(tail -3 "$out/$tag.time")"
  echo "wall $((SECONDS - t0)) s" >> "$out/$tag.time"
  grep -E "Elapsed|Maximum resident|^wall" "$out/$tag.time" | sed "s/^/  $tag: /"
}

run openmp 128 b128_openmp
run openmp 128 b128d_openmp --precision double
if [ -n "$gpu" ]; then
  run "$gpu" 128 b128_gpu
  run "$gpu" 128 b128d_gpu --precision double
  : > "$out/same_bytes.txt"
  for p in b128 b128d; do
    if cmp -s "$out/${p}_gpu.stl" "$out/${p}_openmp.stl"; then echo "$p: same bytes" >> "$out/same_bytes.txt"
    else echo "$p: different: $(cmp "$out/${p}_gpu.stl" "$out/${p}_openmp.stl" 2>&1 | head -1)" >> "$out/same_bytes.txt"; fi
  done
  say "bunny at 128, GPU against OpenMP (float; double): $(tr '\n' ' ' < "$out/same_bytes.txt")"
  say "kernels against the device's copy (roofline, bunny at ${SNVR_RUN_ROOFLINE:-1024})"
  "$bench" --sections roofline --devices "$gpu,openmp" --precisions float,double --repeat 5 \
    --roofline-resolution "${SNVR_RUN_ROOFLINE:-1024}" --data "$here/data" --out "$out/roofline" > "$out/roofline.log" 2>&1 || say "roofline failed"
  # The device's other variant of the brick kernels, for comparison (a GPU's is rows).
  other=planes
  grep -q "$gpu .*cpu" "$out/devices.txt" && other=rows
  say "the same with the $other variant"
  SNVR_OPENCL_KERNELS=$other "$bench" --sections roofline --devices "$gpu" --precisions float,double --repeat 5 \
    --roofline-resolution "${SNVR_RUN_ROOFLINE:-1024}" --data "$here/data" --out "$out/roofline_$other" > "$out/roofline_$other.log" 2>&1 || say "roofline ($other) failed"
  for n in ${SNVR_RUN_GRIDS:-256 1024 2048}; do run "$gpu" "$n" "b${n}_gpu"; done
fi
for n in ${SNVR_RUN_OPENMP_GRIDS:-256 1024}; do run openmp "$n" "b${n}_openmp"; done
rm -f "$out"/b[0-9]*_*.stl.tmp* "$out"/b256*.stl "$out"/b1024*.stl "$out"/b2048*.stl
rm -rf "$out/kernel-cache"
say "done: $out"
