#!/usr/bin/env bash
# Before/after in the same minutes (docs/performance.md "How pairs are measured"): runs two
# aquarelle_bench binaries alternately — A, B, A, B, ... — on the benchmarks FILTER selects, so a
# shared machine's drift falls on both, and prints per build what it measured in every round.
#
# Usage: scripts/ab_bench.sh [--rounds N] [--min-time S] [--phases] BENCH_A BENCH_B FILTER
#   (default)   each round: FILTER with 3 repetitions; per build and benchmark, the round medians
#               of real time (ms) in round order, then their median
#   --phases    each round: FILTER once with AQ_RASTER_PROFILE=1 (raster benchmarks: every frame
#               prints the rasterizer's phases); per build and phase, the median and the 10th
#               percentile of the CPU ms over all frames of all rounds (the 10th percentile is the
#               steadier figure where other tenants load the host)
#   --rounds N  rounds (default 5); --min-time S: --benchmark_min_time per run (default 1)
# A typical pair: build the base commit in a worktree (git worktree add /tmp/base BASE; cmake
# --build /tmp/base/build --target aquarelle_bench), then
#   scripts/ab_bench.sh --phases /tmp/base/build/bench/aquarelle_bench build/bench/aquarelle_bench \
#     'BM_RasterFrame/model:2/w:1920/h:1080/threads:1/'
# Exit status: 0; 1 bad usage, a missing binary, or a filter that selects no benchmark.
set -euo pipefail
rounds=5; min_time=1; phases=0
while [ $# -gt 0 ]; do
  case "$1" in
    --rounds) rounds=${2:?--rounds needs a number}; shift 2 ;;
    --min-time) min_time=${2:?--min-time needs seconds}; shift 2 ;;
    --phases) phases=1; shift ;;
    -h|--help) sed -n 2,18p "$0"; exit 0 ;;
    -*) echo "ab_bench: unknown option $1 (see --help)" >&2; exit 1 ;;
    *) break ;;
  esac
done
[ $# -eq 3 ] || { echo "ab_bench: expected BENCH_A BENCH_B FILTER (see --help)" >&2; exit 1; }
a=$1; b=$2; filter=$3
[[ "$rounds" =~ ^[1-9][0-9]*$ ]] || { echo "ab_bench: --rounds must be a positive integer" >&2; exit 1; }
for x in "$a" "$b"; do [ -x "$x" ] || { echo "ab_bench: not an executable: $x" >&2; exit 1; }; done
[ -n "$("$a" --benchmark_list_tests --benchmark_filter="$filter" 2>/dev/null)" ] ||
  { echo "ab_bench: the filter selects no benchmark of $a: $filter" >&2; exit 1; }
echo "ab_bench: A=$a"
echo "ab_bench: B=$b"
echo "ab_bench: $rounds round(s) of '$filter', $(date -u '+%Y-%m-%d %H:%M UTC'), load $(cut -d' ' -f1-3 /proc/loadavg)"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for r in $(seq 1 "$rounds"); do
  for side in A B; do
    bin=$a; [ $side = B ] && bin=$b
    if [ "$phases" = 1 ]; then
      # Phase lines: "  raster NAME wall W ms  cpu C ms" (raster/raster_internal.h PhaseTimer).
      AQ_RASTER_PROFILE=1 "$bin" --benchmark_filter="$filter" --benchmark_min_time="$min_time" > /dev/null 2> "$tmp/err" ||
        { echo "ab_bench: $bin failed:" >&2; tail -5 "$tmp/err" >&2; exit 1; }
      awk -v s=$side '$1 == "raster" && $3 == "wall" { for (i = 1; i <= NF; ++i) if ($i == "cpu") print s, $2, $(i + 1) }' \
        "$tmp/err" >> "$tmp/phases"
    else
      # The console report (the CSV one refuses benchmarks with different counters): the
      # "NAME_median  TIME UNIT  CPU UNIT  ..." line of each benchmark.
      "$bin" --benchmark_filter="$filter" --benchmark_min_time="$min_time" --benchmark_repetitions=3 \
        --benchmark_report_aggregates_only=true --benchmark_color=false > "$tmp/out" 2> "$tmp/err" ||
        { echo "ab_bench: $bin failed:" >&2; tail -5 "$tmp/err" >&2; exit 1; }
      awk -v s=$side '$1 ~ /_median$/ { n = $1; sub(/_median$/, "", n)
          f = $3 == "ns" ? 1e-6 : $3 == "us" ? 1e-3 : $3 == "s" ? 1e3 : 1; print s, n, $2 * f }' "$tmp/out" \
        >> "$tmp/times"
    fi
  done
done
if [ "$phases" = 1 ]; then
  [ -s "$tmp/phases" ] || { echo "ab_bench: no phase lines (a raster benchmark is needed for --phases)" >&2; exit 1; }
  sort -k1,1 -k2,2 -k3,3g "$tmp/phases" | awk '
    { k = $1 " " $2; v[k, ++n[k]] = $3 }
    END { for (k in n) printf "%s cpu ms: median %.2f  p10 %.2f  (%d frames)\n", k, v[k, int((n[k] + 1) / 2)], v[k, int(n[k] / 10) + 1], n[k] }' | sort
else
  [ -s "$tmp/times" ] || { echo "ab_bench: no benchmark results" >&2; exit 1; }
  awk '{ k = $1 " " $2; r[k] = r[k] sprintf(" %.2f", $3) } END { for (k in r) print k, "ms per round:" r[k] }' "$tmp/times" |
    sort -k2,2 -k1,1 | awk '{ m = 0; for (i = 6; i <= NF; ++i) {  # insertion sort of the round values
        v = $i + 0; j = ++m; while (j > 1 && x[j - 1] > v) { x[j] = x[j - 1]; --j } x[j] = v }
      printf "%s  median %.2f\n", $0, x[int((m + 1) / 2)] }'
fi
echo "ab_bench: done $(date -u '+%H:%M UTC'), load $(cut -d' ' -f1-3 /proc/loadavg)"
