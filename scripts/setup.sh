#!/usr/bin/env bash
# Installs the Debian packages omnisfm needs (only those missing), then configures and builds
# into build/. Idempotent: quiet when everything is already there.
#   scripts/setup.sh --sanitize [TARGET]
#                                 the same into build-sanitize/: clang with AddressSanitizer and
#                                 UndefinedBehaviorSanitizer, the libraries, the tests and the
#                                 libFuzzer targets (no benchmarks); only TARGET if given
#                                 (omnisfm_sanitizer_checks: what CI runs there)
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake ccache pkg-config
  libeigen3-dev libceres-dev libopengv-dev libgeographiclib-dev libopenblas-dev
  libopencv-dev libopencv-contrib-dev libjpeg-dev
  libmrpt-dev mrpt-apps
  libmrcal-dev mrcal python3-mrcal mrgingham
  libcli11-dev libgtest-dev libbenchmark-dev
  gnuplot-nox python3 xvfb xauth
  clang libclang-rt-14-dev
)

sanitize=0
target=()
if [ "${1:-}" = "--sanitize" ]; then
  sanitize=1
  if [ -n "${2:-}" ]; then target=(--target "$2"); fi
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

if [ "$sanitize" -eq 1 ]; then
  build_dir=${OMNISFM_SANITIZE_BUILD_DIR:-build-sanitize}
  if [ ! -f "$build_dir/CMakeCache.txt" ]; then
    # -O1 with line tables: the sanitizers' usual trade between speed and readable reports.
    CC=clang CXX=clang++ cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 \
      -DOMNISFM_FUZZ=ON -DOMNISFM_BUILD_BENCH=OFF >/dev/null
  fi
else
  build_dir=${OMNISFM_BUILD_DIR:-build}
  if [ ! -f "$build_dir/CMakeCache.txt" ]; then
    cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
  fi
fi
echo "setup: building in $build_dir/" >&2
log=$(mktemp)
trap 'rm -f "$log"' EXIT
if ! cmake --build "$build_dir" --parallel "$(nproc)" ${target[@]+"${target[@]}"} >"$log" 2>&1; then
  cat "$log" >&2
  echo "setup: the build failed" >&2
  exit 1
fi
grep -A3 "warning:" "$log" >&2 || true
