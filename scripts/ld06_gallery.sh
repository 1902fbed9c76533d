#!/usr/bin/env bash
# Renders the LD06 pictures of docs/gallery.md ("LD06 (Luft & Deussen 2006)") with the CLI, 360x360,
# --style ld06: the shared oak, ash and bush and procedural tree (scenes/data/tree.json) through the ld06 pipeline (depth,
# lighting and shadow maps, the layer washes, the three particle intensity maps, the glazed layers,
# the final), the binary vs blurred depth test for the particles on a close-up of the oak (LD06
# Fig. 9), a near and a far view of the bush (automatic level of detail, Fig. 11), and the same
# plants in WC18 for the side-by-side. Pictures go to docs/gallery/ld06/ (issue 12, item 3).
# Usage: scripts/ld06_gallery.sh [build-dir]
# The close-up and near/far scene files are written to a temporary folder (camera objects,
# docs/scenes.md); the models stay in ../shared (AQ_SHARED overrides), never copied here.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build}/app/aquarelle
out=docs/gallery/ld06
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"
rm -f "$out"/*.png
size=(--width 360 --height 360 --quiet)
plants=$(cd "${AQ_SHARED:-../shared}/assets/plants/ez-tree" && pwd)

# 1. Each plant through the ld06 pipeline: maps, layers, final; and its WC18 picture.
keep=(ld06.depth ld06.lighting ld06.shadow ld06.layer_id ld06.wash ld06.particles.dark ld06.particles.medium
      ld06.particles.bright ld06.strokes color.layers color.foliage color.final)
for scene in scenes/data/oak.json scenes/data/ash.json scenes/data/bush.json scenes/data/tree.json; do
  tag=$(basename "${scene#procedural:}" .json)
  echo "ld06 gallery: $tag"
  "$bin" render "$scene" "${size[@]}" --style ld06 --out "$tmp/$tag.png" --targets-png "$tmp/$tag"
  for t in "${keep[@]}"; do cp "$tmp/$tag/$t.png" "$out/${tag}_${t}.png"; done
  "$bin" render "$scene" "${size[@]}" --style wc18 --out "$out/${tag}_wc18.png"
done

# Scene file with an explicit camera looking along the automatic framing's direction
# (frame_bounds' view_dir (-0.35, -0.3, -1)) at TARGET from DISTANCE; the plant scene files' light.
# scene NAME GLB TARGET DISTANCE T RADIUS
scene() {
  local eye
  eye=$(awk -v t="$3" -v d="$4" 'BEGIN { split(t, c, ","); n = sqrt(0.35^2 + 0.3^2 + 1);
        printf "%.3f, %.3f, %.3f", c[1] + d*0.35/n, c[2] + d*0.3/n, c[3] + d/n }')
  cat > "$tmp/$1.json" <<EOF
{ "gltf": "$plants/$2",
  "camera": { "eye": [$eye], "target": [$3], "yfov_deg": 34 },
  "lights": [ { "direction": [-0.5, 0.8, 0.45], "color": [1.0, 0.97, 0.9], "intensity": 1.0 } ],
  "foliage": { "meshes": ["foliage"], "T": $5, "radius": $6 } }
EOF
}

# 2. LD06 Fig. 9: the standard (binary, against the depth map itself, no shift) vs the blurred depth
#    test for the particles, on a close-up of the oak's crown (the oak is ~105 units tall).
echo "ld06 gallery: fig9"
scene oak_close ez_oak_large_dense.glb "-10, 60, 10" 110 83.3 0.0755
for v in blurred binary; do
  extra=()
  [ "$v" = binary ] && extra=(--set particles.beta=0)
  "$bin" render "$tmp/oak_close.json" "${size[@]}" --style ld06 --variant particles=$v "${extra[@]}" \
    --out "$out/fig9_${v}_final.png" --targets-png "$tmp/fig9_$v"
  for t in ld06.particles.dark ld06.particles.medium; do cp "$tmp/fig9_$v/$t.png" "$out/fig9_${v}_$t.png"; done
done

# 3. LD06 Fig. 11: the bush (~31 units tall) near and far; sprites and blurs are sized in pixels.
echo "ld06 gallery: fig11"
for view in near:45 far:250; do
  name=${view%%:*}
  scene "bush_$name" ez_bush2.glb "0, 17, 1.7" "${view#*:}" 4.0 0.1
  "$bin" render "$tmp/bush_$name.json" "${size[@]}" --style ld06 --out "$out/fig11_${name}_final.png" \
    --targets-png "$tmp/fig11_$name"
  for t in ld06.particles.medium ld06.particles.wash; do cp "$tmp/fig11_$name/$t.png" "$out/fig11_${name}_$t.png"; done
done
# 4. Issue 46: bare plants at default options (no scene file: the technique, the fit and every
#    colour chosen by the preset), the shared ones and one seed of each generated kind. Their
#    "before" pictures (docs/gallery/ld06_before/, from the binary of c6b92be) are not re-rendered here:
#    AQ_LD06_BEFORE=OLD-aquarelle renders them again with another binary.
echo "ld06 gallery: bare plants"
shared=$(cd "${AQ_SHARED:-../shared}/assets/plants" && pwd)
bare=("ez_oak:$shared/ez-tree/ez_oak_large_dense.glb" "ez_ash:$shared/ez-tree/ez_ash_large.glb"
      "ez_bush:$shared/ez-tree/ez_bush2.glb" "birch:$shared/quaternius/BirchTree_4.glb"
      "common_tree:$shared/quaternius/CommonTree_1.glb" "tree:procedural:tree")
for k in broadleaf light conifer shrub grass; do bare+=("gen_$k:procedural:tree?kind=$k&seed=1"); done
for b in "${bare[@]}"; do
  "$bin" render "${b#*:}" "${size[@]}" --style ld06 --out "$out/bare_${b%%:*}.png" 2>/dev/null
done
if [ -n "${AQ_LD06_BEFORE:-}" ]; then
  mkdir -p docs/gallery/ld06_before
  for b in "${bare[@]:0:6}"; do
    "$AQ_LD06_BEFORE" render "${b#*:}" "${size[@]}" --style ld06 --out "docs/gallery/ld06_before/bare_${b%%:*}.png" 2>/dev/null
  done
  find docs/gallery/ld06_before -name '*.png.json' -delete
fi
# Each render writes its provenance manifest beside the picture (docs/provenance.md); the gallery
# keeps the pictures only (a manifest names this machine's paths and build).
find "$out" -name '*.png.json' -delete
echo "ld06 gallery: wrote $(find "$out" -name '*.png' | wc -l) images under $out/"
