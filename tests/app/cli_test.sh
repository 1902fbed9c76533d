#!/usr/bin/env bash
# tests/app/cli_test.sh — end-to-end checks of the aquarelle command line: help, exit codes,
# hostile input (nothing written, nothing replaced), determinism of the output bytes.
# Usage: cli_test.sh AQUARELLE_BINARY SOURCE_DIR SHARED_DIR WORK_DIR
set -u
bin=$1 src=$2 shared=$3 work=$4
rm -rf "$work"; mkdir -p "$work"
pass=0 fail=0
ok()  { pass=$((pass+1)); echo "ok   - $1"; }
bad() { fail=$((fail+1)); echo "FAIL - $1"; }
expect_rc() {  # expect_rc NAME WANT(0|nonzero|N) CMD...
  local name=$1 want=$2; shift 2
  "$@" >"$work/last.out" 2>"$work/last.err"; local rc=$?
  if { [ "$want" = nonzero ] && [ $rc -ne 0 ] && [ $rc -lt 128 ]; } || [ "$want" = "$rc" ]; then ok "$name (rc=$rc)"
  else bad "$name: rc=$rc, wanted $want"; sed 's/^/    /' "$work/last.err" | head -5; fi
}
small=(--width 96 --height 64 --quiet)

expect_rc "--help exits 0" 0 "$bin" --help
grep -q "render" "$work/last.out" && ok "--help lists render" || bad "--help lists render"
expect_rc "render --help exits 0" 0 "$bin" render --help
expect_rc "compare --help exits 0" 0 "$bin" compare --help
expect_rc "no command is a usage error" 2 "$bin"
expect_rc "unknown command is a usage error" 2 "$bin" frobnicate
expect_rc "render without --out" 2 "$bin" render procedural:swatches
expect_rc "unknown option" 2 "$bin" render procedural:swatches --out "$work/x.png" --bogus
expect_rc "absurd width refused" 2 "$bin" render procedural:swatches --width 100000 --out "$work/x.png"
expect_rc "absurd total size refused" nonzero "$bin" render procedural:swatches --width 16000 --height 16000 --out "$work/x.png"
expect_rc "non-numeric height" 2 "$bin" render procedural:swatches --height 12abc --out "$work/x.png"
expect_rc "ssaa out of range" 2 "$bin" render procedural:swatches --ssaa 9 --out "$work/x.png"
expect_rc "bad output extension" 2 "$bin" render procedural:swatches --out "$work/x.txt"
[ ! -e "$work/x.png" ] && ok "no output written by failed renders" || bad "a failed render wrote $work/x.png"

expect_rc "stages lists the registry" 0 "$bin" stages
grep -q "bleed" "$work/last.out" && ok "stages shows bleed" || bad "stages shows bleed"
expect_rc "styles lists presets" 0 "$bin" styles
grep -q "wc18" "$work/last.out" && ok "styles shows wc18" || bad "styles shows wc18"

# A good render, then hostile inputs aimed at the same --out: the good file must survive.
expect_rc "procedural render" 0 "$bin" render procedural:swatches "${small[@]}" --out "$work/good.png" --targets "$work/targets"
[ -s "$work/good.png" ] && ok "PNG written" || bad "PNG written"
ls "$work/targets"/color.exr "$work/targets"/depth.linear.exr >/dev/null 2>&1 && ok "G-buffer EXRs written" || bad "G-buffer EXRs written"
n_exr=$(ls "$work/targets"/*.exr 2>/dev/null | wc -l)
[ "$n_exr" -ge 12 ] && ok "intermediates written ($n_exr EXR)" || bad "intermediates written (only $n_exr EXR)"
good_sum=$(sha256sum "$work/good.png" | cut -d' ' -f1)
for f in "$shared"/assets/malformed/*.gltf; do
  expect_rc "malformed $(basename "$f") refused" nonzero "$bin" render "$f" "${small[@]}" --out "$work/good.png"
done
head -c 100 "$shared/assets/meshes/stanford_dragon/dragon_202k.glb" > "$work/truncated.glb"
expect_rc "truncated .glb refused" nonzero "$bin" render "$work/truncated.glb" "${small[@]}" --out "$work/good.png"
head -c 4096 /dev/urandom > "$work/garbage.glb"
expect_rc "garbage .glb refused" nonzero "$bin" render "$work/garbage.glb" "${small[@]}" --out "$work/good.png"
expect_rc "missing scene refused" nonzero "$bin" render "$work/nope.gltf" "${small[@]}" --out "$work/good.png"
expect_rc "unknown stage parameter refused" nonzero "$bin" render procedural:swatches "${small[@]}" --set bleed.nonsense=1 --out "$work/good.png"
expect_rc "malformed --set refused" nonzero "$bin" render procedural:swatches "${small[@]}" --set bleed.nonsense --out "$work/good.png"
expect_rc "unknown variant refused" nonzero "$bin" render procedural:swatches "${small[@]}" --variant bleed=nonsense --out "$work/good.png"
printf '{"steps": [ {"stage": "bleed", ' > "$work/broken.json"
expect_rc "malformed style JSON refused" nonzero "$bin" render procedural:swatches "${small[@]}" --style "$work/broken.json" --out "$work/good.png"
grep -q "broken.json" "$work/last.err" && ok "style error names the file" || bad "style error names the file"
[ "$(sha256sum "$work/good.png" | cut -d' ' -f1)" = "$good_sum" ] && ok "good image untouched by failures" || bad "good image was replaced"

# Same input, same bytes, whatever the thread count; a real model end to end.
suz="$src/scenes/data/suzanne.json"
expect_rc "suzanne threads=1" 0 "$bin" render "$suz" "${small[@]}" --threads 1 --out "$work/t1.png" --targets "$work/t1"
expect_rc "suzanne threads=2" 0 "$bin" render "$suz" "${small[@]}" --threads 2 --out "$work/t2.png" --targets "$work/t2"
cmp -s "$work/t1.png" "$work/t2.png" && ok "PNG identical for 1 and 2 threads" || bad "PNG differs between thread counts"
same=1; for e in "$work"/t1/*.exr; do cmp -s "$e" "$work/t2/$(basename "$e")" || { same=0; echo "    differs: $(basename "$e")"; }; done
[ $same = 1 ] && ok "every EXR identical for 1 and 2 threads" || bad "EXRs differ between thread counts"
expect_rc "animation frames 0-2" 0 "$bin" render "$suz" "${small[@]}" --frames 0-2 --out "$work/anim_####.png"
ls "$work"/anim_0000.png "$work"/anim_0002.png >/dev/null 2>&1 && ok "animation frames written" || bad "animation frames written"
cmp -s "$work/anim_0000.png" "$work/anim_0001.png" && bad "tremor: frames 0 and 1 identical" || ok "tremor: frames 0 and 1 differ"
expect_rc "sweep of a parameter" 0 "$bin" render procedural:swatches "${small[@]}" --sweep edge_darken.intensity=0:4:3 --out "$work/sweep_####.png"
ls "$work"/sweep_0000.png "$work"/sweep_0002.png >/dev/null 2>&1 && ok "sweep images written" || bad "sweep images written"
cmp -s "$work/sweep_0000.png" "$work/sweep_0002.png" && bad "sweep: intensity 0 and 4 identical" || ok "sweep: intensity 0 and 4 differ"
expect_rc "sweep out of range refused" 1 "$bin" render procedural:swatches "${small[@]}" --sweep edge_darken.intensity=0:99:3 --out "$work/badsweep_####.png"
ls "$work"/badsweep_* >/dev/null 2>&1 && bad "refused sweep wrote files" || ok "refused sweep wrote nothing"
expect_rc "sweep without ####" 2 "$bin" render procedural:swatches "${small[@]}" --sweep edge_darken.intensity=0:4:3 --out "$work/x.png"
expect_rc "compare identical" 0 "$bin" compare "$work/t1/color.exr" "$work/t2/color.exr" --diff "$work/diff.png"
grep -q "max_abs     0" "$work/last.out" && ok "compare reports zero error" || bad "compare reports zero error"
expect_rc "procedural render, other size" 0 "$bin" render procedural:swatches --width 48 --height 32 --quiet --out "$work/other.exr"
expect_rc "compare size mismatch" 1 "$bin" compare "$work/t1/color.exr" "$work/other.exr"

echo "cli: $pass passed, $fail failed"
[ $fail -eq 0 ]
