// ISA-L, the PNG encoder's deflate (core/png.h kPngIsalLevel), picks a code path at run time by the
// CPU's features: SSE4.2, AVX, AVX2 (and AVX-512 for its Huffman writer). docs/provenance.md says
// every x86-64 CPU with SSE4.2 writes the same PNG bytes. This executable checks it on the paths
// this CPU can run: it defines the library's dispatched level-2 entry points itself (the library
// calls them through its PLT, so these definitions win), sends each call to one chosen per-CPU
// implementation (exported by ISA-L 2.30 as NAME_01 SSE4.2, _02 AVX, _04 AVX2, _06 AVX-512,
// _base plain C) and compares the encoded files with those of ISA-L's own choice. Its own
// executable: the interposed symbols must not reach the other tests.
#include <dlfcn.h>

#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/image.h"
#include "core/png.h"

namespace {

using StreamFn = void (*)(void*);
using EncodeFn = void* (*)(void*, void*, void*, void*);

StreamFn g_body = nullptr;      //!< nullptr: ISA-L's own dispatch
EncodeFn g_encode = nullptr;
int g_body_calls = 0, g_encode_calls = 0;

template <class F>
F next_symbol(const char* name) {
    return reinterpret_cast<F>(dlsym(RTLD_NEXT, name));
}

template <class F>
F variant(const std::string& name) {
    return reinterpret_cast<F>(dlsym(RTLD_DEFAULT, name.c_str()));
}

}  // namespace

// The library's dispatched entry points of level 2 (igzip_icf_body.c: isal_deflate_icf_body ->
// isal_deflate_icf_body_lvl2; the Huffman writer encode_deflate_icf).
extern "C" void isal_deflate_icf_body_lvl2(void* stream) {
    static const StreamFn dispatched = next_symbol<StreamFn>("isal_deflate_icf_body_lvl2");
    ++g_body_calls;
    (g_body ? g_body : dispatched)(stream);
}

extern "C" void* encode_deflate_icf(void* next, void* end, void* bits, void* tables) {
    static const EncodeFn dispatched = next_symbol<EncodeFn>("encode_deflate_icf");
    ++g_encode_calls;
    return (g_encode ? g_encode : dispatched)(next, end, bits, tables);
}

namespace aq {
namespace {

//! A frame-like image: flat regions (long matches), a smooth gradient, and a paper-like grain of
//! hashed values (few matches) — each of the encoder's cases.
ImageF frame_like(int w, int h) {
    ImageF img(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int k = 0; k < 3; ++k) {
                const unsigned hsh = (unsigned(x) * 73856093u) ^ (unsigned(y) * 19349663u) ^ (unsigned(k) * 83492791u);
                const float grain = float(hsh % 17u) / 255.0f;
                float v = 0.9f;                                           // the paper
                if (x > w / 4 && x < 3 * w / 4 && y > h / 5) v = 0.2f + 0.6f * float(y) / float(h);  // paint
                if (x % 64 < 8) v = 0.5f;                                 // flat stripes
                img.at(x, y, k) = v - ((x / 3 + y) % 5 == 0 ? grain : 0.0f);
            }
    return img;
}

std::vector<unsigned char> encode(const ImageF& img) {
    std::vector<unsigned char> out, rows;
    encode_png(img, "", out, rows);
    return out;
}

bool cpu_has(const char* feature) {
    __builtin_cpu_init();
    const std::string f = feature;
    if (f == "sse4.2") return __builtin_cpu_supports("sse4.2");
    if (f == "avx") return __builtin_cpu_supports("avx");
    if (f == "avx2") return __builtin_cpu_supports("avx2");
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
           __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq") &&
           __builtin_cpu_supports("avx512cd");
}

TEST(PngCpuVariants, EveryIsalPathThisCpuRunsWritesTheSameBytes) {
    const ImageF img = frame_like(700, 300);  // 630 kB of rows: several deflate blocks
    g_body = nullptr;
    g_encode = nullptr;
    g_body_calls = g_encode_calls = 0;
    const std::vector<unsigned char> dispatched = encode(img);
    ASSERT_GT(g_body_calls, 0) << "ISA-L did not call the interposed level-2 body: it binds its calls "
                                  "internally, and this test cannot select its CPU paths";
    ASSERT_GT(g_encode_calls, 0) << "ISA-L did not call the interposed Huffman writer";

    // The body's paths (the base C one runs only without SSE4.2 and writes other bytes: not checked).
    struct Path {
        const char* suffix;
        const char* feature;
    };
    const Path bodies[] = {{"_01", "sse4.2"}, {"_02", "avx"}, {"_04", "avx2"}};
    const Path encoders[] = {{"_base", "sse4.2"}, {"_04", "avx2"}, {"_06", "avx512"}};
    int checked = 0;
    for (const Path& b : bodies) {
        if (!cpu_has(b.feature)) continue;
        for (const Path& e : encoders) {
            if (!cpu_has(e.feature)) continue;
            SCOPED_TRACE(std::string("isal_deflate_icf_body_hash_hist") + b.suffix + ", encode_deflate_icf" + e.suffix);
            g_body = variant<StreamFn>(std::string("isal_deflate_icf_body_hash_hist") + b.suffix);
            g_encode = variant<EncodeFn>(std::string("encode_deflate_icf") + e.suffix);
            ASSERT_TRUE(g_body && g_encode) << "this ISA-L does not export its per-CPU paths (2.30 does): "
                                               "check the claim of docs/provenance.md another way";
            g_body_calls = g_encode_calls = 0;
            const std::vector<unsigned char> bytes = encode(img);
            EXPECT_GT(g_body_calls, 0);
            EXPECT_GT(g_encode_calls, 0);
            EXPECT_TRUE(bytes == dispatched) << bytes.size() << " bytes against " << dispatched.size();
            ++checked;
        }
    }
    g_body = nullptr;
    g_encode = nullptr;
    EXPECT_GE(checked, 1) << "no SSE4.2 on this CPU";
    // The plain C path does differ (so the selection above reaches ISA-L): its bytes are not the
    // dispatched ones on this CPU.
    g_body = variant<StreamFn>("isal_deflate_icf_body_hash_hist_base");
    ASSERT_TRUE(g_body);
    EXPECT_FALSE(encode(img) == dispatched);
    g_body = nullptr;
}

}  // namespace
}  // namespace aq
