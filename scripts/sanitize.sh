#!/usr/bin/env bash
# Builds the library, the CLI and the unit tests with AddressSanitizer + UndefinedBehaviorSanitizer
# (-fsanitize=address,undefined -fno-sanitize-recover=undefined) into build-asan/ and runs the unit
# and CLI tests there. The GL reference tests are not part of this build: llvmpipe JIT-compiles
# shaders into code ASan cannot instrument, and Mesa's allocations at exit are reported as leaks
# that are not ours; they run in the normal build (docs/testing.md).
# Leaks inside third-party libraries are suppressed by tests/sanitizers/lsan.supp (each entry named
# and explained there); any other report fails the run.
# Usage: scripts/sanitize.sh [extra ctest args]
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=build-asan
gen=()
command -v ninja >/dev/null && gen=(-G Ninja)
if [ ! -f "$build_dir/CMakeCache.txt" ]; then
  cmake -S . -B "$build_dir" "${gen[@]}" -DCMAKE_BUILD_TYPE=Release -DAQ_SANITIZE=ON \
        -DAQ_BUILD_BENCH=OFF -DAQ_BUILD_REFERENCE=OFF >/dev/null
fi
cmake --build "$build_dir" --parallel "$(nproc)"
supp="$PWD/tests/sanitizers/lsan.supp"
export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1"
export LSAN_OPTIONS="suppressions=$supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
echo "sanitize: running unit and CLI tests under ASan+UBSan"
ctest --test-dir "$build_dir" --output-on-failure --timeout 900 -j "$(nproc)" -L "unit|cli" "$@"
