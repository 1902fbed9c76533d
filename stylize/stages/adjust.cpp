// stylize/stages/adjust.cpp — spec §4.1 "Adjust / load" (MNPR quadAdjustLoad.ogsfx adjustLoadFrag).
// Pointwise: the reference runs adjust_pixel on every pixel; the fast schedule without atmosphere
// restates it with AVX2, two RGBA pixels per register (same IEEE operations, bit-exact; checked
// against the reference by tests/stylize/registry_traversal_test.cpp).
#include "stylize/stages/adjust.h"

#include "stylize/scene_inputs.h"

#include <cmath>

#include <immintrin.h>

#include "stylize/kernels.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

namespace {

//! Linear depth is in scene units, whatever the model's units: a model in large units (a box
//! scaled by 1e6) has an automatic depth range in the millions. Any finite float range is valid.
constexpr double kMaxDepthRange = 1e30;

// One pixel. Branch-free apart from the compile-time atmosphere switch, so the row loop
// vectorises; the reference and the fast traversal both call exactly this.
template <bool kAtmosphere>
inline void adjust_pixel(const float* c, float z, float* o, float& zo, const AdjustParams& p, glm::vec3 substrate,
                         float inv_range, float inv_atm) {
    const bool finite = std::fabs(z) <= 3.402823466e38f;  // false for +-inf and NaN
    const float zn = (z - p.depth_near) * inv_range;
    zo = finite ? zn : 1.0f;  // no geometry -> far (MNPR: zBuffer == 1 -> depth 1)
    const float luma = luminance(c[0], c[1], c[2]);
    const float k = p.contrast * 0.5f + 0.5f;
    const float b = p.brightness - 1.0f;
    float atm = 0.0f;
    if constexpr (kAtmosphere) {
        const float zz = finite ? z : 1.0e9f;  // MNPR: no geometry = 1e9 units
        atm = sat((zz - p.atmosphere_start) * inv_atm);
    }
    const float tint[3] = {p.tint_r, p.tint_g, p.tint_b};
    const float a = c[3];
    for (int i = 0; i < 3; ++i) {
        const float s = lerp(luma, c[i], p.saturation);
        const float ct = lerp(0.5f, s, k);
        float v = sat(ct + b);
        if constexpr (kAtmosphere) v = lerp(v, tint[i], atm);
        o[i] = mix(substrate[i], v, a);
    }
    o[3] = a;
}

template <bool kAtmosphere>
void adjust_rows(ImageF& color_out, ImageF& depth_out, const ImageF& color, const ImageF& depth_linear,
                 glm::vec3 substrate, const AdjustParams& p, const Exec& ex) {
    const int w = color.width(), h = color.height();
    const float inv_range = 1.0f / (p.depth_far - p.depth_near);
    const float inv_atm = kAtmosphere ? 1.0f / (p.atmosphere_end - p.atmosphere_start) : 0.0f;
    const float* cin = color.data();
    const float* zin = depth_linear.data();
    float* cout = color_out.data();
    float* zout = depth_out.data();
#ifdef __AVX2__
    constexpr bool kVector = true;
#else
    constexpr bool kVector = false;  // the AQ_NATIVE_SIMD=OFF build: the plain loop
#endif
    if (kAtmosphere || ex.traversal == Traversal::Reference || !kVector) {
        toolkit::for_each_row_block(ex, h, [&](int y0, int y1) {
            for (std::size_t i = std::size_t(y0) * w; i < std::size_t(y1) * w; ++i)
                adjust_pixel<kAtmosphere>(cin + 4 * i, zin[i], cout + 4 * i, zout[i], p, substrate, inv_range, inv_atm);
        });
        return;
    }
#ifdef __AVX2__
    // Fast, no atmosphere: adjust_pixel two pixels per AVX register (RGBA RGBA), the same IEEE
    // operations in the same order per value (GCC does not vectorise the interleaved scalar loop).
    const float k = p.contrast * 0.5f + 0.5f;
    const float b = p.brightness - 1.0f;
    const __m256 vsat = _mm256_set1_ps(p.saturation), vk = _mm256_set1_ps(k), vb = _mm256_set1_ps(b);
    const __m256 half = _mm256_set1_ps(0.5f), one = _mm256_set1_ps(1.0f);
    const __m256 lr = _mm256_set1_ps(kLumaR), lg = _mm256_set1_ps(kLumaG), lb = _mm256_set1_ps(kLumaB);
    const __m256 sub = _mm256_setr_ps(substrate[0], substrate[1], substrate[2], 0.0f, substrate[0], substrate[1],
                                      substrate[2], 0.0f);
    const __m256 vnear = _mm256_set1_ps(p.depth_near), vinv = _mm256_set1_ps(inv_range);
    const __m256 fmax = _mm256_set1_ps(3.402823466e38f);
    const __m256 absmask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    // Outputs written with non-temporal stores where aligned (the usual case: large images are
    // 2 MiB-aligned): the next stages read them from memory anyway, and the stores need not
    // read the outputs' lines first.
    auto store = [](float* d, __m256 v, bool nt) {
        if (nt) _mm256_stream_ps(d, v);
        else _mm256_storeu_ps(d, v);
    };
    toolkit::for_each_row_block(ex, h, [&](int y0, int y1) {
        const std::size_t i1 = std::size_t(y1) * w;
        std::size_t i = std::size_t(y0) * w;
        const bool cnt = (reinterpret_cast<std::uintptr_t>(cout + 4 * i) & 31) == 0;
        const bool znt = (reinterpret_cast<std::uintptr_t>(zout + i) & 31) == 0;
        for (; i + 2 <= i1; i += 2) {
            const __m256 c = _mm256_loadu_ps(cin + 4 * i);
            const __m256 r = _mm256_permute_ps(c, 0x00), g = _mm256_permute_ps(c, 0x55);
            const __m256 bl = _mm256_permute_ps(c, 0xAA), a = _mm256_permute_ps(c, 0xFF);
            const __m256 luma = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(lr, r), _mm256_mul_ps(lg, g)),
                                              _mm256_mul_ps(lb, bl));
            const __m256 s = _mm256_add_ps(luma, _mm256_mul_ps(_mm256_sub_ps(c, luma), vsat));
            const __m256 ct = _mm256_add_ps(half, _mm256_mul_ps(_mm256_sub_ps(s, half), vk));
            const __m256 x = _mm256_add_ps(ct, vb);
            const __m256 v = sat8(x);  // kernels.h: NaN stays NaN
            // mix(substrate, v, a) = substrate * (1 - a) + v * a
            const __m256 m = _mm256_add_ps(_mm256_mul_ps(sub, _mm256_sub_ps(one, a)), _mm256_mul_ps(v, a));
            store(cout + 4 * i, _mm256_blend_ps(m, c, 0x88), cnt);  // alpha copied
        }
        for (; i < i1; ++i)
            adjust_pixel<false>(cin + 4 * i, zin[i], cout + 4 * i, zout[i], p, substrate, inv_range, inv_atm);
        std::size_t j = std::size_t(y0) * w;
        for (; j + 8 <= i1; j += 8) {
            const __m256 z = _mm256_loadu_ps(zin + j);
            const __m256 finite = _mm256_cmp_ps(_mm256_and_ps(z, absmask), fmax, _CMP_LE_OQ);
            const __m256 zn = _mm256_mul_ps(_mm256_sub_ps(z, vnear), vinv);
            store(zout + j, _mm256_blendv_ps(one, zn, finite), znt);
        }
        for (; j < i1; ++j) {
            const float z = zin[j];
            const bool finite = std::fabs(z) <= 3.402823466e38f;
            const float zn = (z - p.depth_near) * inv_range;
            zout[j] = finite ? zn : 1.0f;
        }
        stream_fence();
    });
#endif
}

}  // namespace

void check_adjust_params(const AdjustParams& p) {
    if (p.depth_far == p.depth_near) throw Error("adjust: depth_near == depth_far");
    if (p.atmosphere && p.atmosphere_end == p.atmosphere_start) throw Error("adjust: atmosphere_start == atmosphere_end");
}

void adjust(ImageF& color_out, ImageF& depth_out, const ImageF& color, const ImageF& depth_linear,
            glm::vec3 substrate, const AdjustParams& p, const Exec& ex) {
    toolkit::check_input(&color, 4, toolkit::Channels::Exactly, "adjust", "color");
    toolkit::check_input(&depth_linear, 1, toolkit::Channels::Exactly, "adjust", "depth");
    toolkit::check_same_size(depth_linear, color, "adjust", "depth", "color");
    check_adjust_params(p);
    toolkit::ensure_output(color_out, color.width(), color.height(), 4);
    toolkit::ensure_output(depth_out, color.width(), color.height(), 1);
    if (p.atmosphere)
        adjust_rows<true>(color_out, depth_out, color, depth_linear, substrate, p, ex);
    else
        adjust_rows<false>(color_out, depth_out, color, depth_linear, substrate, p, ex);
}

void register_adjust(Registry& r) {
    using P = AdjustParams;
    StageVariant v = declare(
        {.stage = "adjust",
         .variant = "mnpr",
         .doc = "MNPR adjust-load: normalised depth (near..far -> 0..1), saturation/contrast/brightness, "
                "atmosphere, background = substrate colour (spec 4.1)",
         .inputs = {{"color", target::kColor, 4, false}, {"depth", target::kDepthLinear, 1, false}},
         .outputs = {{"color", "color.adjusted", 4, false}, {"depth", "depth", 1, false}},
         .reference = StageVariant::Reference::PlainLoop,
         .row_halo = pointwise_rows},
        ParamTable<P>()
            .f("depth_near", &P::depth_near, 0, kMaxDepthRange, "linear depth mapped to 0 (MNPR 8)")
            .f("depth_far", &P::depth_far, 0, kMaxDepthRange, "linear depth mapped to 1 (MNPR 50)")
            .f("saturation", &P::saturation, 0, 5, "saturation, 1 = unchanged")
            .f("contrast", &P::contrast, 0, 5, "contrast, 1 = unchanged")
            .f("brightness", &P::brightness, 0, 5, "brightness, 1 = unchanged")
            .b("atmosphere", &P::atmosphere, "tint towards the atmosphere colour with depth")
            .f("atmosphere_start", &P::atmosphere_start, 0, 1e6, "depth where the tint starts")
            .f("atmosphere_end", &P::atmosphere_end, 0, 1e6, "depth where the tint is full")
            .f("tint_r", &P::tint_r, 0, 1, "atmosphere tint red")
            .f("tint_g", &P::tint_g, 0, 1, "atmosphere tint green")
            .f("tint_b", &P::tint_b, 0, 1, "atmosphere tint blue"),
        [](StageIO& io, const P& p, const Exec& ex) {
            adjust(*io.out[0], *io.out[1], *io.in[0], *io.in[1], globals_of(io).substrate_color, p, ex);
        },
        check_adjust_params);
    // MNPR normalises depth over 8..50 scene units (a Maya scene in cm). An automatically framed
    // camera hugs the scene's bounding sphere, so its clip range is the scene's depth range
    // whatever the model's units: normalise over it instead.
    v.scene_params = [](const ParamValues&, const SceneInputs& scene) {
        std::vector<SceneValue> out;
        if (const auto& range = scene.framed_depth_range()) {
            const std::string why = "the automatic depth range of the framed camera";
            out = {{"depth_near", double(range->first), why}, {"depth_far", double(range->second), why}};
        }
        return out;
    };
    r.add(std::move(v));
}

}  // namespace aq::stylize
