#!/usr/bin/env bash
# Renders the pictures of docs/gallery.md with the CLI: G-buffer targets, each effect's
# contribution along the WC18 pipeline, and the WC16/WC17/WC18 pipelines side by side, for a real
# model (WaterBottle) and the procedural swatches. Usage: scripts/gallery.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build}/app/aquarelle
out=docs/gallery
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"
size=(--width 480 --height 270 --quiet)
keep=(color ctrl.pigment ctrl.substrate ctrl.edge ctrl.abstraction depth.linear normal object_id paper
      color.adjusted edges edges.blurred edges.extended color.density bleed color.bled color.darkened
      color.gaps_overlaps color.pigment color.distorted color.final)
for scene in procedural:swatches scenes/data/waterbottle.json; do
  tag=$(basename "${scene#procedural:}" .json)
  echo "gallery: $tag"
  "$bin" render "$scene" "${size[@]}" --style wc18 --out "$tmp/$tag.png" --targets-png "$tmp/$tag"
  for t in "${keep[@]}"; do cp "$tmp/$tag/$t.png" "$out/${tag}_${t}.png"; done
  for style in wc16 wc17 wc18; do
    "$bin" render "$scene" "${size[@]}" --style "$style" --out "$out/${tag}_style_${style}.png"
  done
done
echo "gallery: wrote $(ls "$out" | wc -l) images to $out/"
