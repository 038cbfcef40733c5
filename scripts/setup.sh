#!/usr/bin/env bash
# Installs the Debian packages libsnvr builds and tests with, only those missing;
# extra package names given as arguments too (scripts/bench.sh adds gnuplot-nox and OpenVDB).
set -euo pipefail
packages=(build-essential cmake libomp-dev ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers
          pocl-opencl-icd libclblast-dev libnanoflann-dev doctest-dev libpng-dev lib3mf-dev
          nlohmann-json3-dev zlib1g-dev pybind11-dev python3-dev python3-numpy python3-pytest "$@")
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
