#!/usr/bin/env bash
# The unit and CLI tests built with AddressSanitizer + UndefinedBehaviorSanitizer
# (-fsanitize=address,undefined -fno-sanitize-recover=undefined), run with leak detection.
#
# One instrumented build serves the sanitizer tests and the fuzzers: build-fuzz/, configured with
# clang, AQ_BUILD_FUZZ=ON (fuzz/flags.cmake adds the sanitizers and libFuzzer's coverage to every
# target) and the tests on. scripts/fuzz.sh then reuses it. One clang build instead of a GCC ASan
# build plus a clang fuzz build roughly halves this part of CI (docs/testing.md "Sanitizers").
# The GL reference tests are not part of this build: llvmpipe JIT-compiles shaders into code ASan
# cannot instrument, and Mesa's allocations at exit are reported as leaks that are not ours; they
# run in the normal build (docs/testing.md). Leaks inside third-party libraries are suppressed by
# fuzz/lsan.supp (each entry named and explained there); any other report fails the run.
# Usage: scripts/sanitize.sh [--no-install] [extra ctest args]
set -euo pipefail
cd "$(dirname "$0")/.."
install=(); [ "${1:-}" = "--no-install" ] && { install=(--no-install); shift; }
build_dir=build-fuzz
# Installs clang + libFuzzer's runtime if missing and configures/builds the fuzz targets.
bash scripts/fuzz.sh "${install[@]}" --build-only
gen=()
command -v ninja >/dev/null && gen=(-G Ninja)
CC=clang CXX=clang++ cmake -S . -B "$build_dir" "${gen[@]}" -DBUILD_TESTING=ON -DAQ_BUILD_PYTHON=OFF >/dev/null
cmake --build "$build_dir" --parallel "$(nproc)"
export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1"
export LSAN_OPTIONS="suppressions=$PWD/fuzz/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
echo "sanitize: running unit and CLI tests under ASan+UBSan (clang, $build_dir)"
ctest --test-dir "$build_dir" --output-on-failure --timeout 900 -j "$(nproc)" -L "unit|cli" "$@"
