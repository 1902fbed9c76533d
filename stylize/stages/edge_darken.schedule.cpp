// stylize/stages/edge_darken.schedule.cpp — the fast schedules of edge_darken: dog (WC17 eq. 8:
// rows in chunks, the exponents per pixel with edge_darken_dog_exponent, the powers in one
// vectorised loop) and rgbd (WC18 §3.1; the
// maths, edge_darken_rgbd_exponent and edge_darken_rgbd_px, in edge_darken.h; the checks and the
// plain reference loop in edge_darken.cpp). Rows in chunks of 64 pixels, each step a simple loop
// over arrays: gather the inputs, the exponents (vectorised), then the powers of only the pixels
// that darken, packed (vectorised pow_c), and the output. Value for value the operations of
// edge_darken_rgbd_px (tests/stylize/row_kernels_test.cpp checks it bit for bit; the
// registry-wide traversal test compares the two schedules).
// The power loops vectorise only when GCC may evaluate both sides of a select; that needs
// -fno-trapping-math (FP exception flags only — no value changes, unlike -ffast-math: no
// reassociation, no FMA, no reciprocal approximations). See docs/stylize.md "Speed".
#pragma GCC optimize("no-trapping-math")
#include "stylize/stages/edge_darken.h"

#include <algorithm>

#include "stylize/kernels.h"

namespace aq::stylize {

using namespace toolkit;

namespace {

constexpr int kChunk = 64;

//! One chunk's inputs as planes: colour, edge, control, bleeding and crowd per pixel.
struct RgbdChunk {
    float cr[kChunk], cg[kChunk], cb[kChunk], ev[kChunk], ci[kChunk], bl[kChunk], cd[kChunk];
};

//! One fast run: the views and resamplers. any_edge, gather and darken are inlined into row(),
//! where the chunk is a local: its stores then provably alias no member (4 % faster than calls).
struct RgbdRun {
    View<const glm::vec4> c;
    Plane e, ctrl, bm, cw;
    Resampler up, upc;  //!< the bleeding mask's and the crowd map's (either may be coarser)
    bool has_crowd;
    View<glm::vec4> o;
    bool in_place;
    glm::vec3 substrate;
    const EdgeDarkenRgbdParams& p;

    //! Whether pixels [xs, xs + n) of row y have an edge. A chunk without is the colour as it is:
    //! an edge of 0 gives E_d = 0 or NaN (0 times a non-finite control or bleeding term), hence
    //! the exponent 1, whatever the other inputs (most of a frame's background). One-channel
    //! edges (a contiguous row) are tested eight at a time before they are read.
    [[gnu::always_inline]] bool any_edge(int xs, int n, int y) const {
        if (e.px == 1) return nonzero_channels_of(e.p + y * e.row + xs, std::size_t(n), 1) != 0;
        bool any = false;
        for (int i = 0; i < n; ++i) any |= e(xs + i, y) != 0.0f;
        return any;
    }

    //! The inputs of pixels [xs, xs + n) of row y, eight at a time where they fit.
    [[gnu::always_inline]] void gather(RgbdChunk& k, int xs, int n, int y) const {
        int i8 = 0;
        for (; i8 + 8 <= n; i8 += 8) {
            const float* cp = &c(xs + i8, y).x;
            store8(k.cr + i8, simd::strided8<4>(cp));
            store8(k.cg + i8, simd::strided8<4>(cp + 1));
            store8(k.cb + i8, simd::strided8<4>(cp + 2));
            store8(k.ev + i8, plane8(e, xs + i8, y));
            store8(k.ci + i8, plane8(ctrl, xs + i8, y));
        }
        for (int i = i8; i < n; ++i) {
            const glm::vec4 cv = c(xs + i, y);
            k.cr[i] = cv.x, k.cg[i] = cv.y, k.cb[i] = cv.z;
            k.ev[i] = e(xs + i, y);
            k.ci[i] = ctrl(xs + i, y);
        }
        for (int i = 0; i < i8; i += 8) store8(k.bl + i, up.sample8(bm, xs + i, y));
        for (int i = i8; i < n; ++i) k.bl[i] = up.sample(bm, xs + i, y);
        if (has_crowd) {
            for (int i = 0; i < i8; i += 8) store8(k.cd + i, upc.sample8(cw, xs + i, y));
            for (int i = i8; i < n; ++i) k.cd[i] = upc.sample(cw, xs + i, y);
        } else {
            std::fill(k.cd, k.cd + n, 0.0f);  // no crowd map: the constant 0 the plain loop samples
        }
    }

    //! Pixels [xs, xs + n) of row y from their inputs: the exponents, the powers of the pixels
    //! that darken (d != 1), packed, and the output.
    [[gnu::always_inline]] void darken(const RgbdChunk& k, int xs, int n, int y) const {
        float d[kChunk], base[3 * kChunk], dexp[3 * kChunk], r[3 * kChunk];
        int idx[kChunk];
        for (int i = 0; i < n; ++i)
            d[i] = edge_darken_rgbd_exponent(k.cr[i], k.cg[i], k.cb[i], k.ev[i], k.ci[i], k.bl[i], k.cd[i], substrate, p);
        int m = 0;
        for (int i = 0; i < n; ++i) {
            idx[m] = i;
            m += d[i] != 1.0f;
        }
        for (int j = 0; j < m; ++j) {
            const int i = idx[j];
            base[3 * j] = k.cr[i], base[3 * j + 1] = k.cg[i], base[3 * j + 2] = k.cb[i];
            dexp[3 * j] = dexp[3 * j + 1] = dexp[3 * j + 2] = d[i];
        }
        pow_c_many(base, dexp, r, std::size_t(3 * m));
        if (!in_place)
            for (int i = 0; i < n; ++i) o(xs + i, y) = c(xs + i, y);
        for (int j = 0; j < m; ++j) {
            const int i = idx[j];
            o(xs + i, y) = glm::vec4(r[3 * j], r[3 * j + 1], r[3 * j + 2], c(xs + i, y).w);
        }
    }

    void row(int y, int x0, int x1) const {
        RgbdChunk k;
        for (int xs = x0; xs < x1; xs += kChunk) {
            const int n = std::min(kChunk, x1 - xs);
            if (!any_edge(xs, n, y)) {
                if (!in_place)
                    for (int i = 0; i < n; ++i) o(xs + i, y) = c(xs + i, y);
                continue;
            }
            gather(k, xs, n, y);
            darken(k, xs, n, y);
        }
    }
};

}  // namespace

void edge_darken_rgbd_fast(ImageF& dst, const ImageF& color, const ImageF& edges, const ImageF& ctrl_edge,
                           const ImageF* bleed, const ImageF* crowd, glm::vec3 substrate, const EdgeDarkenRgbdParams& p,
                           const Exec& ex) {
    const int w = color.width(), h = color.height();
    static const float kZero = 0.0f;
    const Plane bm = bleed ? plane(*bleed, bleed->channels() == 4 ? 3 : 0) : constant_plane(&kZero, w, h);
    const Plane cw = crowd ? plane(*crowd, 0) : constant_plane(&kZero, w, h);
    const RgbdRun run{.c = color.view<glm::vec4>(),
                      .e = plane(edges, 0),
                      .ctrl = plane(ctrl_edge, control::kEdgeIntensity.channel),
                      .bm = bm,
                      .cw = cw,
                      .up = Resampler(w, h, bm.width, bm.height),
                      .upc = Resampler(w, h, cw.width, cw.height),
                      .has_crowd = crowd != nullptr,
                      .o = dst.view<glm::vec4>(),
                      .in_place = &dst == &color,
                      .substrate = substrate,
                      .p = p};
    for_each_row(ex, w, h, [&](int y, int x0, int x1) { run.row(y, x0, x1); });
}

void edge_darken_dog_fast(ImageF& dst, const ImageF& color, const ImageF& blurred, const ImageF& ctrl_edge,
                          const EdgeDarkenDogParams& p, const Exec& ex) {
    const int w = color.width(), h = color.height();
    // The blurred colour (RGB planes of a 3- or 4-channel image), upsampled when at half size.
    const Plane br = plane(blurred, 0), bg = plane(blurred, 1), bb = plane(blurred, 2);
    const Resampler up(w, h, blurred.width(), blurred.height());
    auto blur_at = [&](int x, int y) -> glm::vec3 {
        return {up.sample(br, x, y), up.sample(bg, x, y), up.sample(bb, x, y)};
    };
    const View<const glm::vec4> c = color.view<glm::vec4>();
    const Plane ctrl = plane(ctrl_edge, control::kEdgeIntensity.channel);
    const View<glm::vec4> o = dst.view<glm::vec4>();
    // Rows in chunks: exponents per pixel, then the powers in one vectorisable loop (the same
    // operations as edge_darken_dog_px, pixel by pixel).
    for_each_row(ex, w, h, [&](int y, int x0, int x1) {
        float base[3 * kChunk], dexp[3 * kChunk], r[3 * kChunk];
        for (int xs = x0; xs < x1; xs += kChunk) {
            const int n = std::min(kChunk, x1 - xs);
            for (int i = 0; i < n; ++i) {
                const int x = xs + i;
                const glm::vec4 cv = c(x, y);
                const float d = edge_darken_dog_exponent(cv, blur_at(x, y), ctrl(x, y), p);
                for (int k = 0; k < 3; ++k) base[3 * i + k] = cv[k], dexp[3 * i + k] = d;
            }
            pow_c_many(base, dexp, r, std::size_t(3 * n));
            for (int i = 0; i < n; ++i) {
                const int x = xs + i;
                o(x, y) = dexp[3 * i] == 1.0f ? c(x, y) : glm::vec4(r[3 * i], r[3 * i + 1], r[3 * i + 2], c(x, y).w);
            }
        }
    });
}

}  // namespace aq::stylize
