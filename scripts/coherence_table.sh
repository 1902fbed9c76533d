#!/usr/bin/env bash
# Temporal coherence per style for an orbit of Suzanne (issue 14 item 3; docs/coherence.md): renders
# frames 0..N-1 of scenes/data/suzanne.json with --orbit DEG and --targets for each style, runs
# `aquarelle coherence` on each sequence and prints one Markdown table of the totals.
# Usage: scripts/coherence_table.sh [build-dir] [frames=12] [deg-per-frame=2] [WxH=640x360] [styles]
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build}/app/aquarelle
frames=${2:-12}
deg=${3:-2}
size=${4:-640x360}
styles=${5:-none wc16 wc17 wc18 mnpr ld06}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/aq_coherence.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
echo "| style | static px % | static mean abs change | static px changing > 1/255 | warped % of object px | warp mean abs change | warped px changing > 1/255 |"
echo "|---|---|---|---|---|---|---|"
for s in $styles; do
  mkdir -p "$tmp/$s"
  "$bin" render scenes/data/suzanne.json --style "$s" --width "${size%x*}" --height "${size#*x}" --frames "0-$((frames - 1))" \
    --orbit "$deg" --quiet --targets "$tmp/$s/t" --out "$tmp/$s/f_####.png" 2>/dev/null
  "$bin" coherence "$tmp/$s" --targets "$tmp/$s/t" | awk -F'\t' -v s="$s" \
    '$1 == "total" {printf "| %s | %s | %s | %s %% | %s | %s | %s %% |\n", s, $2, $3, $4, $5, $6, $7}'
  rm -rf "$tmp/$s"
done
