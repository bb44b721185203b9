#!/bin/sh
# The estimators' speed plots from one sfm_bench run written as JSON:
#   sfm_bench --benchmark_out=sfm_bench.json --benchmark_out_format=json
#   bench/plot_sfm_bench.sh sfm_bench.json share/omnisfm/figures
# writes DIR/sfm-filter-time-vs-points.png (the filter's CPU time per frame against the number of
# points: new points, settled points, one iteration) and DIR/sfm-batch-time-vs-images.png (the
# batch against the number of images).
set -eu
if [ $# -ne 2 ] || [ ! -r "$1" ]; then
  echo "usage: $0 SFM_BENCH_JSON OUT_DIR" >&2
  exit 2
fi
json=$1
out=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

python3 - "$json" "$work" <<'EOF'
import json, sys
path, work = sys.argv[1], sys.argv[2]

def fail(message):
    print(f"{path}: {message}", file=sys.stderr)
    sys.exit(2)

try:
    runs = json.load(open(path))["benchmarks"]
except (OSError, ValueError, KeyError) as e:
    fail(f"not a Google Benchmark JSON output ({e})")
tables = {"filter": [], "filter_settled": [], "filter1": [], "batch": []}
for r in runs:
    if r.get("run_type") == "aggregate" and r.get("aggregate_name") != "median":
        continue
    family, _, arg = r["name"].partition("/")
    arg = arg.split("/")[0]
    scale = {"ms": 1e-3, "us": 1e-6, "ns": 1e-9, "s": 1.0}[r["time_unit"]]
    if family == "BM_FilterFrame":
        tables["filter"].append((int(arg), 1e3 * r["s_per_frame"]))
    elif family == "BM_FilterFrameSettled":
        tables["filter_settled"].append((int(arg), 1e3 * r["s_per_frame"]))
    elif family == "BM_FilterFrameOneIteration":
        tables["filter1"].append((int(arg), 1e3 * r["s_per_frame"]))
    elif family == "BM_BatchScaled":
        tables["batch"].append((int(arg), scale * r["real_time"], scale * r["cpu_time"]))
for name in ("filter", "batch"):
    if not tables[name]:
        fail(f"no {'BM_FilterFrame' if name == 'filter' else 'BM_BatchScaled'} results")
for name, rows in tables.items():
    with open(f"{work}/{name}.dat", "w") as f:
        for row in sorted(rows):
            f.write(" ".join(str(v) for v in row) + "\n")
EOF

settled=""
if [ -s "$work/filter_settled.dat" ]; then
  settled=", \"$work/filter_settled.dat\" using 1:2 with linespoints lw 2 pt 9 title \"iterated, depths settled (frames 40-59)\""
fi
one_iteration=""
if [ -s "$work/filter1.dat" ]; then
  one_iteration=", \"$work/filter1.dat\" using 1:2 with linespoints lw 2 pt 5 title \"one iteration (classic EKF)\""
fi
gnuplot <<EOF
set terminal pngcairo size 800,560
set grid
set key top left
set output "$work/filter.png"
set title "Online filter: CPU time per frame (one core)"
set xlabel "points in the state"
set ylabel "ms per frame"
set logscale y
plot "$work/filter.dat" using 1:2 with linespoints lw 2 pt 7 title "iterated update (default), frames 1-20" $settled $one_iteration, \
     3 with lines dt 2 lc rgb "red" title "goal at 112 points: 3 ms"
unset logscale y
set offsets 0, 0, graph 0.12, 0
set key left center Left reverse
set output "$work/batch.png"
set title "Batch adjustment on long drives (tracks about 30 images long)"
set xlabel "images (as many points)"
set ylabel "seconds"
plot "$work/batch.dat" using 1:2 with linespoints lw 2 pt 7 title "wall", \
     "$work/batch.dat" using 1:3 with linespoints lw 2 pt 5 title "CPU of the calling thread (Ceres runs 2)", \
     60 with lines dt 2 lc rgb "red" title "goal at 2,000 images: 60 s"
EOF
mkdir -p "$out"
mv "$work/filter.png" "$out/sfm-filter-time-vs-points.png"
mv "$work/batch.png" "$out/sfm-batch-time-vs-images.png"
