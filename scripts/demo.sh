#!/usr/bin/env bash
# Sets up omnisfm and runs the main job: `omnisfm demo` on the embedded dataset.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
exec build/apps/omnisfm/omnisfm demo "$@"
