#!/usr/bin/env bash
# run_fuzz_target.sh TARGET SECONDS SEED_CORPUS WORK_DIR
# Runs a libFuzzer target for SECONDS from its seed corpus, with a fixed seed so that a run goes
# the same way each time (up to how far it gets in SECONDS). New inputs it finds go to
# WORK_DIR/corpus (the committed seeds are never written); a crash, leak, timeout, sanitizer
# report or broken contract leaves its input in WORK_DIR and fails, with the command that
# reproduces it.
#
# OMNISFM_FUZZ_FLAGS adds libFuzzer flags.
set -euo pipefail
target=$1 seconds=$2 seeds=$3 work=$4
rm -rf "$work"
mkdir -p "$work/corpus"
status=0
"$target" -seed=1 -max_total_time="$seconds" -timeout=20 -rss_limit_mb=3072 -print_final_stats=1 ${OMNISFM_FUZZ_FLAGS:-} \
  -artifact_prefix="$work/" "$work/corpus" "$seeds" >"$work/log" 2>&1 || status=$?
tail -n 30 "$work/log"

failed=0
for input in "$work"/crash-* "$work"/leak-* "$work"/timeout-* "$work"/oom-*; do
  [ -e "$input" ] || continue
  echo "finding: $input (reproduce: $target $input)"
  failed=1
done
if [ "$failed" -ne 0 ]; then exit 1; fi
exit "$status"
