#!/usr/bin/env bash
# tests/app/shard_test.sh — issue 14 item 4 (docs/shards.md): `render --shard I/N` on an animation
# and on a sweep, and `grid --shard I/N` on a grid, four shards run through GNU parallel, write
# exactly the files — names and bytes — of one unsharded run; bad --shard values are usage errors
# (exit 2) that write nothing.
# Usage: shard_test.sh AQUARELLE   (writes only in its own mktemp -d folder, removed on exit)
set -euo pipefail
bin=$1
dir=$(mktemp -d "${TMPDIR:-/tmp}/aq_shard_test.XXXXXX")
export AQUARELLE_CACHE_DIR="$dir/cache"  # never the user's cache (docs/cache.md)
trap 'rm -rf "$dir"' EXIT
fail() { echo "shard_test: FAIL: $*" >&2; exit 1; }
command -v parallel >/dev/null || fail "GNU parallel is not installed (scripts/setup.sh installs it)"
common=(procedural:swatches --width 96 --height 64 --quiet)
mkdir -p "$dir/one" "$dir/four" "$dir/sweep_one" "$dir/sweep_four"  # --out folders must exist

same() {  # same file names and bytes in two folders
  (cd "$1" && sha256sum -- *) >"$dir/a.sum"
  (cd "$2" && sha256sum -- *) >"$dir/b.sum"
  [ -s "$dir/a.sum" ] || fail "nothing rendered in $1"
  diff "$dir/a.sum" "$dir/b.sum" >&2 || fail "$3: the shards differ from one run"
}

# Animation: 9 frames (the hand tremor changes every frame), 4 shards of 3, 2, 2, 2 frames.
"$bin" render "${common[@]}" --frames 0-8 --out "$dir/one/f_####.png"
parallel --will-cite -j 4 "$bin" render "${common[@]}" --frames 0-8 --shard {}/4 --out "$dir/four/f_####.png" ::: 0 1 2 3
# 9 images and their 9 provenance manifests (docs/provenance.md), which do not depend on sharding.
[ "$(ls "$dir/one" | wc -l)" = 18 ] || fail "the unsharded animation wrote $(ls "$dir/one" | wc -l) files, not 18"
same "$dir/one" "$dir/four" "animation"
# One shard alone renders only its frames: k mod 4 == 1 of frames 0..8 -> 1 and 5.
mkdir -p "$dir/only1"
"$bin" render "${common[@]}" --frames 0-8 --shard 1/4 --out "$dir/only1/f_####.png"
[ "$(ls "$dir/only1" | tr '\n' ' ')" = "f_0001.png f_0001.png.json f_0005.png f_0005.png.json " ] || fail "shard 1/4 wrote: $(ls "$dir/only1" | tr '\n' ' ')"

# Sweep: 5 values of one parameter; 4 shards (one renders two values).
"$bin" render "${common[@]}" --style wc18 --sweep edge_darken.intensity=0:2:5 --out "$dir/sweep_one/s_####.png"
parallel --will-cite -j 4 "$bin" render "${common[@]}" --style wc18 --sweep edge_darken.intensity=0:2:5 --shard {}/4 \
  --out "$dir/sweep_four/s_####.png" ::: 0 1 2 3
same "$dir/sweep_one" "$dir/sweep_four" "sweep"

# Grid: 2 styles x 3 values = 6 combinations, 4 shards write exactly the cells of one run, and the
# sheet assembled from the shards' cells (--from-cells) has the bytes of the unsharded sheet.
axes=(--styles wc16,wc18 --set edge_darken.intensity=0.5,1,2)
"$bin" grid "${common[@]}" "${axes[@]}" --cells "$dir/grid_one" --out "$dir/grid_one.png"
parallel --will-cite -j 4 "$bin" grid "${common[@]}" "${axes[@]}" --shard {}/4 --cells "$dir/grid_four" ::: 0 1 2 3
[ "$(ls "$dir/grid_one"/*.exr | wc -l)" = 6 ] || fail "the unsharded grid wrote $(ls "$dir/grid_one"/*.exr | wc -l) cells, not 6"
[ "$(ls "$dir/grid_one"/*.exr.json | wc -l)" = 6 ] || fail "the unsharded grid wrote $(ls "$dir/grid_one"/*.exr.json | wc -l) cell sidecars, not 6"
same "$dir/grid_one" "$dir/grid_four" "grid"
"$bin" grid "${common[@]}" "${axes[@]}" --cells "$dir/grid_four" --from-cells --out "$dir/grid_four.png"
cmp "$dir/grid_one.png" "$dir/grid_four.png" || fail "the sheet assembled from shards differs from one run's"

# Usage errors: exit 2, nothing written.
mkdir -p "$dir/bad"
for bad in 4/4 -1/4 1/0 x/4 2; do
  set +e
  "$bin" render "${common[@]}" --frames 0-3 --shard "$bad" --out "$dir/bad/f_####.png" 2>/dev/null
  rc=$?
  set -e
  [ "$rc" = 2 ] || fail "--shard $bad exited $rc, expected 2"
done
set +e
"$bin" render "${common[@]}" --shard 0/2 --out "$dir/bad/single.png" 2>/dev/null
rc=$?
set -e
[ "$rc" = 2 ] || fail "--shard without --frames or --sweep exited $rc, expected 2"
for args in "--shard 0/2 --out $dir/bad/g.png" "--shard 0/2 --cells $dir/bad/c --out $dir/bad/g.png" "--shard 2/2 --cells $dir/bad/c"; do
  set +e
  # shellcheck disable=SC2086
  "$bin" grid "${common[@]}" --styles wc16,wc18 $args 2>/dev/null
  rc=$?
  set -e
  [ "$rc" = 2 ] || fail "grid $args exited $rc, expected 2"
done
[ -z "$(ls -A "$dir/bad" 2>/dev/null)" ] || fail "a refused run wrote files"
echo "shard_test: ok"
