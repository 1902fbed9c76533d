#!/usr/bin/env bash
# The benchmark suite (issue 14 item 5; docs/bench_suite.md): one command that runs the fixed matrix
# — pipelines (style x size x threads), the rasterizer (scene x size x threads), the LD06 frame
# (plant x threads), the GLSL pipelines on llvmpipe, and the CLI end to end — through
# aquarelle_bench, and writes OUT/suite.json (Google Benchmark's output), OUT/summary.json and
# OUT/suite.md (machine, load, compiler, commit, medians), and checks the ratios of bench/ratios.json
# measured in this run against the recorded ones.
#
# Usage: scripts/bench_suite.sh [--smoke] [--record] [BUILD=build] [OUT=BUILD/bench-suite]
#   (full)    the matrix, 5 repetitions each, medians; ~7 min on 2 cores
#   --smoke   what .ci/run runs: EVERY benchmark of aquarelle_bench once (none may rot unnoticed: a
#             benchmark reporting an error fails), then the ratio benchmarks with 3 short
#             repetitions and the ratio check; ~4 min on 2 cores
#   --record  store this run's ratios in bench/ratios.json (after an intended change)
# Exit status: 0; 4 a ratio dropped beyond its factor; 5 a benchmark failed; 1 other errors.
set -euo pipefail
cd "$(dirname "$0")/.."
smoke=0; record=()
while [ $# -gt 0 ]; do
  case "$1" in
    --smoke) smoke=1; shift ;;
    --record) record=(--record); shift ;;
    -h|--help) sed -n 2,16p "$0"; exit 0 ;;
    *) break ;;
  esac
done
build=${1:-build}
out=${2:-$build/bench-suite}
bench=$build/bench/aquarelle_bench
report=$build/bench/aquarelle_bench_report
[ -x "$bench" ] && [ -x "$report" ] || { echo "bench_suite: build first (cmake --build $build)" >&2; exit 1; }
mkdir -p "$out"
# llvmpipe on as many rasterizer threads as the C++ side it is compared with (threads:2), whatever
# the machine's core count, so "C++ vs llvmpipe" compares like with like (docs/bench_suite.md).
export LP_NUM_THREADS=${LP_NUM_THREADS:-2}
ratio_filter=$(grep -o '"\(slow\|fast\)": "[^"]*"' bench/ratios.json | sed 's/.*: "\(.*\)"/\1/; s#/\(real\|manual\)_time$##; s/[][().*+?^$|]/\\&/g' |
               sort -u | paste -sd'|')
matrix='^(pipeline/(wc16|wc17|wc18|mnpr)/(640x360|1920x1080)/fast/threads:[12]|gl/pipeline/|BM_RasterFrame/|BM_Ld06Frame/|cli/|serve/|style/run_on_gbuffer/)'
if [ "$smoke" = 1 ]; then
  echo "bench_suite: smoke run of every benchmark (one iteration each)"
  "$bench" --benchmark_min_time=0 --benchmark_out="$out/smoke_all.json" --benchmark_out_format=json >"$out/smoke_all.txt" 2>&1 ||
    { tail -20 "$out/smoke_all.txt" >&2; echo "bench_suite: aquarelle_bench failed" >&2; exit 5; }
  "$report" "$out/smoke_all.json" --markdown "$out/smoke_all.md"
  echo "bench_suite: ratio benchmarks, 3 repetitions"
  "$bench" --benchmark_filter="^($ratio_filter)/(real|manual)_time\$" --benchmark_min_time=0.2 --benchmark_repetitions=3 \
    --benchmark_report_aggregates_only=true --benchmark_out="$out/suite.json" --benchmark_out_format=json >"$out/suite.txt" 2>&1
else
  echo "bench_suite: the matrix, 5 repetitions each (medians)"
  "$bench" --benchmark_filter="$matrix" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
    --benchmark_out="$out/suite.json" --benchmark_out_format=json >"$out/suite.txt" 2>&1
fi
"$report" "$out/suite.json" --markdown "$out/suite.md" --summary "$out/summary.json" --ratios bench/ratios.json "${record[@]}"
echo "bench_suite: $out/suite.md, $out/summary.json"
