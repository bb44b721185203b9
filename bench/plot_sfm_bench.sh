#!/bin/sh
# The estimators' speed plots from one sfm_bench run written as CSV:
#   sfm_bench --benchmark_out=sfm_bench.csv --benchmark_out_format=csv
#   bench/plot_sfm_bench.sh sfm_bench.csv share/omnisfm/figures
# writes DIR/sfm-filter-time-vs-points.png (the filter's time per frame against the number of
# points) and DIR/sfm-batch-time-vs-images.png (the batch to convergence against the images).
set -eu
if [ $# -ne 2 ] || [ ! -r "$1" ]; then
  echo "usage: $0 SFM_BENCH_CSV OUT_DIR" >&2
  exit 2
fi
csv=$1
out=$2
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Google Benchmark's CSV: name,iterations,real_time,cpu_time,time_unit,...; the header names the
# counters' columns. Names are quoted and carry the argument after a slash.
awk -F, -v dir="$work" '
  NR == 1 || !/^"BM_/ { if ($1 == "name") for (i = 1; i <= NF; ++i) col[$i] = i; next }
  {
    name = $1; gsub(/"/, "", name); split(name, part, "/")
    if (part[1] == "BM_FilterFrame") print part[2], $(col["\"s_per_frame\""]) * 1000 > dir "/filter.dat"
    if (part[1] == "BM_BatchScaled") print part[2], $3 / 1000, $4 / 1000 > dir "/batch.dat"
  }' "$csv"
for f in filter batch; do
  if [ ! -s "$work/$f.dat" ]; then
    echo "$csv: no BM_$( [ $f = filter ] && echo FilterFrame || echo BatchScaled) rows" >&2
    exit 2
  fi
done

gnuplot <<EOF
set terminal pngcairo size 800,560
set grid
set key top left
set output "$work/filter.png"
set title "Online filter: time per frame (one core)"
set xlabel "points in the state"
set ylabel "ms per frame"
plot "$work/filter.dat" using 1:2 with linespoints lw 2 pt 7 title "measured", \
     3 with lines dt 2 lc rgb "red" title "goal at 112 points"
set output "$work/batch.png"
set title "Batch adjustment to convergence (tracks about 30 images long)"
set xlabel "images (as many points)"
set ylabel "seconds"
plot "$work/batch.dat" using 1:2 with linespoints lw 2 pt 7 title "wall", \
     "$work/batch.dat" using 1:3 with linespoints lw 2 pt 5 title "CPU (2 threads)", \
     60 with lines dt 2 lc rgb "red" title "goal at 2,000 images"
EOF
mv "$work/filter.png" "$out/sfm-filter-time-vs-points.png"
mv "$work/batch.png" "$out/sfm-batch-time-vs-images.png"
