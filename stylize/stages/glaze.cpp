// stylize/stages/glaze.cpp — see glaze.h. Reference: a plain loop sampling the ramp per pixel
// (sample_resampled_plane); fast: oneTBB row blocks resampling each ramp row once (the same values).
#pragma GCC optimize("no-trapping-math")  // lets the row loop if-convert and vectorise; values unchanged
#include "stylize/stages/glaze.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "stylize/stages/toolkit.h"
#include "stylize/stages/wash.h"

namespace aq::stylize {

using namespace toolkit;

namespace {

//! Ramp texels within ±kRampBound resample to finite values (|a + (c - a)·t| <= 3·10^30 < FLT_MAX),
//! the condition for skipping a layer where its wash is 0 (colour ramps lie in [0, 1]).
constexpr float kRampBound = 1e30f;

// One output row: w pixels of 4 channels; rows = the N used layers' resampled ramp rows, one
// after the other; ch[j] = the wash channel of used layer j (in back-to-front order).
template <bool Mul, int N>
void glaze_row(float* __restrict o, const float* __restrict base, const float* __restrict wash,
               const float* __restrict rows, int w, const int* ch) {
    int c4[N > 0 ? N : 1];
    for (int j = 0; j < N; ++j) c4[j] = ch[j];
    // A pixel's RGB in the first three lanes of a 4-lane register: glaze_px's operations lane by
    // lane (the same IEEE operations as its vec3 form; the fourth lane is computed and replaced).
    for (int x = 0; x < w; ++x) {
        const std::size_t i = std::size_t(x) * 4;
        v4f c;
        std::memcpy(&c, base + i, sizeof c);
        for (int j = 0; j < N; ++j) {
            v4f col;
            std::memcpy(&col, rows + (std::size_t(j) * w + x) * 4, sizeof col);
            const float k = sat(col[3] * wash[i + std::size_t(c4[j])]);
            if constexpr (Mul) c = c * (1.0f - k * (1.0f - col));
            else c = c * (1.0f - k) + col * k;
        }
        c[3] = 1.0f;
        std::memcpy(o + i, &c, sizeof c);
    }
}

template <bool Mul>
void glaze_row_n(int n, float* o, const float* base, const float* wash, const float* rows, int w, const int* ch) {
    switch (n) {
        case 0: glaze_row<Mul, 0>(o, base, wash, rows, w, ch); break;
        case 1: glaze_row<Mul, 1>(o, base, wash, rows, w, ch); break;
        case 2: glaze_row<Mul, 2>(o, base, wash, rows, w, ch); break;
        case 3: glaze_row<Mul, 3>(o, base, wash, rows, w, ch); break;
        default: glaze_row<Mul, 4>(o, base, wash, rows, w, ch); break;
    }
}

}  // namespace

void glaze(ImageF& dst, const ImageF* base, const ImageF& wash, const ImageF* const ramp[4], glm::vec3 paper_color,
           bool multiplicative, const Exec& ex) {
    static const char* kPorts[4] = {"ramp0", "ramp1", "ramp2", "ramp3"};
    check_input(&wash, 4, Channels::Exactly, "glaze", "wash");
    check_not_alias(dst, &wash, "glaze", "wash");
    for (int k = 0; k < 4; ++k) {
        check_input(ramp[k], 4, Channels::Exactly, "glaze", kPorts[k]);
        check_not_alias(dst, ramp[k], "glaze", kPorts[k]);
        if (k) check_same_size(*ramp[k], *ramp[0], "glaze", kPorts[k], "ramp0");
    }
    if (base) {
        check_input(base, 4, Channels::Exactly, "glaze", "color");
        check_same_size(*base, wash, "glaze", "color", "wash");
        check_not_alias(dst, base, "glaze", "color");
    }
    const int w = wash.width(), h = wash.height();
    ensure_output(dst, w, h, 4);
    Plane rp[16];
    for (int c = 0; c < 16; ++c) rp[c] = plane(*ramp[c / 4], c % 4);
    const float* wd = wash.data();
    const float* bd = base ? base->data() : nullptr;
    float* od = dst.data();
    auto px = [&](int x, int y, auto&& sample) {
        const std::size_t i = std::size_t(y) * w + x;
        glm::vec3 c = bd ? glm::vec3(bd[i * 4], bd[i * 4 + 1], bd[i * 4 + 2]) : paper_color;
        for (int k = 0; k < 4; ++k) {
            const glm::vec3 col(sample(rp[4 * k], x, y), sample(rp[4 * k + 1], x, y), sample(rp[4 * k + 2], x, y));
            const float a = sample(rp[4 * k + 3], x, y);
            c = glaze_px(c, col, sat(a * wd[i * 4 + k]), multiplicative);
        }
        od[i * 4] = c.r, od[i * 4 + 1] = c.g, od[i * 4 + 2] = c.b, od[i * 4 + 3] = 1.0f;
    };
    if (ex.traversal == Traversal::Reference) {
        plain_loop(w, h, [&](int x, int y) {
            px(x, y, [&](const Plane& p, int sx, int sy) { return sample_resampled_plane(p, sx, sy, w, h); });
        });
        return;
    }
    // Fast: each used ramp's row resampled once per output row (RowResampler: sample_resampled's
    // values), then the layers composited over the row with the variant as a constant.
    // A multiplicative layer whose wash is 0 multiplies by exactly 1 (dst·(1 - 0·(1 - c))) where
    // its resampled ramp is finite, which holds where the ramp texels it lerps lie within
    // ±kRampBound (a lerp of such values cannot overflow). So such a layer is skipped: in the whole
    // image when its wash is 0 everywhere (the empty slots of an ID pack), else in each row where
    // its wash is 0 (LD06's layers cover parts of the picture: 52-68 % of the oak's layer rows).
    // Over is not skipped (dst + c·0 can turn -0 into +0).
    const std::uint32_t painted = multiplicative ? nonzero_channels(ex, wash) : 0xfu;
    int used[4], n = 0;
    for (int k = 0; k < 4; ++k) {
        const bool skip = !(painted >> k & 1u) && !any_beyond(ex, ramp[k]->data(), ramp[k]->num_values(), kRampBound);
        if (!skip) used[n++] = k;
    }
    const int rw = ramp[0]->width(), rh = ramp[0]->height();
    const ResampleAxis ax(w, rw), ay(h, rh);
    for_each_row_block(ex, h, [&](int y0, int y1) {
        std::vector<RowResampler<4>> up;
        for (int j = 0; j < n; ++j) up.emplace_back(ramp[used[j]]->data(), rw, w, ax, ay);
        std::vector<float> rows(std::size_t(w) * 4 * std::size_t(std::max(n, 1))), paper_row;
        if (!bd) {  // no picture yet: a row of the paper colour
            paper_row.resize(std::size_t(w) * 4);
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 3; ++c) paper_row[std::size_t(x) * 4 + c] = paper_color[c];
        }
        // Whether source row r of used layer j lies within ±kRampBound, cached for the rows of
        // this block (each source row serves one or two output rows).
        std::vector<std::int8_t> bounded(std::size_t(n) * std::size_t(rh), -1);
        auto row_bounded = [&](int j, int r) {
            std::int8_t& b = bounded[std::size_t(j) * std::size_t(rh) + std::size_t(r)];
            if (b < 0) b = all_within(ramp[used[j]]->data() + std::size_t(r) * rw * 4, std::size_t(rw) * 4, kRampBound);
            return b == 1;
        };
        for (int y = y0; y < y1; ++y) {
            const std::size_t i0 = std::size_t(y) * w;
            const std::uint32_t row_painted = multiplicative ? nonzero_channels_of(wd + i0 * 4, std::size_t(w) * 4, 4) : 0xfu;
            int row_used[4], m = 0;
            for (int j = 0; j < n; ++j) {
                const int k = used[j];
                const bool skip = !(row_painted >> k & 1u) && row_bounded(j, ay.i0[std::size_t(y)]) &&
                                  row_bounded(j, ay.i1[std::size_t(y)]);
                if (skip) continue;
                up[std::size_t(j)].row(y, rows.data() + std::size_t(m) * w * 4);
                row_used[m++] = k;
            }
            const float* b = bd ? bd + i0 * 4 : paper_row.data();
            if (multiplicative) glaze_row_n<true>(m, od + i0 * 4, b, wd + i0 * 4, rows.data(), w, row_used);
            else glaze_row_n<false>(m, od + i0 * 4, b, wd + i0 * 4, rows.data(), w, row_used);
        }
    });
}

void register_glaze(Registry& r) {
    for (bool mul : {true, false}) {
        StageVariant v;
        v.stage = "glaze";
        v.variant = mul ? "multiplicative" : "over";
        v.doc = mul ? "LD06 §4.2 glazing, subtractive-like: dst·(1 - k·(1 - c)) per layer, back to front, over the picture or the paper colour"
                    : "LD06 §4.2 glazing as plain alpha blending: mix(dst, c, k) per layer, back to front";
        v.inputs = {{"color", "color.ld06", 4, true},     {"wash", "ld06.wash", 4, false},
                    {"ramp0", "ld06.ramp.0", 4, false},   {"ramp1", "ld06.ramp.1", 4, false},
                    {"ramp2", "ld06.ramp.2", 4, false},   {"ramp3", "ld06.ramp.3", 4, false}};
        v.outputs = {{"color", "color.glazed", 4, false}};
        v.run = with_port_check(v, [mul](StageIO& io, const ParamValues&, const Exec& ex) {
            const ImageF* const ramp[4] = {io.in[2], io.in[3], io.in[4], io.in[5]};
            glaze(*io.out[0], io.in[0], *io.in[1], ramp, globals_of(io).substrate_color, mul, ex);
        });
        v.reference = StageVariant::Reference::PlainLoop;
        r.add(std::move(v));
    }
}

}  // namespace aq::stylize
