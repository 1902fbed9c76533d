#!/usr/bin/env bash
# Runs the whole test suite (docs/testing.md):
#   1. builds (if needed) and runs every CTest test of the normal build: unit, invariants,
#      determinism, bad input, the CLI end-to-end script and the GPU-equivalent OpenGL reference
#      checks (label `reference`);
#   2. the same unit and CLI tests built with clang, AddressSanitizer + UBSan (scripts/sanitize.sh,
#      build-fuzz/);
#   3. a smoke run of every benchmark (scripts/bench_suite.sh --smoke: each once, none may fail,
#      and the ratios of bench/ratios.json measured in the same run against the recorded ones),
#      and of the A/B tool scripts/ab_bench.sh;
#   4. a smoke run of every libFuzzer target on its seed corpus and regression inputs, from the same
#      instrumented build (scripts/fuzz.sh --smoke: a fixed number of inputs per target from a
#      fixed seed, the same on every run; $AQ_FUZZ_SECONDS caps each target, default 120).
# Usage: scripts/test.sh                 everything (what .ci/run runs)
#        scripts/test.sh --quick         the inner loop: build what changed, then the unit and CLI tests
#                                        of the normal build (no GL reference, goldens, sanitizers,
#                                        benchmarks or fuzzing; about 1.5 minutes on 2 cores)
#        scripts/test.sh CTEST_ARGS...   only step 1, with extra ctest args (e.g. -L reference, -R raster)
# AQ_SKIP_SANITIZERS=1 / AQ_SKIP_BENCH=1 / AQ_SKIP_FUZZ=1 skip steps 2 / 3 / 4 for a quick local run.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--quick" ]; then
  shift
  bash scripts/setup.sh --no-install
  exec ctest --test-dir build --output-on-failure --timeout 900 -j "$(nproc)" -L "unit|cli" "$@"
fi
bash scripts/setup.sh
start=$SECONDS
ctest --test-dir build --output-on-failure --timeout 900 -j "$(nproc)" "$@"
echo "test.sh: normal build tests in $((SECONDS - start)) s"
[ $# -gt 0 ] && exit 0
if [ "${AQ_SKIP_SANITIZERS:-0}" != 1 ]; then
  start=$SECONDS
  bash scripts/sanitize.sh
  echo "test.sh: sanitizer build and tests in $((SECONDS - start)) s"
fi
if [ "${AQ_SKIP_BENCH:-0}" != 1 ]; then
  start=$SECONDS
  bash scripts/bench_suite.sh --smoke build
  # The A/B tool (scripts/ab_bench.sh) on one small benchmark, both report forms: it must not rot.
  ab=(build/bench/aquarelle_bench build/bench/aquarelle_bench 'BM_RasterFrame/model:0/w:640/h:360/threads:1/')
  out=$(bash scripts/ab_bench.sh --rounds 1 --min-time 0.01 "${ab[@]}")
  grep -q '^B BM_RasterFrame/.* median [0-9]' <<< "$out" || { echo "test.sh: ab_bench.sh printed no median" >&2; exit 1; }
  out=$(bash scripts/ab_bench.sh --phases --rounds 1 --min-time 0.01 "${ab[@]}")
  grep -q '^B raster cpu ms: median [0-9]' <<< "$out" || { echo "test.sh: ab_bench.sh --phases printed no phase" >&2; exit 1; }
  echo "test.sh: benchmark smoke run in $((SECONDS - start)) s"
fi
if [ "${AQ_SKIP_FUZZ:-0}" != 1 ]; then
  start=$SECONDS
  bash scripts/fuzz.sh --smoke --seconds "${AQ_FUZZ_SECONDS:-120}"
  echo "test.sh: fuzz smoke run in $((SECONDS - start)) s"
fi
