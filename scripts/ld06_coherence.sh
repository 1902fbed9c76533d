#!/usr/bin/env bash
# LD06's claim as a number (issue 12 item 4; docs/ld06.md "Frame-to-frame coherence"): in a camera
# orbit of the shared dense oak, how much the particle intensity maps change from one frame to the
# next with the binary depth test (popping) and with the blurred one (smooth visibility).
# For each variant it renders frames 0..N-1 of `--style ld06 --orbit DEG` (the oak scene file,
# 720 x 720 output, 520 x 520 maps), keeps the three particle maps of each frame (--targets), and
# compares consecutive frames with `aquarelle compare`: mean |change| and the fraction of values
# that jump by more than 0.5 (a particle appearing or vanishing at once). Prints one table.
# Usage: scripts/ld06_coherence.sh [build-dir] [frames=24] [degrees-per-frame=1]
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build}/app/aquarelle
frames=${2:-24}
deg=${3:-1}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
maps=(ld06.particles.dark ld06.particles.medium ld06.particles.bright)
printf "variant\tframes\tdeg/frame\tmean |change|\tvalues jumping > 0.5\n"
for variant in blurred binary; do
  # binary: the standard depth test — the depth map itself (the variant's default input) and no shift
  extra=()
  [ "$variant" = binary ] && extra=(--set particles.beta=0)
  for ((f = 0; f < frames; ++f)); do
    "$bin" render scenes/data/oak.json --style ld06 --variant "particles=$variant" "${extra[@]}" --width 720 --height 720 \
      --frame "$f" --orbit "$deg" --quiet --out "$tmp/frame.png" --targets "$tmp/t"
    for m in "${maps[@]}"; do cp "$tmp/t/$m.exr" "$tmp/${variant}_${f}_$m.exr"; done
    rm -rf "$tmp/t"
  done
  sum_mean=0; sum_jump=0; n=0
  for ((f = 1; f < frames; ++f)); do
    for m in "${maps[@]}"; do
      out=$("$bin" compare "$tmp/${variant}_$((f - 1))_$m.exr" "$tmp/${variant}_${f}_$m.exr" --threshold 0.5)
      mean=$(awk '/^mean_abs/ {print $2}' <<<"$out")
      jump=$(awk '/^over/ {print $3}' <<<"$out")
      sum_mean=$(awk -v a="$sum_mean" -v b="$mean" 'BEGIN {printf "%.9g", a + b}')
      sum_jump=$(awk -v a="$sum_jump" -v b="$jump" 'BEGIN {printf "%.9g", a + b}')
      n=$((n + 1))
    done
  done
  awk -v v="$variant" -v f="$frames" -v d="$deg" -v m="$sum_mean" -v j="$sum_jump" -v n="$n" \
    'BEGIN {printf "%s\t%d\t%s\t%.5f\t%.4f %%\n", v, f, d, m / n, j / n}'
done
