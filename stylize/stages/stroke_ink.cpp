// stylize/stages/stroke_ink.cpp — see stroke_ink.h. Reference: plain loop with per-pixel
// resampling; fast: oneTBB rows with precomputed taps (the same values).
#include "stylize/stages/stroke_ink.h"

#include <algorithm>
#include <cstring>

#include "stylize/stages/toolkit.h"
#include "stylize/stages/wash.h"

namespace aq::stylize {

using namespace toolkit;

void stroke_ink(ImageF& dst, const ImageF& color, const ImageF& ink, const StrokeInkParams& p, const Exec& ex) {
    check_input(&color, 4, Channels::Exactly, "stroke_ink", "color");
    check_input(&ink, 1, Channels::Exactly, "stroke_ink", "ink");
    check_not_alias(dst, &ink, "stroke_ink", "ink");
    const bool in_place = &dst == &color;  // only the inked pixels are written
    const int w = color.width(), h = color.height();
    if (!in_place) ensure_output(dst, w, h, 4);
    const Plane ip = plane(ink, 0);
    const float* c = color.data();
    float* o = dst.data();
    if (ex.traversal == Traversal::Reference) {
        plain_loop(w, h, [&](int x, int y) {
            const std::size_t i = std::size_t(y) * w + x;
            const float k = ink_opacity(p.alpha, sample_resampled_plane(ip, x, y, w, h));
            const glm::vec3 d(c[i * 4], c[i * 4 + 1], c[i * 4 + 2]);
            const glm::vec3 r = k == 0.0f ? d : glaze_px(d, p.color, k, false);
            o[i * 4] = r.r, o[i * 4 + 1] = r.g, o[i * 4 + 2] = r.b, o[i * 4 + 3] = c[i * 4 + 3];
        });
        return;
    }
    // Fast: the ink row resampled once (RowResampler; the ink itself at the same size), then the
    // row glazed in registers (glaze_px4: glaze_px's values); in place, uninked pixels untouched.
    const ResampleAxis ax(w, ink.width()), ay(h, ink.height());
    const v4f col = {p.color.r, p.color.g, p.color.b, 0.0f};
    constexpr int kGroup = 8;
    for_each_row_block(ex, h, [&](int y0, int y1) {
        RowResampler<1> up(ink.data(), ink.width(), w, ax, ay);
        std::vector<float> buf(static_cast<std::size_t>(w));
        for (int y = y0; y < y1; ++y) {
            const float* cov = up.row_or_source(y, buf.data());
            const float* src = c + std::size_t(y) * w * 4;
            float* out = o + std::size_t(y) * w * 4;
            for (int x0 = 0; x0 < w; x0 += kGroup) {
                const int x1 = std::min(w, x0 + kGroup);
                if (in_place && x1 - x0 == kGroup) {  // skip 8 uninked pixels at once (sat(v) == 0 iff v <= 0)
#ifdef __AVX2__
                    const __m256 v = _mm256_mul_ps(_mm256_set1_ps(p.alpha), _mm256_loadu_ps(cov + x0));
                    if (_mm256_movemask_ps(_mm256_cmp_ps(v, _mm256_setzero_ps(), _CMP_LE_OQ)) == 0xFF) continue;
#else
                    bool none = true;
                    for (int l = 0; l < kGroup; ++l) none &= p.alpha * cov[x0 + l] <= 0.0f;
                    if (none) continue;
#endif
                }
                for (int x = x0; x < x1; ++x) {
                    const float k = ink_opacity(p.alpha, cov[x]);
                    if (in_place && k == 0.0f) continue;
                    v4f d;
                    std::memcpy(&d, src + std::size_t(x) * 4, sizeof d);
                    if (k != 0.0f) {
                        const float a = d[3];
                        d = glaze_px4<false>(d, col, k);
                        d[3] = a;
                    }
                    std::memcpy(out + std::size_t(x) * 4, &d, sizeof d);
                }
            }
        }
    });
}

void register_stroke_ink(Registry& r) {
    using P = StrokeInkParams;
    r.add(declare({.stage = "stroke_ink",
                   .variant = "over",
                   .doc = "LD06 §4.4: the strokes' ink coverage painted last, over the washes, in one ink colour",
                   .inputs = {{"color", "color.shadowed", 4, false}, {"ink", "ld06.strokes", 1, false}},
                   .outputs = {{"color", "color.inked", 4, false}},
                   .reference = StageVariant::Reference::PlainLoop,
                   .in_place_input = "color",  // strokes cover a few per cent of the image
                   .in_place_output = "color"},
                  ParamTable<P>()
                      .f("color_r", field_path(&P::color, &glm::vec3::r), 0, 1, "ink colour (r; display value; ours: dark sepia)")
                      .f("color_g", field_path(&P::color, &glm::vec3::g), 0, 1, "ink colour (g)")
                      .f("color_b", field_path(&P::color, &glm::vec3::b), 0, 1, "ink colour (b)")
                      .f("alpha", &P::alpha, 0, 1, "ink opacity at full coverage (ours: 0.85)"),
                  [](StageIO& io, const P& p, const Exec& ex) { stroke_ink(*io.out[0], *io.in[0], *io.in[1], p, ex); }));
}

}  // namespace aq::stylize
