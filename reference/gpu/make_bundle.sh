#!/bin/bash
# reference/gpu/make_bundle.sh — packs reference_test for a GPU machine that lacks our Debian
# libraries (docs/reference.md, "On a real GPU"): the stripped test executable, the shared
# libraries it needs except glibc's core and the GL/EGL libraries (those must come from the GPU
# driver's GLVND), with OpenImageIO's never-called heavy dependencies replaced by stubs
# (bundle_libs.py), the run-time source files the tests read (shaders, scene files, presets) and
# the shared assets they use.
#
# Usage (from the repository root): reference/gpu/make_bundle.sh SRC BUILD [BUNDLE=.gpu]
#   SRC    the source tree the test was built from (its compiled-in AQ_SOURCE_DIR)
#   BUILD  its build folder (holds tests/reference/reference_test)
# The bundle folder must be git-ignored (.git/info/exclude: /.gpu/). Run it on the GPU machine
# with reference/gpu/run_on_gpu.sh (copied into the bundle).
set -euo pipefail
SRC=$(realpath "$1")
BUILD=$(realpath "$2")
B=${3:-.gpu}
SHARED=${AQ_SHARED:-$(realpath "$SRC/../shared")}
rm -rf "$B/bin" "$B/lib" "$B/libcxx" "$B/src" "$B/shared"
mkdir -p "$B/bin" "$B/lib" "$B/libcxx" "$B/src" "$B/shared/assets"
cp "$BUILD/tests/reference/reference_test" "$B/bin/"
strip "$B/bin/reference_test"
"$(dirname "$0")/bundle_libs.py" "$BUILD/tests/reference/reference_test" "$B/lib" "$B/libcxx"
# OpenImageIO is not linked: it is the module core/libaq_oiio.so, loaded on first use (core/oiio.h);
# run_on_gpu.sh points AQ_OIIO_MODULE at this copy.
cp "$BUILD/core/libaq_oiio.so" "$B/lib/"
"$(dirname "$0")/bundle_libs.py" "$BUILD/core/libaq_oiio.so" "$B/lib" "$B/libcxx"
strip --strip-unneeded "$B"/lib/* "$B"/libcxx/* 2>/dev/null || true
# Run-time sources: the binary reads these through its compiled-in source path.
for d in reference/shaders scenes/data stylize/presets; do
    mkdir -p "$B/src/$d"
    cp -r "$SRC/$d/." "$B/src/$d/"
done
[ -f "$SRC/GPU_SNAPSHOT_COMMIT" ] && cp "$SRC/GPU_SNAPSHOT_COMMIT" "$B/src/"
echo "$SRC" >"$B/src_path"   # where run_on_gpu.sh links $B/src
echo "$BUILD/test-output" >"$B/test_output_path"   # the binary's compiled-in AQ_TEST_OUTPUT_DIR
# Shared assets used by tests/reference (scene files' models and papers, bare glTFs).
for a in paper/mnpr/rough_default_2k.jpg gltf/Suzanne gltf/WaterBottle gltf/OrientationTest gltf/Fox gltf/BoxTextured \
         meshes/stanford_dragon/dragon_202k.glb plants/ez-tree/ez_bush2.glb plants/ez-tree/ez_oak_large_dense.glb; do
    mkdir -p "$B/shared/assets/$(dirname "$a")"
    cp -r "$SHARED/assets/$a" "$B/shared/assets/$a"
done
cp "$(dirname "$0")/run_on_gpu.sh" "$B/run.sh"
du -sh "$B" "$B"/*
