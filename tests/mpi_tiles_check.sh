#!/usr/bin/env bash
# snvr-cl under mpirun (2 processes, as CI runs it: root, oversubscribed): the tiled run's
# shell byte for byte the one process's; the other process reads nothing (the first gives
# it the plan and its points), under a budget too; --tile-cells required; one process failing
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

# Every figure of the mesh (the depth guard's among them: run on slabs) and of the check the
# same (the walls and points' depths are shared among the processes).
same_check() {
    python3 - "$1" "$2" <<'PY' || fail "the mesh's or the check's figures differ between 1 and 2 processes"
import json, sys
a, b = ({**r["mesh"], **r["check"]} for r in (json.load(open(f)) for f in sys.argv[1:]))
diff = {k: (a[k], b[k]) for k in a if k != "seconds" and a[k] != b[k]}
if diff:
    print(diff)
    sys.exit(1)
PY
}

"$cli" "${run[@]/--quiet/--report}" "$tmp/one.json" -o "$tmp/one.stl" 2>/dev/null || fail "one process"
"${mpi[@]}" -np 2 "$cli" "${run[@]/--quiet/--report}" "$tmp/two.json" -o "$tmp/two.stl" 2>"$tmp/two.log" ||
    fail "two processes"
cmp "$tmp/one.stl" "$tmp/two.stl" || fail "two processes wrote other bytes than one"
same_check "$tmp/one.json" "$tmp/two.json"
# Whether the check counted the shell's topology by the slabs the processes kept (report $2),
# as $1 says it should (1 or 0), and the same figures as the whole shell's (above).
slab_topology() {
    python3 -c 'import json, sys; sys.exit(0 if json.load(open(sys.argv[1]))["tiles"]["check_topology_by_slabs"] == (sys.argv[2] == "1") else 1)' \
        "$2" "$1" || fail "$2: the check's topology was $([ "$1" = 1 ] && echo not) counted by the slabs"
}
slab_topology 1 "$tmp/two.json"
# Whether the surface stayed in the slabs (report $2), as $1 says (1 or 0): no process held
# the whole mesh, the file written from the slabs in turn.
slabs_kept() {
    python3 -c 'import json, sys; sys.exit(0 if json.load(open(sys.argv[1]))["tiles"]["surface_kept_in_slabs"] == (sys.argv[2] == "1") else 1)' \
        "$2" "$1" || fail "$2: the surface was $([ "$1" = 1 ] && echo not) kept in the slabs"
}
# Its points near the other's slab are more than that slab's vertices, but the surface stays
# in the slabs, which then keep the points deep.
slabs_kept 1 "$tmp/two.json"
# At 128 cells the slabs keep their points deep, and then the surface stays in them: as STL,
# PLY and OBJ, the one process's bytes and figures.
for as in stl ply obj; do
    kept=(reconstruct "$data/bunny.ply" --resolution 128 --tile-cells 32 --device openmp)
    "$cli" "${kept[@]}" --report "$tmp/kept1.json" -o "$tmp/kept1.$as" 2>/dev/null || fail "one process ($as)"
    "${mpi[@]}" -np 2 "$cli" "${kept[@]}" --report "$tmp/kept2.json" -o "$tmp/kept2.$as" 2>/dev/null ||
        fail "two processes ($as)"
    cmp "$tmp/kept1.$as" "$tmp/kept2.$as" || fail "two processes wrote other bytes than one ($as)"
    same_check "$tmp/kept1.json" "$tmp/kept2.json"
    slabs_kept 1 "$tmp/kept2.json"
done
rm "$tmp"/kept[12].*
# A preview needs the mesh whole: the first gathers the slabs and, their points near the
# other's slab being more than its vertices, keeps the points deep on the whole surface;
# the same bytes.
"${mpi[@]}" -np 2 "$cli" "${run[@]/--quiet/--report}" "$tmp/whole.json" -o "$tmp/whole.stl" --preview "$tmp/whole.png" \
    2>/dev/null || fail "two processes with a preview"
cmp "$tmp/one.stl" "$tmp/whole.stl" || fail "two processes with a preview wrote other bytes than one"
slabs_kept 0 "$tmp/whole.json"
python3 -c 'import json, sys; t = json.load(open(sys.argv[1]))["tiles"]; sys.exit(0 if not t["guard_on_slabs"] else 1)' \
    "$tmp/whole.json" || fail "with a preview the first did not keep the points deep on the whole surface"
rm "$tmp"/whole.*
# Input $2 (then the run's options) on one process and on two, as "$1": the same bytes and
# check ($tmp/${1}1.json and ${1}2.json the reports).
one_and_two() {
    local name=$1 input=$2
    shift 2
    local args=(reconstruct "$input" --device openmp "$@")
    "$cli" "${args[@]}" --report "$tmp/${name}1.json" -o "$tmp/${name}1.stl" 2>/dev/null || fail "$name on one process"
    "${mpi[@]}" -np 2 "$cli" "${args[@]}" --report "$tmp/${name}2.json" -o "$tmp/${name}2.stl" 2>/dev/null ||
        fail "$name on two processes"
    cmp "$tmp/${name}1.stl" "$tmp/${name}2.stl" || fail "$name: other bytes on two processes"
    same_check "$tmp/${name}1.json" "$tmp/${name}2.json"
}
# A solid blob: most walls far thicker than a process's share reaches (the first measures them).
awk 'BEGIN { srand(3); for (i = 0; i < 4000; ++i) printf "%.6f %.6f %.6f\n", rand(), 0.5 * rand(), 0.7 * rand() }' \
    >"$tmp/blob.xyz"
one_and_two blob "$tmp/blob.xyz" --resolution 64 --tile-cells 16
# Two balls of points, the smaller dropped (--keep-largest 1): the shell is no longer the
# slabs the processes kept, so the first counts its topology whole.
awk 'BEGIN { srand(5); for (i = 0; i < 6000; ++i) { u = 2 * rand() - 1; t = 6.2831853 * rand(); s = sqrt(1 - u * u)
    r = i < 4500 ? 0.25 : 0.1; c = i < 4500 ? 0.3 : 0.8
    printf "%.6f %.6f %.6f\n", c + r * s * cos(t), 0.5 + r * s * sin(t), 0.5 + r * u } }' >"$tmp/balls.xyz"
one_and_two balls "$tmp/balls.xyz" --resolution 64 --tile-cells 16 --keep-largest 1
python3 -c 'import json, sys; sys.exit(0 if json.load(open(sys.argv[1]))["pieces_dropped"]["count"] == 1 else 1)' \
    "$tmp/balls2.json" || fail "two balls: the smaller was not dropped"
slab_topology 0 "$tmp/balls2.json"
rm "$tmp"/balls*
# A dense sphere (318,054 points, over the 2^18 the check samples for its percentile): the
# points' depths are measured by the process whose range of the points filed by both holds
# them (half of those the first does not sample: 79 k), where it kept them since the filing.
# The points near the other's slab of the surface (256 k) are more than its vertices, but
# the surface stays in the slabs, which keep them deep.
"$cli" sample noisy-sphere --spacing 0.0022 -o "$tmp/dense.ply" >/dev/null || fail "the sampler"
one_and_two dense "$tmp/dense.ply" --resolution 64 --tile-cells 16
python3 - "$tmp/dense2.json" <<'PY' || fail "the other process measured none of the check"
import json, sys
t = json.load(open(sys.argv[1]))["tiles"]
print(f"the other process: {t['check_walls_elsewhere']} walls, {t['check_points_elsewhere']} points' depths "
      f"({t['check_points_far']} asked of every slab), {t['guard_slab_points']} points given its slab for the depth guard")
sys.exit(0 if t["check_walls_elsewhere"] > 0 and t["check_points_elsewhere"] > 60000
         and t["guard_slab_points"] > 100000 and t["guard_on_slabs"] and t["surface_kept_in_slabs"] else 1)
PY
slab_topology 1 "$tmp/dense2.json"
# The other measures them where it kept them since the filing: scaled as the first's (in
# centimetres: told while the outlier rules ask, or, where they ask nothing, with its share
# of the check) and moved as the first's (centred): the same bytes and figures. With a
# preview the mesh is gathered whole, and the first keeps the points deep on the whole
# surface, the other searching its range of them for it, moved alike.
one_and_two dense_cm "$tmp/dense.ply" --resolution 64 --tile-cells 16 --units cm --origin center --preview "$tmp/p.png"
one_and_two dense_kept "$tmp/dense.ply" --resolution 64 --tile-cells 16 --units cm --origin center --keep-outliers
# (Points it holds elsewhere than the first's would come back undecided: the same figures,
# but measured by the first.)
python3 - "$tmp/dense_cm2.json" "$tmp/dense_kept2.json" <<'PY' || fail "the other process measured none of the points moved"
import json, sys
t = [json.load(open(f))["tiles"] for f in sys.argv[1:]]
sys.exit(0 if all(x["check_points_elsewhere"] > 60000 and x["check_points_far"] < 0.05 * x["check_points_elsewhere"]
                  for x in t) and t[0]["guard_points_elsewhere"] > 100000 and not t[0]["surface_kept_in_slabs"] else 1)
PY
rm "$tmp"/dense_cm[12].* "$tmp"/dense_kept[12].* "$tmp/p.png"
# The whole field kept (--volume): the level set made from it, the guard's search shared
# alike, the same field and shell.
for p in 1 2; do
    launch=("$cli")
    [ $p = 2 ] && launch=("${mpi[@]}" -np 2 "$cli")
    "${launch[@]}" reconstruct "$tmp/dense.ply" --device openmp --resolution 64 --tile-cells 16 \
        --volume "$tmp/field$p.vti" --report "$tmp/field$p.json" -o "$tmp/field$p.stl" 2>/dev/null ||
        fail "the field kept on $p processes"
done
cmp "$tmp/field1.stl" "$tmp/field2.stl" && cmp "$tmp/field1.vti" "$tmp/field2.vti" ||
    fail "the field kept: other bytes on two processes"
python3 -c 'import json, sys; sys.exit(0 if json.load(open(sys.argv[1]))["tiles"]["guard_points_elsewhere"] > 100000 else 1)' \
    "$tmp/field2.json" || fail "the field kept: the other searched none of its points for the depth guard"
slab_topology 0 "$tmp/field2.json"  # the first meshed the whole field: there are no slabs
rm "$tmp"/field[12].*
# Three processes: a middle range too (its clusters' links with the last range, its depths).
"${mpi[@]}" -np 3 "$cli" reconstruct "$tmp/dense.ply" --device openmp --resolution 64 --tile-cells 16 \
    --report "$tmp/dense3.json" -o "$tmp/dense3.stl" 2>/dev/null || fail "dense on three processes"
cmp "$tmp/dense1.stl" "$tmp/dense3.stl" || fail "dense: other bytes on three processes"
same_check "$tmp/dense1.json" "$tmp/dense3.json"
slabs_kept 1 "$tmp/dense3.json"
python3 -c 'import json, sys; t = json.load(open(sys.argv[1]))["tiles"]; sys.exit(0 if t["points_sent"] > 0 and t["points_from_ranges"] > 0 else 1)' \
    "$tmp/dense3.json" || fail "three processes: the tiles' points did not go by the ranges the others kept"
slab_topology 1 "$tmp/dense3.json"
rm "$tmp"/dense3.*
# A scan sparse beside its surface (the sampler's lidar scene, 10 k points): the points
# near the other's slab are fewer than its vertices, so each slab keeps its points deep, its
# checked ghosts the same as their owner's.
"$cli" sample lidar --spacing 0.005 -o "$tmp/lidar.ply" >/dev/null || fail "the sampler (lidar)"
one_and_two lidar "$tmp/lidar.ply" --resolution 192 --tile-cells 64
python3 -c 'import json, sys; t = json.load(open(sys.argv[1]))["tiles"]; sys.exit(0 if t["guard_on_slabs"] and t["guard_slab_points"] > 5000 and not t["guard_run_again_whole"] else 1)' \
    "$tmp/lidar2.json" || fail "the lidar scene: its slabs did not keep their points deep"
slab_topology 1 "$tmp/lidar2.json"  # the slabs as kept, each rounded as the STL holds it
rm "$tmp"/lidar[12].* "$tmp/lidar.ply"
# Slabs welded with too few ghosts for the guard (4 planes, 2 checked; a test's setting,
# which has the slabs guard whatever their points): their checked ghosts come out other than
# their owners', and the first runs the guard again on the whole surface from the slabs'
# vertices before theirs; the same bytes and figures.
SNVR_TEST_GUARD_GHOSTS=4 one_and_two rerun "$data/bunny.ply" --resolution 128 --tile-cells 32
python3 -c 'import json, sys; t = json.load(open(sys.argv[1]))["tiles"]; sys.exit(0 if t["guard_on_slabs"] and t["guard_run_again_whole"] and t["guard_ghosts_differing"] > 0 else 1)' \
    "$tmp/rerun2.json" || fail "slabs with 4 ghost planes: the slabs' guard was not run again on the whole"
slab_topology 1 "$tmp/rerun2.json"
slabs_kept 0 "$tmp/rerun2.json"  # gathered for the guard run again
rm "$tmp"/rerun[12].*
# Its binary PLY is read in parts, a part a process, and the points' tree filed by both
# (above); as text the first reads it and gives the other its part; where the other
# cannot see the file, the first gives it its part too: the same bytes each time.
"$cli" sample noisy-sphere --spacing 0.0022 -o "$tmp/dense.xyz" >/dev/null || fail "the sampler (text)"
one_and_two dense_text "$tmp/dense.xyz" --resolution 64 --tile-cells 16
dense=(reconstruct "$tmp/dense.ply" --device openmp --resolution 64 --tile-cells 16 --quiet)
"${mpi[@]}" -np 1 "$cli" "${dense[@]}" -o "$tmp/w.stl" : -np 1 "$cli" "${dense[@]/dense.ply/absent.ply}" -o "$tmp/w.stl" ||
    fail "the dense sphere with the other process not seeing it"
cmp "$tmp/dense1.stl" "$tmp/w.stl" || fail "the dense sphere with the other not seeing it: other bytes"
rm "$tmp/w.stl"
# The other process fails to read its part (the read-fault hook): the run fails, names it,
# and writes nothing.
out=$("${mpi[@]}" -np 1 "$cli" "${dense[@]}" -o "$tmp/y.stl" : -np 1 -x SNVR_TEST_READ_FAULT=eio:3000000 "$cli" \
      "${dense[@]}" -o "$tmp/y.stl" 2>&1)
[ $? -ne 0 ] || fail "a process that failed to read its part did not fail the run"
grep -q "process 1 of 2" <<<"$out" || fail "the failure to read a part does not name the process: $out"
[ ! -e "$tmp/y.stl" ] || fail "an output was written"
echo "read in parts, given parts, the other not seeing the file: the same bytes; a part that fails fails the run"
rm "$tmp"/dense_text[12].* "$tmp/dense.xyz"
# Under a budget: the points' arrays beyond it in files on both processes (the other's
# received straight into its cloud's), the same bytes as one process without a budget.
"$cli" sample noisy-sphere --spacing 0.0015 -o "$tmp/budget.ply" >/dev/null || fail "the sampler (budget)"
budget=(reconstruct "$tmp/budget.ply" --device openmp --resolution 64 --tile-cells 16)
"$cli" "${budget[@]}" -o "$tmp/budget1.stl" 2>/dev/null || fail "budget on one process"
"${mpi[@]}" -np 2 "$cli" "${budget[@]}" --max-memory 64M --report "$tmp/budget2.json" -o "$tmp/budget2.stl" \
    2>/dev/null || fail "budget on two processes"
cmp "$tmp/budget1.stl" "$tmp/budget2.stl" || fail "budget: other bytes on two processes under --max-memory"
python3 -c 'import json, sys; sys.exit(0 if json.load(open(sys.argv[1]))["memory"]["spilled"]["arrays"] > 0 else 1)' \
    "$tmp/budget2.json" || fail "budget: no array went to a file"
rm "$tmp"/budget[12].* "$tmp/budget.ply"
# A sparse sphere (616 points): the points added between them are made by both processes.
"$cli" sample noisy-sphere --spacing 0.05 -o "$tmp/sparse.ply" >/dev/null || fail "the sampler (sparse)"
one_and_two sparse "$tmp/sparse.ply" --resolution 64 --tile-cells 16
python3 - "$tmp/sparse1.json" "$tmp/sparse2.json" <<'PY' || fail "the points added were not made by both processes"
import json, sys
one, two = (json.load(open(f))["upsampled"] for f in sys.argv[1:])
print(f"points added: {two['points_added']}, {two['made_elsewhere']} by the other process")
sys.exit(0 if one["points_added"] == two["points_added"] > 1000 and 0 < two["made_elsewhere"] < two["points_added"]
         and one["made_elsewhere"] == 0 else 1)
PY
# A random sampling (5,000 points on a sphere): its holes sought by both processes.
"$cli" sample sphere --random 5000 -o "$tmp/random.ply" >/dev/null || fail "the sampler (random)"
one_and_two random "$tmp/random.ply" --resolution 128 --tile-cells 16
python3 - "$tmp/random1.json" "$tmp/random2.json" <<'PY' || fail "the holes were not sought by both processes"
import json, sys
one, two = (json.load(open(f))["sampling_holes"] for f in sys.argv[1:])
print(f"points at holes: {two['points_added']}, the holes at {two['sought_elsewhere']} points sought by the other")
sys.exit(0 if one["points_added"] == two["points_added"] > 100 and two["sought_elsewhere"] == 2500
         and one["sought_elsewhere"] == 0 else 1)
PY
rm "$tmp"/random*
# A sparse city block (300,000 points, past the 2^18 whose groups are all sampled) at a
# voxel finer than its scan lines' spacing: the tree's leaves run along the lines, many
# voxels long; cut narrower, their depths are dealt too (94 k points to the other, which
# makes its slab's answers before it measures; 115 k when it made them after; 76 k when
# such groups stayed with the first), in the groups the first made.
"$cli" sample city --points 300000 -o "$tmp/city.ply" >/dev/null || fail "the sampler (city)"
one_and_two city "$tmp/city.ply" --resolution 384 --tile-cells 64
python3 - "$tmp/city2.json" <<'PY' || fail "the sparse block's wide groups were not dealt"
import json, sys
t = json.load(open(sys.argv[1]))["tiles"]
print(f"sparse block: {t['check_points_elsewhere']} points' depths by the other ({t['check_points_far']} asked of every slab)")
sys.exit(0 if t["check_points_elsewhere"] > 85000 else 1)
PY
rm "$tmp"/city[12].* "$tmp/city.ply"
# The same with six stray points far off: the outlier rules drop them and shrink the box,
# which then is not the first process's tree's frame; the other files the points it is
# given in that frame, so that its run of them is the first's (6,621 points added, not
# 6,639, when it filed them in their own box).
"$cli" sample noisy-sphere --spacing 0.05 -o "$tmp/strays.xyz" >/dev/null || fail "the sampler (strays)"
awk 'BEGIN { for (i = 0; i < 6; ++i) printf "%.4f %.4f %.4f\n", 3 + 0.0002 * i, 3, 3 }' >>"$tmp/strays.xyz"
one_and_two strays "$tmp/strays.xyz" --resolution 64 --tile-cells 16
rm "$tmp"/blob[12].* "$tmp/blob.xyz" "$tmp/one.json" "$tmp"/dense[12].* "$tmp/dense.ply" "$tmp"/sparse[12].* "$tmp/sparse.ply"
rm "$tmp"/strays[12].* "$tmp/strays.xyz"
grep -q '"processes": 2' "$tmp/two.json" || fail "the report does not say 2 processes"
rm "$tmp/two.json"
grep -q "tile: .* s left; process 0: [0-9]* of [0-9]*, process 1: [0-9]* of [0-9]*" "$tmp/two.log" ||
    fail "the progress does not show each process's tiles: $(tail -3 "$tmp/two.log")"
rm "$tmp/two.log"
echo "2 processes: the same bytes and check as 1 (the bunny, a solid blob, a dense sphere, a sparse one, a sparse city block, one with strays)"

out=$("${mpi[@]}" -np 2 "$cli" reconstruct "$data/bunny.ply" -o "$tmp/x.stl" --quiet 2>&1)
[ $? -ne 0 ] || fail "no --tile-cells under mpirun was accepted"
grep -q "give --tile-cells N" <<<"$out" || fail "no --tile-cells: $out"
[ "$(grep -c 'give --tile-cells' <<<"$out")" -eq 1 ] || fail "the usage error said more than once: $out"
[ ! -e "$tmp/x.stl" ] || fail "an output was written"
echo "no --tile-cells: refused once"

# The others need not see the input: process 1 given an input that is not there runs its
# tiles as the first gives them, the same bytes.
absent=(reconstruct "$tmp/absent.ply" "${run[@]:2}")
"${mpi[@]}" -np 1 "$cli" "${run[@]}" -o "$tmp/w.stl" : -np 1 "$cli" "${absent[@]}" -o "$tmp/w.stl" ||
    fail "process 1 read its input"
cmp "$tmp/one.stl" "$tmp/w.stl" || fail "process 1 without the input: other bytes"
rm "$tmp/w.stl"
echo "the other processes need not see the input: the same bytes"

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
