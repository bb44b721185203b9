#!/usr/bin/env bash
# run_fuzz_target.sh TARGET SECONDS SEED_CORPUS WORK_DIR
# Runs a libFuzzer target for SECONDS from its seed corpus, with a fixed seed so that a run goes
# the same way each time (up to how far it gets in SECONDS). New inputs it finds go to
# WORK_DIR/corpus (the committed seeds are never written); a crash, leak, timeout, sanitizer
# report or broken contract leaves its input in WORK_DIR and fails, with the command that
# reproduces it.
#
# OMNISFM_FUZZ_FLAGS adds libFuzzer flags. The rawlog target runs in fork mode and goes on past
# its findings, since MRPT 2.5 sizes a damaged rawlog's strings and vectors from their stored
# lengths (2.6 GB, 16 GB seen) before it finds the file too short (issue 19). Each finding is
# then replayed: one that is running out of memory in an allocation made by MRPT's own code is
# that known finding and is listed; any other fails the run.
set -euo pipefail
target=$1 seconds=$2 seeds=$3 work=$4
rm -rf "$work"
mkdir -p "$work/corpus"
status=0
"$target" -seed=1 -max_total_time="$seconds" -timeout=20 -rss_limit_mb=3072 -print_final_stats=1 ${OMNISFM_FUZZ_FLAGS:-} \
  -artifact_prefix="$work/" "$work/corpus" "$seeds" >"$work/log" 2>&1 || status=$?
tail -n 30 "$work/log"

# True when replaying INPUT runs out of memory in an allocation whose first caller outside the
# allocator, the C++ library, OpenCV's matrices and the fuzzer is a function of an MRPT library.
# The slow unwinder follows the stack through libraries built without frame pointers.
allocation_by_mrpt() {
  local replay
  replay=$(ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}fast_unwind_on_malloc=0" \
    "$target" -malloc_limit_mb=256 -rss_limit_mb=3072 "$1" 2>&1 || true)
  grep -qE "ERROR: (libFuzzer: out-of-memory \(malloc|AddressSanitizer: (allocator is out of memory|out of memory|requested allocation size))" \
    <<<"$replay" || return 1
  awk '/ERROR: (libFuzzer|AddressSanitizer)/ { stack = 1; next }
       stack && /^ +#[0-9]+ / {
         if ($0 ~ / in (__sanitizer|__asan|__interceptor|fuzzer::|operator new|malloc|calloc|realloc|std::|__gnu_cxx::|void std::|cv::)/) next
         found = ($0 ~ /\/libmrpt-[a-z0-9_-]+\.so/); exit }
       END { exit found ? 0 : 1 }' <<<"$replay"
}

failed=0 known=0
for input in "$work"/crash-* "$work"/leak-* "$work"/timeout-* "$work"/oom-*; do
  [ -e "$input" ] || continue
  case $(basename "$input") in
    crash-* | oom-*)
      if allocation_by_mrpt "$input"; then
        echo "known finding, MRPT's allocation from a stored length: $input"
        known=$((known + 1))
        continue
      fi ;;
  esac
  echo "finding: $input (reproduce: $target $input)"
  failed=1
done
if [ "$failed" -ne 0 ]; then exit 1; fi
# A run that ended in failure without a known finding to explain it fails.
if [ "$status" -ne 0 ] && [ "$known" -eq 0 ]; then exit "$status"; fi
exit 0
