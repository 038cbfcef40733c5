#!/usr/bin/env bash
# A user's own CMake project links the installed libsnvr with find_package(snvr).
set -euo pipefail
build=$1 source=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
cmake -S "$source/examples/link-libsnvr" -B "$tmp/build" -DCMAKE_PREFIX_PATH="$tmp/prefix" >/dev/null
cmake --build "$tmp/build" >/dev/null
"$tmp/build/shell_of_sphere" "$tmp/sphere.stl"
test -s "$tmp/sphere.stl"
echo "linked against the installed library and wrote a closed shell"
