#!/usr/bin/env bash
# tests/app/cli_test.sh — end-to-end checks of the aquarelle command line: help, exit codes,
# hostile input (nothing written, nothing replaced), determinism of the output bytes.
# Usage: cli_test.sh AQUARELLE_BINARY SOURCE_DIR SHARED_DIR OUTPUT_PARENT
# Everything is written inside a fresh folder OUTPUT_PARENT/cli.XXXXXX (mktemp), removed when every
# check passed and kept (path printed) when one failed.
set -u
bin=$1 src=$2 shared=$3
mkdir -p "$4"
work=$(mktemp -d "$4/cli.XXXXXX") || { echo "cannot create a work folder under $4"; exit 1; }
# The content cache (docs/cache.md) inside the work folder: repeated renders below hit it, and
# `reproduce` (which never reads it) checks that a render from the cache has the same bytes.
export AQUARELLE_CACHE_DIR="$work/cache"
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
expect_rc "unknown compression" 2 "$bin" render procedural:swatches --compression zip --out "$work/x.png"
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

# OpenImageIO is a module loaded on first use (core/oiio.h): a command that reads and writes no
# image through it does not load OpenImageIO's ~260 libraries (--help; a PNG render whose paper is
# a JPEG, core/jpeg.h); one that needs it loads it; a render that needs a missing module fails with
# a message naming it and writes nothing.
LD_DEBUG=files "$bin" --help >/dev/null 2>"$work/ld_help.txt"
LD_DEBUG=files "$bin" render procedural:swatches "${small[@]}" --out "$work/no_oiio.png" 2>"$work/ld_png.txt"
# A plant whose leaves are a palette PNG and whose bark a progressive JPEG (core/png.h, core/jpeg.h).
LD_DEBUG=files "$bin" render "$shared/assets/plants/ez-tree/ez_bush2.glb" --style ld06 "${small[@]}" \
  --out "$work/no_oiio_plant.png" 2>"$work/ld_plant.txt"
if [ "${AQ_CLI_LINKS_OIIO:-0}" = 1 ]; then
  # The sanitizer/fuzz build links OpenImageIO on purpose (core/CMakeLists.txt): not counted.
  echo "skip - --help, a PNG render and a plant do not load OpenImageIO (this build links it; checked in the normal build)"
else
  grep -q "file=libtbb" "$work/ld_help.txt" && ! grep -q "file=libOpenImageIO" "$work/ld_help.txt" \
    && ok "--help does not load OpenImageIO" || bad "--help does not load OpenImageIO"
  [ -s "$work/no_oiio.png" ] && grep -q "file=libtbb" "$work/ld_png.txt" && ! grep -q "file=libOpenImageIO" "$work/ld_png.txt" \
    && ok "a PNG render with a JPEG paper does not load OpenImageIO" || bad "a PNG render with a JPEG paper does not load OpenImageIO"
  [ -s "$work/no_oiio_plant.png" ] && grep -q "file=libtbb" "$work/ld_plant.txt" && ! grep -q "file=libOpenImageIO" "$work/ld_plant.txt" \
    && ok "an LD06 plant with palette PNG leaves does not load OpenImageIO" || bad "an LD06 plant with palette PNG leaves does not load OpenImageIO"
fi
[ -s "$work/no_oiio.png" ] && ok "PNG render with LD_DEBUG" || bad "PNG render with LD_DEBUG"
LD_DEBUG=files "$bin" compare "$work/good.png" "$work/good.png" >/dev/null 2>"$work/ld_compare.txt"
grep -q "file=libOpenImageIO" "$work/ld_compare.txt" && ok "compare loads OpenImageIO" || bad "compare loads OpenImageIO"
expect_rc "EXR render without the OpenImageIO module fails cleanly" 1 env AQ_OIIO_MODULE="$work/no_such_module.so" \
  "$bin" render procedural:swatches "${small[@]}" --out "$work/no_module.exr"
grep -q "OpenImageIO module.*no_such_module.so" "$work/last.err" && ok "the error names the module" || bad "the error names the module"
[ ! -e "$work/no_module.exr" ] && ok "nothing written without the module" || bad "an EXR was written without the module"
expect_rc "PNG render without the OpenImageIO module" 0 env AQ_OIIO_MODULE="$work/no_such_module.so" \
  "$bin" render procedural:swatches "${small[@]}" --out "$work/no_module.png"
cmp -s "$work/no_module.png" "$work/no_oiio.png" && ok "the same PNG with and without the module" || bad "the same PNG with and without the module"

# Issue 8 regressions: hostile files, full disks, inputs as outputs, stale temporaries.
# Each reader refuses FIFOs and devices at once (timeout guards a hang: rc 124 would fail "1").
mkfifo "$work/paper.fifo"
sed "s#paper/mnpr/rough_default_2k.jpg#$work/paper.fifo#" "$src/stylize/presets/wc18.json" > "$work/fifo_style.json"
expect_rc "paper naming a FIFO refused without hanging" 1 timeout 30 "$bin" render procedural:swatches "${small[@]}" --style "$work/fifo_style.json" --out "$work/good.png"
grep -q "FIFO" "$work/last.err" && ok "FIFO error says FIFO" || bad "FIFO error says FIFO"
expect_rc "--style /dev/zero refused without hanging" 1 timeout 30 "$bin" render procedural:swatches "${small[@]}" --style /dev/zero --out "$work/good.png"
grep -q "character device" "$work/last.err" && ok "/dev/zero error names the device" || bad "/dev/zero error names the device"
printf '{"name":"x","paper":{"file":"p.png","scale":1e400},"steps":[]}' > "$work/overflow.json"
expect_rc "number 1e400 refused" 1 "$bin" render procedural:swatches "${small[@]}" --style "$work/overflow.json" --out "$work/good.png"
grep "overflow.json" "$work/last.err" | grep -q "paper.scale" && ok "1e400 error names file and key" || bad "1e400 error names file and key"
expect_rc "compare with a FIFO refused" 1 timeout 30 "$bin" compare "$work/paper.fifo" "$work/good.png"
[ "$(sha256sum "$work/good.png" | cut -d' ' -f1)" = "$good_sum" ] && ok "good image untouched by hostile files" || bad "good image was replaced"

# A full file system, simulated by a file-size limit (writes fail with EFBIG): every format and
# --targets-png keep the old file, exit 1, name the file, leave no temporary.
mkdir -p "$work/full"
for ext in png exr jpg tif; do
  "$bin" render procedural:swatches --width 8 --height 8 --quiet --out "$work/full/keep.$ext" >/dev/null 2>&1
  before=$(sha256sum "$work/full/keep.$ext" | cut -d' ' -f1)
  expect_rc "full disk ($ext) fails" 1 bash -c "ulimit -f 1; exec \"\$0\" \"\$@\"" "$bin" render procedural:swatches --width 256 --height 256 --quiet --out "$work/full/keep.$ext"
  grep -q "keep.$ext" "$work/last.err" && ok "full disk ($ext): message names the file" || bad "full disk ($ext): message names the file"
  [ "$(sha256sum "$work/full/keep.$ext" | cut -d' ' -f1)" = "$before" ] && ok "full disk ($ext): old file kept" || bad "full disk ($ext): old file replaced"
done
expect_rc "full disk (--targets-png) fails" 1 bash -c "ulimit -f 1; exec \"\$0\" \"\$@\"" "$bin" render procedural:swatches --width 256 --height 256 --quiet --targets-png "$work/full/tp" --out "$work/full/tp.png"
empty=$(find "$work/full/tp" -type f -size 0 2>/dev/null | wc -l)
[ "$empty" = 0 ] && ok "full disk: no 0-byte target PNG" || bad "full disk: $empty 0-byte target PNGs"
left=$(find "$work/full" -name '.aqtmp*' | wc -l)
[ "$left" = 0 ] && ok "full disk: no temporaries left" || bad "full disk: $left temporaries left"

# An output naming one of the model's own files is refused; the model's texture is untouched.
mkdir -p "$work/boxtex"
cp "$shared"/assets/gltf/BoxTextured/BoxTextured.gltf "$shared"/assets/gltf/BoxTextured/BoxTextured0.bin "$shared"/assets/gltf/BoxTextured/CesiumLogoFlat.png "$work/boxtex/"
tex_sum=$(sha256sum "$work/boxtex/CesiumLogoFlat.png" | cut -d' ' -f1)
expect_rc "--out naming the model's texture refused" 1 "$bin" render "$work/boxtex/BoxTextured.gltf" "${small[@]}" --out "$work/boxtex/CesiumLogoFlat.png"
[ "$(sha256sum "$work/boxtex/CesiumLogoFlat.png" | cut -d' ' -f1)" = "$tex_sum" ] && ok "input texture untouched" || bad "input texture overwritten"
expect_rc "--out naming the model itself refused" 2 "$bin" render "$work/boxtex/BoxTextured.gltf" "${small[@]}" --out "$work/boxtex/BoxTextured.gltf"

# Path policy: a buffer URI leaving the model's folder ('..', percent-encoded, symlink) is refused
# unless --allow-outside-files; the working-folder fallback is refused too.
mkdir -p "$work/esc/model"
cp "$shared"/assets/gltf/BoxTextured/BoxTextured0.bin "$work/esc/outside.bin"
for uri in "../outside.bin" "%2e%2e/outside.bin" "link.bin"; do
  sed "s#\"BoxTextured0.bin\"#\"$uri\"#; s#\"CesiumLogoFlat.png\"#\"missing.png\"#" "$shared"/assets/gltf/BoxTextured/BoxTextured.gltf > "$work/esc/model/m.gltf"
  ln -sf ../outside.bin "$work/esc/model/link.bin"
  expect_rc "buffer URI '$uri' outside the model refused" 1 "$bin" render "$work/esc/model/m.gltf" "${small[@]}" --out "$work/esc/x.png"
  grep -q "outside the model's folder" "$work/last.err" && ok "refusal for '$uri' explains the policy" || bad "refusal for '$uri' explains the policy"
  expect_rc "buffer URI '$uri' allowed with --allow-outside-files" 0 "$bin" render "$work/esc/model/m.gltf" "${small[@]}" --allow-outside-files --out "$work/esc/x.png"
done
sed "s#\"BoxTextured0.bin\"#\"cwd_only.bin\"#" "$shared"/assets/gltf/BoxTextured/BoxTextured.gltf > "$work/esc/model/cwd.gltf"
cp "$work/esc/outside.bin" "$work/esc/cwd_only.bin"
expect_rc "working-folder fallback refused" 1 bash -c "cd \"$work/esc\" && exec \"\$0\" \"\$@\"" "$bin" render model/cwd.gltf "${small[@]}" --out x.png

# A valid model in large units renders (the automatic depth range is not a --set).
python3 - "$shared/assets/gltf/Box/glTF-Embedded/Box.gltf" "$work/bigbox.gltf" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
for n in j["nodes"]:
    n.pop("matrix", None)
j["nodes"][0]["scale"] = [1e6, 1e6, 1e6]
json.dump(j, open(sys.argv[2], "w"))
PY
expect_rc "box scaled by 1e6 renders" 0 "$bin" render "$work/bigbox.gltf" "${small[@]}" --out "$work/bigbox.png"

# Temporaries of a killed render are recognisable and removed by the next run into the folder.
mkdir -p "$work/kill"
"$bin" render procedural:swatches --width 64 --height 64 --quiet --out "$work/kill/k.png" >/dev/null 2>&1
kill_sum=$(sha256sum "$work/kill/k.png" | cut -d' ' -f1)
# SIGKILL at the exact moments of writing, stopped there by gdb (a breakpoint on the system call,
# then `kill`): before the new image's temporary gets a name (linkat), before it is renamed into
# place (rename #1), and after it, before its manifest is renamed (rename #2). Each breakpoint must
# be hit (asserted: the check checks); after each kill the image is the old one or the whole new one,
# and a manifest beside it, if any, describes the image beside it (docs/limits.md "Writing files").
kill_args=("$src/scenes/data/suzanne.json" --width 320 --height 180 --quiet --threads 2)
"$bin" render "${kill_args[@]}" --out "$work/kill/full.png" >/dev/null 2>&1
full_sum=$(sha256sum "$work/kill/full.png" | cut -d' ' -f1)
rm -f "$work/kill/full.png" "$work/kill/full.png.json"
if command -v gdb >/dev/null; then
  for stop in "linkat 0" "rename 0" "rename 1"; do
    set -- $stop
    "$bin" render procedural:swatches --width 64 --height 64 --quiet --out "$work/kill/k.png" >/dev/null 2>&1
    kill_sum=$(sha256sum "$work/kill/k.png" | cut -d' ' -f1)
    log=$(timeout 120 gdb -batch -nx -ex 'set breakpoint pending on' -ex "break $1" -ex "ignore 1 $2" -ex run -ex kill \
      --args "$bin" render "${kill_args[@]}" --out "$work/kill/k.png" 2>&1 || true)
    grep -Eq "Breakpoint 1(\.[0-9]+)?, .*$1" <<<"$log" || { bad "SIGKILL at $1 #$(( $2 + 1 )): the breakpoint was not hit"; continue; }
    now_sum=$(sha256sum "$work/kill/k.png" | cut -d' ' -f1)
    { [ "$now_sum" = "$kill_sum" ] || [ "$now_sum" = "$full_sum" ]; } || bad "SIGKILL at $1 #$(( $2 + 1 )): the image is neither the old nor the new one"
    if [ -f "$work/kill/k.png.json" ]; then
      python3 -c 'import json,sys; m=json.load(open(sys.argv[1])); sys.exit(0 if [o["sha256"] for o in m["outputs"] if o["kind"]=="out"]==[sys.argv[2]] else 1)' \
        "$work/kill/k.png.json" "$now_sum" || bad "SIGKILL at $1 #$(( $2 + 1 )): the manifest beside the image describes another image"
    fi
    ok "SIGKILL at $1 #$(( $2 + 1 )) (stopped there by gdb): the image is the old or the whole new one, no manifest describes another"
  done
else
  bad "gdb is not installed (scripts/setup.sh installs it): the SIGKILL checks cannot stop the render mid-write"
fi
true & dead=$!; wait $dead  # a PID that is no longer alive
echo half > "$work/kill/.aqtmp.$dead.0.k.png"
expect_rc "render after a killed one" 0 "$bin" render procedural:swatches --width 32 --height 32 --quiet --out "$work/kill/k2.png"
left=$(find "$work/kill" -name '.aqtmp*' | wc -l)
[ "$left" = 0 ] && ok "stale temporaries removed by the next run" || bad "$left stale temporaries left"

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
expect_rc "one frame: --frames N" 0 "$bin" render "$suz" "${small[@]}" --frames 2 --out "$work/one_####.png"
cmp -s "$work/anim_0002.png" "$work/one_0002.png" && ok "--frames 2 writes frame 2 of 0-2" || bad "--frames 2 writes frame 2 of 0-2"
expect_rc "--frames with a leading dash" 2 "$bin" render "$suz" "${small[@]}" --frames -3 --out "$work/one_####.png"
expect_rc "--frames 3-1 refused" 2 "$bin" render "$suz" "${small[@]}" --frames 3-1 --out "$work/one_####.png"
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

# The content cache (docs/cache.md): a first render fills it, a second reads it; both, and a
# render without it, write the same bytes, and reproduce (which never reads it) agrees.
cdir="$work/cache_check"
bottle="$shared/assets/gltf/WaterBottle/glTF/WaterBottle.gltf"
csmall=(--width 160 --height 96)
expect_rc "cache: a first render fills it" 0 "$bin" render "$bottle" "${csmall[@]}" --cache-dir "$cdir" --out "$work/c1.png"
ls "$cdir"/scene-*.aqc >/dev/null 2>&1 && ok "cache: the scene's entry written" || bad "cache: no scene entry in $cdir"
expect_rc "cache: a second render reads it" 0 "$bin" render "$bottle" "${csmall[@]}" --cache-dir "$cdir" --threads 1 --out "$work/c2.png"
grep -q "from the cache" "$work/last.err" && ok "cache: the second render says it read the cache" || bad "cache: the second render did not read the cache"
expect_rc "cache: --no-cache" 0 "$bin" render "$bottle" "${csmall[@]}" --no-cache --out "$work/c0.png"
cmp -s "$work/c0.png" "$work/c1.png" && cmp -s "$work/c0.png" "$work/c2.png" && ok "cache: the same PNG bytes without, filling and reading it" \
  || bad "cache: PNG bytes differ with the cache"
expect_rc "cache: reproduce of a render from the cache" 0 "$bin" reproduce "$work/c2.png.json" --quiet
grep -q "identical" "$work/last.out" && ok "cache: reproduce says identical" || bad "cache: reproduce does not say identical"
entry=$(ls "$cdir"/scene-*.aqc | head -1)
printf 'X' | dd of="$entry" bs=1 seek=4000 conv=notrunc status=none
expect_rc "cache: a damaged entry" 0 "$bin" render "$bottle" "${csmall[@]}" --cache-dir "$cdir" --out "$work/c3.png"
grep -q "damaged" "$work/last.err" && ok "cache: the damaged entry is reported" || bad "cache: the damaged entry is not reported"
cmp -s "$work/c0.png" "$work/c3.png" && ok "cache: a damaged entry changes no byte" || bad "cache: a damaged entry changed the image"
bush="$shared/assets/plants/ez-tree/ez_bush2.glb"
expect_rc "cache: LD06 fills it" 0 "$bin" render "$bush" --style ld06 "${csmall[@]}" --cache-dir "$cdir" --out "$work/b1.png" --quiet
ls "$cdir"/foliage-*.aqc >/dev/null 2>&1 && ok "cache: the foliage's entry written" || bad "cache: no foliage entry"
expect_rc "cache: LD06 reads it" 0 "$bin" render "$bush" --style ld06 "${csmall[@]}" --cache-dir "$cdir" --out "$work/b2.png" --quiet
expect_rc "cache: LD06 without it" 0 "$bin" render "$bush" --style ld06 "${csmall[@]}" --no-cache --out "$work/b0.png" --quiet
cmp -s "$work/b0.png" "$work/b1.png" && cmp -s "$work/b0.png" "$work/b2.png" && ok "cache: the same LD06 bytes with and without it" \
  || bad "cache: LD06 bytes differ with the cache"
expect_rc "cache: a folder that cannot be made still renders" 0 "$bin" render "$bottle" "${csmall[@]}" --cache-dir "$work/c0.png/sub" --out "$work/c4.png"
grep -q "not cached" "$work/last.err" && ok "cache: says why nothing was cached" || bad "cache: no reason given for not caching"
cmp -s "$work/c0.png" "$work/c4.png" && ok "cache: same bytes without a usable folder" || bad "cache: bytes differ without a usable folder"
AQUARELLE_CACHE_MAX_MB=lots expect_rc "cache: a malformed AQUARELLE_CACHE_MAX_MB" 1 "$bin" render "$bottle" "${csmall[@]}" --out "$work/c5.png"
grep -q "AQUARELLE_CACHE_MAX_MB" "$work/last.err" && ok "cache: names the malformed variable" || bad "cache: does not name the malformed variable"

# --view with a pan and --scene-set: what the live page sets, written into the manifest and
# rendered again by reproduce; scene-values lists what --scene-set may edit.
oak="$src/scenes/data/oak.json"
expect_rc "scene-values lists a scene file's values" 0 "$bin" scene-values "$oak"
grep -q "^/layers/1/color	color	" "$work/last.out" && ok "scene-values: the crown's colour is a colour" || bad "scene-values: no /layers/1/color colour"
expect_rc "scene-values of a bare model" 1 "$bin" scene-values "$bottle"
expect_rc "render with --scene-set and a panned --view" 0 "$bin" render "$oak" "${small[@]}" --no-cache --view 20,10,1.2,0.3,-0.2 \
  --scene-set '/layers/1/color=[0.8,0.3,0.2]' --scene-set /foliage/T=70 --out "$work/edit.png"
expect_rc "the same without the edits" 0 "$bin" render "$oak" "${small[@]}" --no-cache --view 20,10,1.2,0.3,-0.2 --out "$work/noedit.png"
cmp -s "$work/edit.png" "$work/noedit.png" && bad "--scene-set changed nothing" || ok "--scene-set changes the image"
grep -q '"/layers/1/color=\[0.8,0.3,0.2\]"' "$work/edit.png.json" && ok "the manifest records the edits" || bad "the manifest lacks scene_set"
expect_rc "reproduce of an edited, panned render" 0 "$bin" reproduce "$work/edit.png.json" --quiet
grep -q "identical" "$work/last.out" && ok "reproduce of --scene-set and the pan says identical" || bad "reproduce of --scene-set is not identical"
expect_rc "--scene-set of a value the file lacks" 1 "$bin" render "$oak" "${small[@]}" --scene-set /gltf=1 --out "$work/x.png"
grep -q "not an editable value" "$work/last.err" && ok "--scene-set names a value it cannot edit" || bad "--scene-set's error is unclear"
expect_rc "--scene-set without a pointer" 2 "$bin" render "$oak" "${small[@]}" --scene-set foliage=1 --out "$work/x.png"
expect_rc "--scene-set on a bare model" 1 "$bin" render "$bottle" "${small[@]}" --scene-set /foliage/T=1 --out "$work/x.png"
expect_rc "--view with four values" 2 "$bin" render "$oak" "${small[@]}" --view 1,2,1,0 --out "$work/x.png"
expect_rc "--view pan out of range" 2 "$bin" render "$oak" "${small[@]}" --view 1,2,1,0,99 --out "$work/x.png"

echo "cli: $pass passed, $fail failed"
if [ $fail -eq 0 ]; then rm -rf "$work"; else echo "cli: outputs kept in $work"; fi
[ $fail -eq 0 ]
