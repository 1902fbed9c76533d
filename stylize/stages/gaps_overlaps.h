// stylize/stages/gaps_overlaps.h — stage "gaps_overlaps" (spec §4.7): WC18 §3.2 Algorithm 1.
//
// Variant wc18, in MNPR's form (quadGapsOverlaps gapsOverlapsFrag) with the paper's loop bounds:
// only pixels with alpha > 0.1, bleeding mask < 0.01 and extended edge E_e > 0.1 (paper: 0.2) are
// touched. p = ctrl.edge.b * m (m = 5 steps, paper and MNPR). G = normalize(Sobel-like gradient of
// E_e over the 3x3 neighbourhood: d/du = (r + (tr + br)/2) - (l + (tl + bl)/2), same for v).
//   Overlaps (p > 0.1): for i = 1..m while i <= p: C_n = colour at x + i G (bilinear); if
//     |C_n - C| > 0.33 (RGBA distance; paper "RGBD" 0.5): unless C_n is within 0.1 of the substrate,
//     C = mixRYB(C, C_n) (ryb.h); stop. If all m steps found nothing (the gradient did not converge),
//     C = mixRYB(C, colour at x - G) (Algorithm 1 lines 22-26).
//   Gaps (p < -0.1): if E_e > 2/m (MNPR's "direct edge"; the paper tests the unextended edge > 0.7)
//     the pixel becomes a gap; else for i = 1..m while i <= |p|: if E_e(x + i G) > 1/m: gap; stop.
//   A gap writes the substrate colour, or (transparent_gaps) keeps the colour and writes alpha 0
//   ("transparent gaps are obtained by zeroing the output color alpha channel").
#pragma once

#include <limits>
#include <type_traits>

#include <glm/glm.hpp>

#include "core/exec.h"
#include "core/image.h"
#include "core/lanes.h"
#include "stylize/ryb.h"
#include "stylize/stage.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

inline constexpr int kGapsOverlapsSteps = 5;              //!< m: WC18 "m = 5 in our experiments" (MNPR gGORadius 5)
inline constexpr float kGoColorDifference = 0.33f;        //!< MNPR (paper: 0.5 in RGBD)
inline constexpr float kGoSubstrateProximity = 0.1f;      //!< MNPR: no overlap with the substrate colour
inline constexpr float kGoAlphaThreshold = 0.1f;          //!< MNPR: only painted pixels
inline constexpr float kGoBleedThreshold = 0.01f;         //!< MNPR: not where colours bleed
inline constexpr float kGoEdgeThreshold = 0.1f;           //!< MNPR (paper: 0.2)
inline constexpr float kGoCtrlThreshold = 0.1f;           //!< MNPR: |p| must exceed this

struct GapsOverlapsParams {
    int steps = kGapsOverlapsSteps;                  //!< m, the widest gap/overlap in pixels [1, 16]
    float color_difference = kGoColorDifference;     //!< [0, 2]
    float substrate_proximity = kGoSubstrateProximity;  //!< [0, 2]
    float alpha_threshold = kGoAlphaThreshold;       //!< [0, 1]
    float bleed_threshold = kGoBleedThreshold;       //!< [0, 1]
    float edge_threshold = kGoEdgeThreshold;         //!< [0, 1]
    float mix_brightness = 1.0f;                     //!< brightness scale of the RYB mix (MNPR 0.9) [0, 2]
    bool transparent_gaps = false;                   //!< gaps zero alpha instead of painting the substrate
    Border border = Border::Clamp;                   //!< taps outside the image
};

//! color: 4 ch; edges_ext: >= 1 ch (channel 0 = extended edges E_e), same size; ctrl_edge: >= 3 ch
//! (B = gaps/overlaps), same size; bleed: optional, 1 ch or 4 ch (alpha), full or half size (resampled,
//! clamp to edge). dst (re)allocated to color's size, 4 ch.
void gaps_overlaps(ImageF& dst, const ImageF& color, const ImageF& edges_ext, const ImageF& ctrl_edge,
                   const ImageF* bleed, glm::vec3 substrate, const GapsOverlapsParams& p,
                   const Exec& ex = {});

//! The stage's maths (the reference runs operator() per pixel), over the checked inputs: colour,
//! extended edges, the control's gaps/overlaps channel, the bleeding mask (a constant zero plane
//! without one) and its resampling to the colour's size.
struct GapsOverlapsKernel {
    View<const glm::vec4> c;
    toolkit::Plane e, ctrl, bleed;
    const toolkit::Resampler* up;
    int w, h;
    glm::vec3 substrate;
    GapsOverlapsParams p;
    Border b;

    float bleed_at(int x, int y) const {
        return up->sample(bleed, x, y);
    }

    //! The gradient's maths over lanes, written once (F = float for one pixel, simd::v8f for eight
    //! of a row): tap(dx, dy) is the extended edge at the neighbour (dx, dy); gu, gv the Sobel-like
    //! sums, len their length. Returns where it can be normalised (len > 1e-12 and finite): a bool,
    //! or a lane mask.
    template <class F, class Tap>
    static auto gradient_parts(Tap&& tap, F& gu, F& gv, F& len) {
        const F r = tap(1, 0), l = tap(-1, 0), d = tap(0, 1), u = tap(0, -1);
        const F tr = tap(1, -1), tl = tap(-1, -1), dr = tap(1, 1), dl = tap(-1, 1);
        gu = (r + 0.5f * (tr + dr)) - (l + 0.5f * (tl + dl));
        gv = (d + 0.5f * (dr + dl)) - (u + 0.5f * (tr + tl));
        len = lanes::root(gu * gu + gv * gv);
        if constexpr (std::is_same_v<F, float>) return len > 1e-12f && len < std::numeric_limits<float>::infinity();
        else return (len > 1e-12f) & (len < std::numeric_limits<float>::infinity());
    }

    //! Normalised gradient of the extended edges; false if it is zero or not finite.
    bool gradient(int x, int y, glm::vec2& g) const {
        float gu, gv, len;
        const bool usable = gradient_parts([&](int dx, int dy) { return e.at(x + dx, y + dy, b); }, gu, gv, len);
        if (!usable) return false;
        g = {gu / len, gv / len};
        return true;
    }

    glm::vec4 colour_at(float px, float py) const { return sample_bilinear(c, px, py, b); }

    glm::vec4 operator()(int x, int y) const {
        const glm::vec4 col = c(x, y);
        // The activity tests are a conjunction; the cheap ones first.
        if (!(col.w > p.alpha_threshold)) return col;
        const float ee = e(x, y);
        if (!(ee > p.edge_threshold)) return col;
        const float go = ctrl(x, y) * float(p.steps);
        if (!(go > kGoCtrlThreshold) && !(go < -kGoCtrlThreshold)) return col;
        if (!(bleed_at(x, y) < p.bleed_threshold)) return col;
        return paint(x, y, col, ee, go);
    }

    //! Eight pixels from x (x + 8 <= w): bit i set when pixel x + i passes the activity tests of
    //! operator() (the same comparisons of the same values, lane by lane), its go = ctrl * m in go.
    //! (The fast schedule's; gaps_overlaps.schedule.cpp.)
    unsigned active8(int x, int y, simd::v8f& ee, simd::v8f& go) const;
    //! Of the pixels x + i in `lanes`, those whose gap march (decide's) finds an edge: bit i set
    //! when pixel x + i is a gap. For pixels that passed the activity tests with go < -0.1 and
    //! ee <= 2/m, x >= 1, x + 9 <= w and 1 <= y < h - 1 (the gradient's taps inside the image).
    unsigned gaps8(int x, int y, unsigned lanes, simd::v8f go) const;

    //! What a gap writes in place of col.
    glm::vec4 gap_colour(const glm::vec4& col) const {
        return p.transparent_gaps ? glm::vec4(glm::vec3(col), 0.0f) : glm::vec4(substrate, col.w);
    }

    //! What paint gives a pixel: `value`, or (mix) the RYB mix of its colour with `with`.
    struct Painted {
        glm::vec4 value;
        bool mix = false;
        glm::vec3 with{};
    };

    //! A pixel that passed the activity tests: its edge ee and go = ctrl * m.
    glm::vec4 paint(int x, int y, glm::vec4 col, float ee, float go) const {
        const Painted d = decide(x, y, col, ee, go);
        return d.mix ? overlap_colour(col, d.with) : d.value;
    }

    //! An overlap: col mixed with the colour it meets, col's alpha.
    glm::vec4 overlap_colour(const glm::vec4& col, const glm::vec3& with) const {
        return {mix_ryb(glm::vec3(col), with, 0.5f, p.mix_brightness), col.w};
    }
    //! overlap_colour from the two colours' RYB amounts (rgb_to_ryb of glm::vec3(col) and with).
    glm::vec4 overlap_colour(const glm::vec4& col, const glm::vec3& with, const glm::vec3& col_ryb,
                             const glm::vec3& with_ryb) const {
        return {mix_ryb_converted(glm::vec3(col), with, col_ryb, with_ryb, 0.5f, p.mix_brightness), col.w};
    }

    //! paint without the RYB mix: an overlap returns what to mix col with.
    Painted decide(int x, int y, glm::vec4 col, float ee, float go) const {
        const float m = float(p.steps);
        const float cx = float(x) + 0.5f, cy = float(y) + 0.5f;
        if (go > kGoCtrlThreshold) {  // overlaps
            glm::vec2 g;
            if (!gradient(x, y, g)) return {col};
            for (int i = 1; i <= p.steps; ++i) {
                if (go < float(i)) return {col};  // not enough overlap parameter
                const glm::vec4 cn = colour_at(cx + float(i) * g.x, cy + float(i) * g.y);
                const glm::vec4 d = cn - col;
                if (std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z + d.w * d.w) > p.color_difference) {
                    if (length3(glm::vec3(cn) - substrate) < p.substrate_proximity) return {col};
                    return {col, true, glm::vec3(cn)};
                }
            }
            // The march reached m without meeting another colour: we sit on the edge itself and the
            // gradient points away from the neighbour, so mix with the pixel behind.
            const glm::vec4 cn = colour_at(cx - g.x, cy - g.y);
            return {col, true, glm::vec3(cn)};
        }
        if (go < -kGoCtrlThreshold) {  // gaps
            bool gap = ee > 2.0f / m;
            if (!gap) {
                glm::vec2 g;
                if (!gradient(x, y, g)) return {col};
                const float ag = -go;
                for (int i = 1; i <= p.steps; ++i) {
                    if (ag < float(i)) break;
                    if (sample_bilinear(e, cx + float(i) * g.x, cy + float(i) * g.y, b) > 1.0f / m) {
                        gap = true;
                        break;
                    }
                }
            }
            if (gap) return {gap_colour(col)};
        }
        return {col};
    }
};

//! The fast schedule (gaps_overlaps.schedule.cpp), which the stage runs for Traversal::Fast after
//! its checks with o allocated: the reference's bytes. ed: the one-channel extended edges (the
//! chunk test), or null. in_place: o is the colour's image (pixels without an edge are not written).
void gaps_overlaps_fast(const View<glm::vec4>& o, const GapsOverlapsKernel& k, const float* ed, bool in_place,
                        const Exec& ex);

void register_gaps_overlaps(Registry& r);

}  // namespace aq::stylize
