#!/bin/bash
# fuzz/remote/run.sh — runs on the machine that received the bundle (fuzz/remote/make_bundle.sh),
# from the repository root: JOBS libFuzzer processes per target, all four targets at once, each
# for SECONDS, sharing one corpus per target (seeded from fuzz/corpus). Writes to $OUT:
#   <target>-<job>.log  libFuzzer's output with -print_final_stats
#   cpu-<target>.txt    the CPU time of that target's processes (bash `times`: user and system)
#   corpus-<target>.tgz the grown corpus; artifacts/ any crash, leak, timeout or OOM input
#   env.txt             machine and library resolution
# Usage: SECONDS_PER_JOB=540 JOBS=4 bash .fuzz/run.sh
set -u
F=$PWD/.fuzz
OUT=${OUT:-$PWD/fuzz-out}
S=${SECONDS_PER_JOB:-60}
J=${JOBS:-4}
mkdir -p "$OUT/artifacts"
LP=$F/lib
ldconfig -p | grep -q 'libstdc++.so.6 ' || LP=$LP:$F/libcxx
export LD_LIBRARY_PATH=$LP${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
export AQ_OIIO_MODULE=$F/lib/libaq_oiio.so   # the bundle's copy (core/oiio.h)
# The bundle's libraries are stripped and the machine has no llvm-symbolizer, so fuzz/lsan.supp's
# suppressions by function name cannot match there: its OpenImageIO leak is suppressed by module.
supp=$(mktemp)
{ cat fuzz/lsan.supp; echo "leak:libOpenImageIO_Util.so"; echo "leak:libOpenImageIO.so"; } >"$supp"
export LSAN_OPTIONS="suppressions=$supp"
{ date -u; uname -a; lscpu | head -20; nproc; free -g; ldd "$F/bin/fuzz_pipeline"; } >"$OUT/env.txt" 2>&1
work=$(mktemp -d)
for t in gltf scene_file pipeline image; do
    case $t in gltf|image) len=65536 ;; *) len=16384 ;; esac
    mkdir -p "$work/$t/corpus" "$work/$t/tmp"
    cp fuzz/corpus/$t/* "$work/$t/corpus/" 2>/dev/null
    dict=(); [ -f fuzz/dict/$t.dict ] && dict=(-dict=fuzz/dict/$t.dict)
    (
        for j in $(seq 1 "$J"); do
            TMPDIR=$work/$t/tmp "$F/bin/fuzz_$t" -rss_limit_mb=2048 -timeout=10 -max_len=$len -print_final_stats=1 \
                "${dict[@]}" -max_total_time="$S" -artifact_prefix="$OUT/artifacts/$t-$j-" "$work/$t/corpus" \
                >"$OUT/$t-$j.log" 2>&1 &
        done
        wait
        times >"$OUT/cpu-$t.txt"
    ) &
done
wait
for t in gltf scene_file pipeline image; do
    tar -czf "$OUT/corpus-$t.tgz" -C "$work/$t" corpus
    echo "$t: $(ls "$work/$t/corpus" | wc -l) corpus files; cpu: $(tail -1 "$OUT/cpu-$t.txt")"
    grep -h "^stat::number_of_executed_units" "$OUT/$t"-*.log | awk '{s += $2} END {print "  runs:", s}'
done
ls "$OUT/artifacts"
