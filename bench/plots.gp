# PNG plots of snvr-bench's .dat files (scripts/bench.sh runs this):
#   gnuplot -e "dir='bench/latest'" bench/plots.gp
if (!exists("dir")) dir = "bench/latest"
set terminal pngcairo size 960,620 noenhanced font ",11"
set grid
set key outside right top

# One line per series (first column: device/precision or shape/device/precision).
series(file) = system("awk '!/^#/ {print $1}' " . file . " | sort -u | tr '\n' ' '")
rows(file, s) = "< awk '$1 == \"" . s . "\"' " . file

# A section that was not run has an empty .dat file: no plot for it.
f = dir . "/scaling.dat"
if (strlen(series(f)) > 0) {
set output dir . "/scaling.png"
set title "Scaling: the bunny from 128 cells on the longest axis up"
set logscale xy
set xlabel "cells in the band"
set ylabel "seconds, file to mesh (median)"
plot for [s in series(f)] rows(f, s) using 3:4 with linespoints pt 7 title s

set output dir . "/scaling_cells.png"
set title "Scaling against all cells of the grid"
set xlabel "cells in the grid"
plot for [s in series(f)] rows(f, s) using 2:4 with linespoints pt 7 title s

set output dir . "/scaling_memory.png"
set xlabel "cells in the band"
set title "Peak memory against cells in the band"
set ylabel "peak resident memory, MiB"
plot for [s in series(f)] rows(f, s) using 3:6 with linespoints pt 7 title s

set output dir . "/scaling_bytes_per_band_cell.png"
set title "Memory per cell of the band: the solver's fields (lines) and the peak (points)"
unset logscale y
set yrange [0:*]
set ylabel "bytes per band cell"
plot for [s in series(f)] rows(f, s) using 3:7 with linespoints pt 7 title s . " solver", \
     for [s in series(f)] rows(f, s) using 3:8 with points pt 4 ps 1.5 title s . " peak"
set autoscale y
unset logscale
}

f = dir . "/table2.dat"
if (strlen(series(f)) > 0) {
set logscale xy
set output dir . "/table2.png"
set title "Table 2: grown-sheet error against grid size (lines: ours; points: the paper)"
set xlabel "cells per axis"
set ylabel "RMS error of the grown sheet"
plot for [s in series(f)] rows(f, s) using 2:3 with linespoints pt 7 title s, \
     for [s in series(f)] rows(f, s) using 2:5 with points pt 4 ps 2 notitle
unset logscale
}

# The points section: one line per program (colour) and grid (dashes: 256 solid, 512
# dashed, ...) along the noisy sphere's densities; the other shapes and the scans as
# open circles in their line's colour.
f = dir . "/points.dat"
if (strlen(series(f)) > 0) {
S = series(f)
family_rows(file, s, condition) = "< awk '$1 == \"" . s . "\" && " . condition . "' " . file
colour(s) = strstrt(s, "snvr-cl") ? 1 : (strstrt(s, "distance") ? 2 : 4)
dashes(s) = 1 + ((int(log(real(s[strstrt(s, "/") + 1:])) / log(2) + 0.5) - 8) % 5 + 5) % 5
sphere = "$2 == \"noisy-sphere\""
others = "$2 != \"noisy-sphere\""
set logscale xy
set xlabel "points"
set output dir . "/points.png"
set title "Seconds against points at a fixed grid (lines: the noisy sphere; circles: other shapes and scans)"
set ylabel "wall-clock seconds, file to mesh (whole process)"
plot for [i=1:words(S)] family_rows(f, word(S, i), sphere) using 3:4 with linespoints lc colour(word(S, i)) dt dashes(word(S, i)) pt 7 title word(S, i), \
     for [i=1:words(S)] family_rows(f, word(S, i), others) using 3:4 with points lc colour(word(S, i)) pt 6 ps 1.5 notitle
set output dir . "/points_cpu.png"
set title "CPU seconds against points at a fixed grid (lines: the noisy sphere; circles: other shapes and scans)"
set ylabel "CPU seconds, user + system, every thread"
plot for [i=1:words(S)] family_rows(f, word(S, i), sphere) using 3:6 with linespoints lc colour(word(S, i)) dt dashes(word(S, i)) pt 7 title word(S, i), \
     for [i=1:words(S)] family_rows(f, word(S, i), others) using 3:6 with points lc colour(word(S, i)) pt 6 ps 1.5 notitle
set output dir . "/points_memory.png"
set title "Peak memory against points at a fixed grid (lines: the noisy sphere; circles: other shapes and scans)"
set ylabel "peak resident memory, MiB"
plot for [i=1:words(S)] family_rows(f, word(S, i), sphere) using 3:5 with linespoints lc colour(word(S, i)) dt dashes(word(S, i)) pt 7 title word(S, i), \
     for [i=1:words(S)] family_rows(f, word(S, i), others) using 3:5 with points lc colour(word(S, i)) pt 6 ps 1.5 notitle
unset logscale
}

f = dir . "/roofline.dat"
if (strlen(series(f)) > 0) {
set output dir . "/roofline.png"
set title "Achieved bandwidth as a fraction of a copy on the same device"
set xlabel ""
set ylabel "fraction of copy bandwidth"
set yrange [0:1.1]
set xtics rotate by -20
plot for [s in series(f)] rows(f, s) using 0:4:xtic(2) with linespoints pt 7 title s
}
