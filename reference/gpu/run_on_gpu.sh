#!/bin/bash
# reference/gpu/run_on_gpu.sh — runs the bundled reference_test (reference/gpu/make_bundle.sh) on
# a machine with a GPU driver but without our Debian libraries, and writes to $OUT:
#   env.txt        machine, nvidia-smi, GLVND vendor files, NVIDIA libraries
#   platform.txt   GlHarness.ContextIsOpenGL45Core under AQ_GL_PLATFORM=surfaceless and =device
#   log.txt        the full reference_test run (every comparison's metrics), CI=1 so no skip
#   reference_test.xml, reference_stage_errors.tsv, test-output.tgz (failure images, if any)
#   log2.txt, reference_stage_errors_exact_bilinear.tsv  a second run, AQ_REFERENCE_EXACT_BILINEAR=1
# Usage (repository root, with the bundle in .gpu and GLVND .debs in .gl): bash .gpu/run.sh
set -u
G=$PWD/.gpu
OUT=${OUT:-$PWD/gpu-out}
mkdir -p "$OUT"
if ls .gl/*.deb >/dev/null 2>&1; then
    for f in .gl/*.deb; do dpkg -x "$f" /; done
    ldconfig
fi
E=$OUT/env.txt
{
    date -u; uname -a; head -4 /etc/os-release
    echo "== nvidia-smi"; nvidia-smi
    nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm,clocks.max.mem --format=csv
    echo "== GLVND EGL vendor files"
    ls -la /usr/share/glvnd/egl_vendor.d /etc/glvnd/egl_vendor.d /usr/local/nvidia/share/glvnd/egl_vendor.d
    echo "== ldconfig (EGL/GL/nvidia)"; ldconfig -p | grep -iE 'libEGL|libGL|libOpenGL|nvidia'
    echo "== CPU"; lscpu | head -20
} >"$E" 2>&1
if ! compgen -G "/usr/share/glvnd/egl_vendor.d/*.json" >/dev/null && ! compgen -G "/etc/glvnd/egl_vendor.d/*.json" >/dev/null; then
    export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
    echo "no system EGL vendor file: __EGL_VENDOR_LIBRARY_FILENAMES=$__EGL_VENDOR_LIBRARY_FILENAMES" >>"$E"
fi
LP=$G/lib
ldconfig -p | grep -q 'libstdc++.so.6 ' || LP=$LP:$G/libcxx
export LD_LIBRARY_PATH=$LP:/usr/local/nvidia/lib64:/usr/local/nvidia/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
export AQ_OIIO_MODULE=$G/lib/libaq_oiio.so   # the bundle's copy (core/oiio.h)
echo "LD_LIBRARY_PATH=$LD_LIBRARY_PATH" >>"$E"
# The binary's compiled-in paths: source tree (scene files, test output) and ../shared beside it.
SRC=$(cat "$G/src_path")
mkdir -p "$(dirname "$SRC")"
[ -e "$SRC" ] || ln -s "$G/src" "$SRC"
[ -e "$(dirname "$SRC")/shared" ] || ln -s "$G/shared" "$(dirname "$SRC")/shared"
export AQ_SHARED=$G/shared AQ_REFERENCE_SHADER_DIR=$SRC/reference/shaders AQ_PRESET_DIR=$SRC/stylize/presets
export AQ_KEEP_TEST_OUTPUT=1 CI=1
ldd "$G/bin/reference_test" >>"$E" 2>&1
T=$G/bin/reference_test
{
    for p in surfaceless device; do
        echo "== AQ_GL_PLATFORM=$p"
        AQ_GL_PLATFORM=$p timeout 45 "$T" --gtest_filter=GlHarness.ContextIsOpenGL45Core 2>&1
        echo "rc=$?"
    done
} >"$OUT/platform.txt" 2>&1
set -o pipefail
TO=$(cat "$G/test_output_path" 2>/dev/null || echo "$SRC/build-gpu/test-output")
rm -rf "$TO"
SECONDS=0
timeout 200 "$T" --gtest_output=xml:"$OUT/reference_test.xml" 2>&1 | tee "$OUT/log.txt"
rc=$?
echo "reference_test rc=$rc wall=${SECONDS}s" | tee -a "$OUT/log.txt"
find "$TO" -name reference_stage_errors.tsv | head -1 | xargs -r -I{} cp {} "$OUT/reference_stage_errors.tsv"
[ -d "$TO" ] && tar czf "$OUT/test-output.tgz" -C "$(dirname "$TO")" test-output
# A second run with exact-weight bilinear taps in the twins (common.glsl, AQ_EXACT_BILINEAR):
# separates the texture unit's filtering from the shader arithmetic.
rm -rf "$TO"
SECONDS=0
AQ_REFERENCE_EXACT_BILINEAR=1 timeout 90 "$T" >"$OUT/log2.txt" 2>&1
echo "exact-bilinear run rc=$? wall=${SECONDS}s" >>"$OUT/log2.txt"
find "$TO" -name reference_stage_errors.tsv | head -1 | xargs -r -I{} cp {} "$OUT/reference_stage_errors_exact_bilinear.tsv"
exit $rc
