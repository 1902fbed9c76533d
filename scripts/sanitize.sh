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
# The Python module too when pybind11 is installed (scripts/setup.sh installs it), as fuzz.sh
# configures it: its tests run below with the ASan runtime preloaded into the interpreter.
python=OFF; [ -f /usr/lib/cmake/pybind11/pybind11Config.cmake ] && python=ON
CC=clang CXX=clang++ cmake -S . -B "$build_dir" "${gen[@]}" -DBUILD_TESTING=ON -DAQ_BUILD_PYTHON=$python >/dev/null
cmake --build "$build_dir" --parallel "$(nproc)"
export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1"
export LSAN_OPTIONS="suppressions=$PWD/fuzz/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
echo "sanitize: running unit and CLI tests under ASan+UBSan (clang, $build_dir)"
ctest --test-dir "$build_dir" --output-on-failure --timeout 900 -j "$(nproc)" -L "unit|cli" "$@"
if [ "$python" = ON ]; then
  # The interpreter is not instrumented: the ASan runtime (with UBSan's handlers) is preloaded, leak
  # detection off (CPython keeps its objects at exit); lifetimes, overflows and undefined
  # behaviour of the module are checked, and the suite's reference-count test covers leaks.
  echo "sanitize: the Python module's tests under ASan+UBSan ($build_dir/python)"
  LD_PRELOAD="$(clang -print-file-name=libclang_rt.asan-x86_64.so)" AQ_SANITIZER=1 \
    ASAN_OPTIONS="detect_leaks=0:strict_string_checks=1:check_initialization_order=1" \
    PYTHONPATH="$PWD/$build_dir/python" PYTHONDONTWRITEBYTECODE=1 AQ_BIN="$PWD/$build_dir/app/aquarelle" \
    AQ_SHARED="${AQ_SHARED:-$PWD/../shared}" AQ_SOURCE="$PWD" \
    /usr/bin/python3 -m pytest -q -p no:cacheprovider --basetemp="$PWD/$build_dir/pytest-tmp" tests/python
fi
