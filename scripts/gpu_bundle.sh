#!/usr/bin/env bash
# One folder that runs snvr-cl and snvr-bench (without its OpenVDB peer) on a machine
# with nothing but a GPU driver: both programs, every shared library they load (the OpenCL ICD loader,
# lib3mf, libpng, zlib, OpenMP, the C++ and C libraries and the C library's own loader,
# so that no library of the machine is mixed with ours), the bunny, and run.sh, which
# finds the driver's OpenCL library and measures (scripts/gpu_bundle/run.sh).
#   bash scripts/gpu_bundle.sh [FOLDER]     (default build/gpu-bundle; builds first if needed)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build/gpu-bundle}
# A build/ made by the example alone has no benchmarks configured.
grep -qs "SNVR_BUILD_BENCH:BOOL=ON" build/CMakeCache.txt || bash scripts/build.sh
# The suite without the OpenVDB peer (a GPU run measures the kernels, not the peers).
cmake --build build -j"$(nproc)" --target snvr-cl snvr-bench-portable >/dev/null
rm -rf "$out"
mkdir -p "$out/bin" "$out/lib" "$out/libexec" "$out/data"
strip --strip-unneeded -o "$out/libexec/snvr-cl" build/cli/snvr-cl
strip --strip-unneeded -o "$out/libexec/snvr-bench" build/bench/suite/snvr-bench-portable

# Every library the programs load, by the name they ask for, and the loader itself.
# The C library's stubs (libpthread, libdl, librt) too: a driver may still ask for them,
# and they must come from the same C library as ours.
libraries() {
  for program in "$out"/libexec/*; do ldd "$program"; done |
    awk '$2 == "=>" && $3 ~ /^\// {print $3} $1 ~ /^\// {print $1}' | sort -u
  for stub in libpthread.so.0 libdl.so.2 librt.so.1; do
    ldconfig -p | awk -v n="$stub" '$1 == n && /x86-64/ && !found {print $NF; found = 1}'
  done
}
libraries | while read -r path; do
  cp -L "$path" "$out/lib/$(basename "$path")"
done
[ -f "$out/lib/ld-linux-x86-64.so.2" ] || { echo "gpu_bundle: no ld-linux-x86-64.so.2 among the libraries"; exit 1; }
chmod +x "$out/lib/ld-linux-x86-64.so.2"

# Each program through the bundled loader, with the bundle's libraries first and the
# driver's folder (run.sh sets SNVR_DRIVER_DIR) after them. OMP_WAIT_POLICY is set here:
# snvr-cl would set it by starting itself again, and under a loader started by hand
# /proc/self/exe is the loader.
for program in snvr-cl snvr-bench; do
  cat > "$out/bin/$program" <<WRAPPER
#!/bin/sh
here=\$(cd "\$(dirname "\$0")/.." && pwd)
export OMP_WAIT_POLICY=\${OMP_WAIT_POLICY:-passive}
exec "\$here/lib/ld-linux-x86-64.so.2" --library-path "\$here/lib\${SNVR_DRIVER_DIR:+:\$SNVR_DRIVER_DIR}" \\
  "\$here/libexec/$program" "\$@"
WRAPPER
  chmod +x "$out/bin/$program"
done

data=../shared/data
[ -f "$data/bunny.ply" ] || { echo "gpu_bundle: $data/bunny.ply is missing"; exit 1; }
cp "$data/bunny.ply" "$out/data/"
cp scripts/gpu_bundle/run.sh "$out/run.sh"
chmod +x "$out/run.sh"
git rev-parse --short HEAD > "$out/VERSION" 2>/dev/null || echo unknown > "$out/VERSION"
echo "gpu_bundle: $out, $(du -sm "$out" | cut -f1) MB: $(ls "$out/lib" | wc -l) libraries"
