#!/bin/sh
# The soak plots from soak_bench's series:
#   soak_bench --soak_out=soak_
#   bench/plot_soak.sh soak_ share/omnisfm/figures
# writes DIR/soak-memory-time.png (resident memory and time per frame against the frames) and
# DIR/soak-errors.png (the errors against the distance driven) from PREFIXfilter_soak.vnl and
# PREFIXestimator_soak.vnl, whichever exist.
set -eu
if [ $# -ne 2 ]; then
  echo "usage: $0 SERIES_PREFIX OUT_DIR" >&2
  exit 2
fi
prefix=$1
out=$2
filter=${prefix}filter_soak.vnl
estimator=${prefix}estimator_soak.vnl
[ -r "$filter" ] || [ -r "$estimator" ] || { echo "$0: neither $filter nor $estimator" >&2; exit 2; }
mkdir -p "$out"
# gnuplot skips the '#' header; the columns are soak_bench's. Both series, of those that exist:
both() {  # X Y FILTER_TITLE ESTIMATOR_TITLE
  line=""
  [ -r "$filter" ] && line="'$filter' using $1:$2 with lines lw 2 title '$3'"
  if [ -r "$estimator" ]; then
    [ -n "$line" ] && line="$line, "
    line="$line'$estimator' using $1:$2 with lines lw 2 title '$4'"
  fi
  printf '%s' "$line"
}
gnuplot <<GNUPLOT
set terminal pngcairo size 1000,700 font ",11"
set output "$out/soak-memory-time.png"
set multiplot layout 2,1 title "Soak over the endless drive (0.2 px, 3 cm per frame)"
set grid
set ylabel "resident memory (MB)"
plot $(both 1 3 "filter alone" "MRPT estimator, odometry and gyro")
set xlabel "frames"
set ylabel "time per frame (ms)"
set yrange [0:*]
plot $(both 1 4 "filter alone" "MRPT estimator, odometry and gyro")
unset multiplot

set output "$out/soak-errors.png"
set multiplot layout 2,1 title "Errors along the endless drive (every 1,000 frames, 30 m)"
set xlabel "distance driven (m)"
set ylabel "error of the last 30 m (% of 30 m)"
set logscale y
set yrange [*:*]
plot $(both 2 '($5 > 0 ? $5 : 1e-3)' "filter alone, similarity" "estimator, rigid")
set ylabel "rotation error (deg)"
plot $(both 2 '($8 > 0 ? $8 : 1e-3)' "filter alone" "estimator")
unset multiplot
GNUPLOT
