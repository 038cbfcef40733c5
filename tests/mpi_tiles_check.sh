#!/usr/bin/env bash
# snvr-cl under mpirun (2 processes, as CI runs it: root, oversubscribed): the tiled run's
# shell byte for byte the one process's; the other process reads nothing (the first gives
# it the plan and its points); --tile-cells required; one process failing
# (reading, in a tile, or killed) fails the run, names the process (and the tile), and
# nothing is written.
set -uo pipefail
cli=$1 data=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export OMP_NUM_THREADS=1 OMPI_MCA_btl_vader_single_copy_mechanism=none
mpi=(mpirun --oversubscribe --allow-run-as-root)
run=(reconstruct "$data/bunny.ply" --resolution 96 --tile-cells 24 --device openmp --quiet)
fail() { echo "FAIL: $*"; exit 1; }

"$cli" "${run[@]}" -o "$tmp/one.stl" || fail "one process"
"${mpi[@]}" -np 2 "$cli" "${run[@]/--quiet/--report}" "$tmp/two.json" -o "$tmp/two.stl" 2>"$tmp/two.log" ||
    fail "two processes"
cmp "$tmp/one.stl" "$tmp/two.stl" || fail "two processes wrote other bytes than one"
grep -q '"processes": 2' "$tmp/two.json" || fail "the report does not say 2 processes"
grep -q "tile: .* s left; process 0: [0-9]* of [0-9]*, process 1: [0-9]* of [0-9]*" "$tmp/two.log" ||
    fail "the progress does not show each process's tiles: $(tail -3 "$tmp/two.log")"
rm "$tmp/two.log"
echo "2 processes: the same bytes as 1"

out=$("${mpi[@]}" -np 2 "$cli" reconstruct "$data/bunny.ply" -o "$tmp/x.stl" --quiet 2>&1)
[ $? -ne 0 ] || fail "no --tile-cells under mpirun was accepted"
grep -q "give --tile-cells N" <<<"$out" || fail "no --tile-cells: $out"
[ "$(grep -c 'give --tile-cells' <<<"$out")" -eq 1 ] || fail "the usage error said more than once: $out"
[ ! -e "$tmp/x.stl" ] || fail "an output was written"
echo "no --tile-cells: refused once"

# The others read nothing: process 1 given an input that is not there runs its tiles as
# the first gives them, the same bytes.
absent=(reconstruct "$tmp/absent.ply" "${run[@]:2}")
"${mpi[@]}" -np 1 "$cli" "${run[@]}" -o "$tmp/w.stl" : -np 1 "$cli" "${absent[@]}" -o "$tmp/w.stl" ||
    fail "process 1 read its input"
cmp "$tmp/one.stl" "$tmp/w.stl" || fail "process 1 without the input: other bytes"
rm "$tmp/w.stl"
echo "the other processes read nothing: the same bytes"

# The first process fails to read the input (the read-fault hook): the run fails, says
# which process, and writes nothing.
out=$("${mpi[@]}" -np 1 -x SNVR_TEST_READ_FAULT=eio:1000 "$cli" "${run[@]}" -o "$tmp/y.stl" : -np 1 "$cli" "${run[@]}" \
      -o "$tmp/y.stl" 2>&1)
[ $? -ne 0 ] || fail "a process that failed did not fail the run"
grep -q "process 0 of 2" <<<"$out" || fail "the failure does not name the process: $out"
[ ! -e "$tmp/y.stl" ] || fail "an output was written"

# Process 1 fails in the first tile it runs (the tile-fault hook): the message names the
# tile and the process; nothing is written.
out=$("${mpi[@]}" -np 1 "$cli" "${run[@]}" -o "$tmp/z.stl" : -np 1 -x SNVR_TEST_TILE_FAULT=first "$cli" "${run[@]}" \
      -o "$tmp/z.stl" 2>&1)
[ $? -ne 0 ] || fail "a tile that failed did not fail the run"
grep -q "error (process 1 of 2): .*tile [0-9]* (cells [0-9-]*, [0-9-]*, [0-9-]*): a test fault" <<<"$out" ||
    fail "the failure does not name the tile and the process: $out"
[ ! -e "$tmp/z.stl" ] || fail "an output was written"

# Process 1 killed (SIGKILL) in its first tile: the run fails, the launcher names the
# process, and nothing is written (the first process's staged outputs have no name).
out=$("${mpi[@]}" -np 1 "$cli" "${run[@]}" -o "$tmp/k.stl" : -np 1 -x SNVR_TEST_TILE_FAULT=kill "$cli" "${run[@]}" \
      -o "$tmp/k.stl" 2>&1)
[ $? -ne 0 ] || fail "a process killed did not fail the run"
grep -q "rank 1" <<<"$out" || fail "the kill does not name the process: $out"
[ ! -e "$tmp/k.stl" ] || fail "an output was written"
ls "$tmp" | grep -v -E '^(one|two)\.(stl|json)$' && fail "something was left beside the outputs"
echo "a failing process (an error, or killed): the run failed, naming the process (and the tile), nothing written"
