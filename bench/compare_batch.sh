#!/bin/sh
# The batch's figures from two omnisfm builds on the simulated lab, crane and rover, seeds 1-3:
# iterations, residual RMS and the errors after a similarity alignment, one line per build and
# run, for checking that a change to the batch leaves its results alone.
#   bench/compare_batch.sh ../main/build/apps/omnisfm/omnisfm build/apps/omnisfm/omnisfm
set -eu
if [ $# -ne 2 ] || [ ! -x "$1" ] || [ ! -x "$2" ]; then
  echo "usage: $0 OMNISFM_BEFORE OMNISFM_AFTER" >&2
  exit 2
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for scenario in lab crane rover; do
  for seed in 1 2 3; do
    data="$work/$scenario-$seed"
    "$1" simulate --scenario $scenario --seed $seed --out "$data" >/dev/null 2>"$work/log" ||
      { cat "$work/log" >&2; exit 1; }
    for build in before after; do
      program=$1
      [ $build = after ] && program=$2
      "$program" sfm --camera "$data/camera.ini" --tracks "$data/tracks.vnl" --out "$work/out" \
        --ground-truth "$data/ground_truth.tum" >/dev/null
      summary=$(sed -n 's/^batch: \(converged\|did not converge\) in \([0-9]*\) iterations.*RMS [0-9.]* -> \([0-9.]*\) px.*/\1 in \2 iterations, RMS \3 px/p' "$work/out/report.txt")
      errors=$(sed -n 's/^batch *translation [0-9.]* m mean (\([0-9.]*\)% .*rotation \([0-9.]*\) deg, yaw \([0-9.]*\) deg.*/\1 %, rotation \2 deg, yaw \3 deg/p' "$work/out/report.txt")
      outliers=$(sed -n 's/.*outlier tracks \([0-9]*\).*/\1/p' "$work/out/report.txt")
      echo "$scenario$seed $build: $summary; $errors; $outliers outlier tracks"
    done
  done
done
