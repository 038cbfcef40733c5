#!/usr/bin/env bash
# Runs a test program on Oclgrind's simulated OpenCL device with its checks on (data
# races and API errors asked for; out-of-bounds, invalid and misaligned accesses and
# barrier and work-group divergence always on) and fails on any report. Oclgrind's
# uninitialized-value plugin is left off: it aborts on LLVM's `freeze` instruction.
set -euo pipefail
command -v oclgrind >/dev/null || { echo "oclgrind is not installed (scripts/test.sh installs it)"; exit 1; }
log=$(mktemp)
trap 'rm -f "$log"' EXIT
oclgrind --data-races --check-api --log "$log" "$@"
if [ -s "$log" ]; then
  echo "Oclgrind reported $(grep -c 'Kernel:' "$log" || true) problems in kernels ($(grep 'Kernel:' "$log" | sort -u | tr -s '\t ' ' ' | tr '\n' ';')):"
  head -c 20000 "$log"
  exit 1
fi
echo "Oclgrind: no report"
