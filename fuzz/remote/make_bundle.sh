#!/bin/bash
# fuzz/remote/make_bundle.sh — packs the built libFuzzer targets (build-fuzz/fuzz/fuzz_*), the
# shared libraries they need (reference/gpu/bundle_libs.py: OpenImageIO's never-called heavy
# dependencies become stubs that abort if called), the seed corpora, dictionaries and this folder's
# run.sh into a git-ignored folder, so that a many-core machine without our Debian packages (the
# lent device machine) can fuzz for longer than the 2-core CI machine can (fuzz/README.md).
# The image readers are limited to an allow-list of formats (core/io.cpp), none of which is a
# stubbed library, so a stub abort during fuzzing would be a bundle defect, not a finding.
# Usage (repository root): fuzz/remote/make_bundle.sh [BUILD=build-fuzz] [BUNDLE=.fuzz]
# then on the remote machine, from a copy of the repository with BUNDLE.tar.xz beside it:
#   tar -xJf .fuzz.tar.xz && SECONDS_PER_JOB=510 JOBS=4 bash .fuzz/run.sh
set -euo pipefail
BUILD=${1:-build-fuzz}
B=${2:-.fuzz}
rm -rf "$B"
mkdir -p "$B/bin" "$B/lib" "$B/libcxx"
for t in gltf scene_file pipeline image; do
    cp "$BUILD/fuzz/fuzz_$t" "$B/bin/"
    # Stripping keeps every code address: symbolize a report here with the unstripped binary
    # (llvm-symbolizer --obj=build-fuzz/fuzz/fuzz_X 0xADDR).
    strip "$B/bin/fuzz_$t"
done
reference/gpu/bundle_libs.py "$BUILD/fuzz/fuzz_pipeline" "$B/lib" "$B/libcxx"
# OpenImageIO is the module core/libaq_oiio.so, loaded at start by every target (core/oiio.h,
# fuzz/fuzz_common.cpp); run.sh points AQ_OIIO_MODULE at this copy.
cp "$BUILD/core/libaq_oiio.so" "$B/lib/"
reference/gpu/bundle_libs.py "$BUILD/core/libaq_oiio.so" "$B/lib" "$B/libcxx"
strip --strip-unneeded "$B"/lib/* "$B"/libcxx/* 2>/dev/null || true
cp fuzz/remote/run.sh "$B/run.sh"
# One compressed file to carry (the device tool carries 64 MiB with the working tree).
tar -cJf "$B.tar.xz" "$B"
du -sh "$B" "$B"/* "$B.tar.xz"
