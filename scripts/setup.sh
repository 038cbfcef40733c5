#!/usr/bin/env bash
# Installs the Debian packages libsnvr builds with, only those missing:
#   bash scripts/setup.sh                 what libsnvr and snvr-cl need (the example)
#   bash scripts/setup.sh --all [NAMES]   that, and what the tests, the benchmarks and the
#                                         Python module need, and any NAMES given
#                                         (test.sh adds Open3D and Oclgrind, bench.sh gnuplot and OpenVDB)
set -euo pipefail
packages=(build-essential cmake libomp-dev ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers
          pocl-opencl-icd libnanoflann-dev libpng-dev lib3mf-dev nlohmann-json3-dev zlib1g-dev)
if [[ "${1:-}" == "--all" ]]; then
  shift
  packages+=(libclblast-dev doctest-dev pybind11-dev python3-dev python3-numpy python3-pytest "$@")
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
