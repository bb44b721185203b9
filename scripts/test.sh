#!/usr/bin/env bash
# Sets up omnisfm and runs the whole test suite (every CTest label) in build/, then the readers',
# the camera's and the plugin's tests (label sanitize) and the fuzz targets under
# AddressSanitizer and UndefinedBehaviorSanitizer in build-sanitize/ (docs/reliability.md).
#   scripts/test.sh [CTEST ARGS...]   the arguments go to the first ctest run
#   OMNISFM_SANITIZE=0                skips the sanitizer build
#   OMNISFM_SANITIZE_LABELS=REGEX     the labels run there (default: sanitize|fuzz)
set -euo pipefail
cd "$(dirname "$0")/.."
# The tests run side by side on every core: the omnisfm command's image work takes one thread
# each (its OpenCV threads would spin waiting for a core), as the gtest programs are given.
export OMNISFM_THREADS="${OMNISFM_THREADS:-1}"
scripts/setup.sh
(cd "${OMNISFM_BUILD_DIR:-build}" &&
  ctest --output-on-failure --parallel "$(nproc)" --timeout 600 "$@")
if [ "${OMNISFM_SANITIZE:-1}" != 0 ]; then
  # The default labels' tests and fuzz targets alone are built there; other labels build all.
  if [ -z "${OMNISFM_SANITIZE_LABELS:-}" ]; then
    scripts/setup.sh --sanitize omnisfm_sanitizer_checks
  else
    scripts/setup.sh --sanitize
  fi
  (cd "${OMNISFM_SANITIZE_BUILD_DIR:-build-sanitize}" &&
    ctest --output-on-failure --parallel "$(nproc)" --timeout 600 \
      -L "${OMNISFM_SANITIZE_LABELS:-sanitize|fuzz}")
fi
