#!/usr/bin/env bash
# Renders the pictures of docs/gallery.md with the CLI: G-buffer targets, each effect's
# contribution along the WC18 pipeline, and the WC16/WC17/WC18 pipelines side by side, for a real
# model (WaterBottle) and the procedural swatches; then every shared glTF model bare, default
# options, 640x480, in --style none, wc16, wc17, wc18 (docs/gallery.md "Bare models", docs/look.md).
# Usage: scripts/gallery.sh [build-dir]
# BEFORE_BIN=path/to/old/aquarelle BEFORE_PRESETS=dir also renders the "before" column of the bare
# models (three of them) with an older binary and its presets (AQ_PRESET_DIR) into docs/gallery/bare_before/.
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
# Bare models: default options, 640x480 (issue 10). Assets stay in ../shared (never copied here).
shared=${AQ_SHARED:-../shared}/assets
bare_models=(gltf/Avocado/glTF/Avocado.gltf gltf/Box/glTF-Embedded/Box.gltf gltf/BoxTextured/BoxTextured.gltf
             gltf/BoxVertexColors_CC0/glTF-Embedded/BoxVertexColors.gltf gltf/Cube/glTF/Cube.gltf gltf/Fox/glTF/Fox.gltf
             gltf/OrientationTest/glTF/OrientationTest.gltf gltf/Suzanne/glTF/Suzanne.gltf
             gltf/Triangle/glTF/Triangle.gltf gltf/WaterBottle/glTF/WaterBottle.gltf
             plants/quaternius/BirchTree_4.glb plants/quaternius/CommonTree_1.glb)
bare=(--width 640 --height 480 --quiet)
mkdir -p "$out/bare"
for m in "${bare_models[@]}"; do
  [ -f "$shared/$m" ] || { echo "gallery: $shared/$m missing, skipped" >&2; continue; }
  tag=$(basename "${m%.*}")
  echo "gallery: bare $tag"
  for style in none wc16 wc17 wc18; do
    "$bin" render "$shared/$m" "${bare[@]}" --style "$style" --out "$out/bare/${tag}_${style}.png" 2>/dev/null
  done
  # "before" pictures for three representative models only (flat colours, photoscan, textured):
  # the textured paper makes each 640x480 PNG ~0.4 MB.
  if [ -n "${BEFORE_BIN:-}" ] && [[ " BirchTree_4 Avocado Fox " == *" $tag "* ]]; then
    mkdir -p "$out/bare_before"
    for style in wc16 wc17 wc18; do
      AQ_PRESET_DIR=${BEFORE_PRESETS:?set BEFORE_PRESETS to the old presets} \
        "$BEFORE_BIN" render "$shared/$m" "${bare[@]}" --style "$style" --out "$out/bare_before/${tag}_${style}.png" 2>/dev/null
    done
  fi
done
# Plants in the WC styles (issue 46 items 5, 8): the shared ez-tree plants and two generated ones,
# default options, 640x480. PLANTS_BEFORE_PRESETS=dir also renders the "before" row of the
# generated conifer, the oak and the Fox with this binary and older presets (the issue-46 look
# changes are preset values and a stage parameter whose default is the old behaviour, so the
# current binary with the presets of 801532b gives that commit's bytes) into docs/gallery/wc_before/.
plants=(plants/ez-tree/ez_oak_large_dense.glb plants/ez-tree/ez_ash_large.glb plants/ez-tree/ez_bush2.glb
        "procedural:tree?kind=conifer&seed=1" "procedural:tree?kind=grass&seed=1")
mkdir -p "$out/wc_plants"
for m in "${plants[@]}"; do
  if [[ $m == procedural:* ]]; then src=$m; tag=generated_$(sed 's/.*kind=\([a-z]*\).*/\1/' <<<"$m");
  else src=$shared/$m; tag=$(basename "${m%.*}"); [ -f "$src" ] || { echo "gallery: $src missing, skipped" >&2; continue; }; fi
  echo "gallery: wc plants $tag"
  for style in none wc16 wc17 wc18; do
    "$bin" render "$src" "${bare[@]}" --style "$style" --out "$out/wc_plants/${tag}_${style}.png" 2>/dev/null
  done
done
if [ -n "${PLANTS_BEFORE_PRESETS:-}" ]; then
  mkdir -p "$out/wc_before"
  for m in "procedural:tree?kind=conifer&seed=1" "$shared/plants/ez-tree/ez_oak_large_dense.glb" "$shared/gltf/Fox/glTF/Fox.gltf"; do
    case $m in procedural:*) tag=generated_conifer ;; *) tag=$(basename "${m%.*}") ;; esac
    for style in wc16 wc17 wc18; do
      AQ_PRESET_DIR=$PLANTS_BEFORE_PRESETS "$bin" render "$m" "${bare[@]}" --style "$style" --out "$out/wc_before/${tag}_${style}.png" 2>/dev/null
    done
  done
fi
# Each render writes its provenance manifest beside the picture (docs/provenance.md); the gallery
# keeps the pictures only (a manifest names this machine's paths and build).
find "$out" -name '*.png.json' -delete
echo "gallery: wrote $(find "$out" -name '*.png' | wc -l) images under $out/"
