#!/usr/bin/env bash
# Sets up omnisfm and runs the whole test suite (every CTest label).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cd "${OMNISFM_BUILD_DIR:-build}"
ctest --output-on-failure --parallel "$(nproc)" --timeout 600 "$@"
