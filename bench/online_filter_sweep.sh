#!/bin/sh
# The online filter's translation error (% of the distance travelled, after a similarity
# alignment) on the simulated lab, crane and rover for seeds 1-3, with the given [sfm] settings
# and no batch: one line per settings string, for comparing filter settings.
#   bench/online_filter_sweep.sh build/apps/omnisfm/omnisfm "" "update_iterations = 1"
# Each argument after the program is the body of an [sfm] section (lines separated by "\n").
set -eu
if [ $# -lt 2 ] || [ ! -x "$1" ]; then
  echo "usage: $0 OMNISFM SETTINGS..." >&2
  exit 2
fi
omnisfm=$1
shift
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

for scenario in lab crane rover; do
  for seed in 1 2 3; do
    "$omnisfm" simulate --scenario $scenario --seed $seed --out "$work/$scenario-$seed" \
      >/dev/null 2>"$work/simulate.log" || { cat "$work/simulate.log" >&2; exit 1; }
  done
done
for settings in "$@"; do
  printf '[sfm]\nbatch = 0\n%b\n' "$settings" > "$work/sfm.ini"
  line=""
  for scenario in lab crane rover; do
    for seed in 1 2 3; do
      data="$work/$scenario-$seed"
      "$omnisfm" sfm --camera "$data/camera.ini" --tracks "$data/tracks.vnl" --out "$work/out" \
        --config "$work/sfm.ini" --ground-truth "$data/ground_truth.tum" >/dev/null
      error=$(sed -n 's/^online .*(\([0-9.]*\)% of.*/\1/p' "$work/out/report.txt")
      line="$line $scenario$seed=$error"
    done
  done
  echo "[$(printf '%b' "$settings" | tr '\n' ';')]$line"
done
