#!/usr/bin/env bash
# Builds (if needed) and runs every test with CTest: unit, invariants, determinism, bad input and
# the GPU-equivalent OpenGL reference checks (label `reference`).
# Usage: scripts/test.sh [extra ctest args, e.g. -L reference or -R raster]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
ctest --test-dir build --output-on-failure --timeout 900 -j "$(nproc)" "$@"
