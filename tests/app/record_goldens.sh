#!/bin/bash
# tests/app/record_goldens.sh — records tests/app/golden_hashes.tsv from the current
# implementation (tests/app/golden_test.cpp). Only for a deliberate change of bytes, in its own
# commit that says which targets changed and why.
# Usage (repository root): tests/app/record_goldens.sh [BUILD=build]
set -euo pipefail
BUILD=${1:-build}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
AQ_GOLDEN_RECORD=$dir "$BUILD/tests/app/golden_test" --gtest_brief=1
{
    echo "# Regression goldens (tests/app/golden_test.cpp): scene, preset, target, SHA-256 of the target"
    echo "# (width, height, channels and float bytes; 'final' = the image --out receives), 400x226, frame 5."
    echo "# Recorded by tests/app/record_goldens.sh at $(git rev-parse --short HEAD)$(git diff --quiet HEAD -- . ':!tests/app/golden_hashes.tsv' || echo ' + local changes')."
    sort "$dir"/*.tsv
} >tests/app/golden_hashes.tsv
wc -l tests/app/golden_hashes.tsv
