#!/usr/bin/env bash
# The GPU run in one call, on a machine with only a GPU driver (no OpenCL packages, no
# network): finds the driver's OpenCL library, points the bundled ICD loader at it in a
# vendors folder of its own, and writes into FOLDER: devices.txt; the bunny at 128 cells
# on the GPU and on OpenMP, float and double (same_bytes.txt: are the STLs the same
# bytes? same_check.txt: are the check's verdicts and figures the same, the walls' rays
# cast on the GPU by the rule against the host's? each report's per_unit prices the
# stages); the bunny
# at 256, 1024 and 2048 cells on the GPU (and at 256 and 1024 on OpenMP), each run's
# --report with its seconds per stage; every kernel's GB/s against the device's copy
# (roofline/, and roofline_planes/ for the CPU variant of the kernels); run.log. Under 5 minutes on a 16-core machine with one GPU.
#   ./run.sh FOLDER [DRIVER_LIBRARY]      (or SNVR_OPENCL_DRIVER=path ./run.sh FOLDER)
# Smaller runs (a CPU "driver" such as PoCL's, for a test of the bundle):
# SNVR_RUN_GRIDS="256 1024 2048", SNVR_RUN_OPENMP_GRIDS="256 1024", SNVR_RUN_ROOFLINE=1024,
# SNVR_RUN_SPHERE_SPACING=0.00025 (the 24.6 M-point noisy sphere, made here by the sampler;
# "none" skips it). Each GPU grid runs twice, the second with the driver's kernel cache
# warm (tag _warm); with nvidia-smi, the device's memory in use is sampled every 0.1 s
# during each GPU run (TAG.gpu_memory: the most, MiB).
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
  say "$(basename "${RUN_INPUT:-$bunny}") at $n on $device"
  rm -f "$out/$tag.stl" "$out/$tag.json"
  local timer=()
  [ -x /usr/bin/time ] && timer=(/usr/bin/time -v)
  local input=${RUN_INPUT:-$bunny}
  local sampler=
  if [ "$device" != openmp ] && command -v nvidia-smi >/dev/null; then
    nvidia-smi --query-gpu=memory.used --format=csv,noheader,nounits -lms 100 > "$out/$tag.gpu_samples" 2>/dev/null &
    sampler=$!
  fi
  local t0=$SECONDS
  timeout 150 "${timer[@]}" "$cli" reconstruct "$input" -o "$out/$tag.stl" --resolution "$n" --device "$device" \
    --report "$out/$tag.json" --quiet "$@" 2> "$out/$tag.time" || say "failed: $(tail -3 "$out/$tag.time")"
  echo "wall $((SECONDS - t0)) s" >> "$out/$tag.time"
  if [ -n "$sampler" ]; then
    kill "$sampler" 2>/dev/null; wait "$sampler" 2>/dev/null
    echo "device memory used, most: $(sort -n "$out/$tag.gpu_samples" | tail -1) MiB" >> "$out/$tag.time"
    rm -f "$out/$tag.gpu_samples"
  fi
  grep -E "Elapsed|Maximum resident|^wall|^device memory" "$out/$tag.time" | sed "s/^/  $tag: /"
}

# The check's verdicts and figures in a run's report, but its seconds and where its rays went.
check_figures() { awk '/^  "check": \{/{on=1; next} on && /^  \}/{exit} on' "$1" | grep -v -E '"(seconds|walls_on)"'; }
same_check() {  # TAG_A TAG_B LABEL
  [ -f "$out/$1.json" ] && [ -f "$out/$2.json" ] || return 0
  local on
  on=$(grep -o '"walls_on": "[^"]*"' "$out/$1.json" | cut -d'"' -f4)
  if diff <(check_figures "$out/$1.json") <(check_figures "$out/$2.json") > /dev/null; then
    echo "$3: same check figures (walls cast on $on)" >> "$out/same_check.txt"
  else
    echo "$3: check figures differ (walls cast on $on): $(diff <(check_figures "$out/$1.json") <(check_figures "$out/$2.json") | head -4 | tr '\n' ' ')" >> "$out/same_check.txt"
  fi
}
: > "$out/same_check.txt"

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
  same_check b128_gpu b128_openmp b128
  same_check b128d_gpu b128d_openmp b128d
  say "kernels against the device's copy (roofline, bunny at ${SNVR_RUN_ROOFLINE:-1024})"
  "$bench" --sections roofline --devices "$gpu,openmp" --precisions float,double --repeat 5 \
    --roofline-resolution "${SNVR_RUN_ROOFLINE:-1024}" --data "$here/data" --out "$out/roofline" > "$out/roofline.log" 2>&1 || say "roofline failed"
  # The device's other variant of the brick kernels, for comparison (a GPU's is rows).
  other=planes
  grep -q "$gpu .*cpu" "$out/devices.txt" && other=rows
  say "the same with the $other variant"
  SNVR_OPENCL_KERNELS=$other "$bench" --sections roofline --devices "$gpu" --precisions float,double --repeat 5 \
    --roofline-resolution "${SNVR_RUN_ROOFLINE:-1024}" --data "$here/data" --out "$out/roofline_$other" > "$out/roofline_$other.log" 2>&1 || say "roofline ($other) failed"
  for n in ${SNVR_RUN_GRIDS:-256 1024 2048}; do
    run "$gpu" "$n" "b${n}_gpu"
    run "$gpu" "$n" "b${n}_gpu_warm"
  done
fi
for n in ${SNVR_RUN_OPENMP_GRIDS:-256 1024}; do run openmp "$n" "b${n}_openmp"; done
# The same answers at the finer grids: the GPU's STL against the host's.
for n in ${SNVR_RUN_OPENMP_GRIDS:-256 1024}; do
  [ -f "$out/b${n}_gpu_warm.stl" ] && [ -f "$out/b${n}_openmp.stl" ] || continue
  if cmp -s "$out/b${n}_gpu_warm.stl" "$out/b${n}_openmp.stl"; then echo "b$n: same bytes" >> "$out/same_bytes.txt"
  else echo "b$n: different: $(cmp "$out/b${n}_gpu_warm.stl" "$out/b${n}_openmp.stl" 2>&1 | head -1)" >> "$out/same_bytes.txt"; fi
done
for n in ${SNVR_RUN_OPENMP_GRIDS:-256 1024}; do same_check "b${n}_gpu_warm" "b${n}_openmp" "b$n"; done
# A large scan: the 24.6 M-point noisy sphere at 512 cells, on the GPU (twice) and on the host.
spacing=${SNVR_RUN_SPHERE_SPACING:-0.00025}
if [ "$spacing" != none ]; then
  say "the noisy sphere at spacing $spacing"
  "$cli" sample noisy-sphere --spacing "$spacing" -o "$out/sphere.ply" > /dev/null 2>&1 || say "sampler failed"
  if [ -f "$out/sphere.ply" ]; then
    export RUN_INPUT="$out/sphere.ply"
    if [ -n "$gpu" ]; then run "$gpu" 512 s512_gpu; run "$gpu" 512 s512_gpu_warm; fi
    run openmp 512 s512_openmp
    unset RUN_INPUT
    if [ -f "$out/s512_gpu_warm.stl" ]; then
      if cmp -s "$out/s512_gpu_warm.stl" "$out/s512_openmp.stl"; then echo "s512: same bytes" >> "$out/same_bytes.txt"
      else echo "s512: different: $(cmp "$out/s512_gpu_warm.stl" "$out/s512_openmp.stl" 2>&1 | head -1)" >> "$out/same_bytes.txt"; fi
    fi
    same_check s512_gpu_warm s512_openmp s512
    rm -f "$out/sphere.ply" "$out"/s512*.stl
  fi
fi
[ -f "$out/same_bytes.txt" ] && say "same bytes: $(tr '\n' ' ' < "$out/same_bytes.txt")"
[ -s "$out/same_check.txt" ] && say "same check: $(tr '\n' ' ' < "$out/same_check.txt")"
rm -f "$out"/b[0-9]*_*.stl.tmp* "$out"/b256*.stl "$out"/b1024*.stl "$out"/b2048*.stl
rm -rf "$out/kernel-cache"
say "done: $out"
