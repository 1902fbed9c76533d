// stylize/stages/bleed.cpp — colour bleeding (WC16 naive, WC17 Algorithm 1, MNPR colorBleeding).
//
// Data flow: the inputs are de-interleaved (or, at half resolution, bilinearly resampled with the
// convention of kernels.h texel_coord) into planes R, G, B, C (bleeding control) and Z, then a
// horizontal and a vertical 1-D pass run, each computing per output pixel
//   acc_p = s_p;  for a = -r..r (ascending): acc_p = acc_p + W[a] * (bleed(a) ? d_p - s_p : 0)
// for p in {R, G, B, C}. The reference traversal does exactly that per pixel with border-resolved
// taps. The fast traversal runs the same expression in the same order per pixel, but over rows:
// padded row copies (H) or row pointers (V), eight pixels per register with the taps innermost
// (the sums stay in registers), oneTBB row blocks, and rows (or 128-pixel column chunks of a
// row) whose tap window holds no positive control are written as s + 0 (what the full sum
// yields bit for bit when every delta is zero: it only turns -0 into +0). Hence fast ==
// reference bit for bit. This file: the checks, the planes, the reference passes and the
// declarations; the fast passes are bleed.schedule.cpp.
#include "stylize/stages/bleed.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "stylize/kernels.h"

namespace aq::stylize {

namespace {

// ---- reference: per pixel, taps through the border rule --------------------------------------
template <BleedRule R>
void pass_reference(const BleedPlanes& in, const std::vector<float>& ctrl, const std::vector<float>& z, BleedPlanes& out,
                    bool horizontal, const BleedKernel& k, Border border) {
    const int w = in.w, h = in.h;
    const int nacc = R == BleedRule::Naive ? 3 : 4;  // naive: the mask is not blurred
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t si = std::size_t(y) * w + x;
            const float cs = ctrl[si], zs = z[si];
            float acc[4], s[4];
            for (int p = 0; p < 4; ++p) s[p] = acc[p] = (p < 3 ? in.p[p][si] : ctrl[si]);
            for (int a = -k.r; a <= k.r; ++a) {
                const std::size_t di = horizontal ? std::size_t(y) * w + resolve_border(x + a, w, border)
                                                  : std::size_t(resolve_border(y + a, h, border)) * w + x;
                const bool b = bleeds<R>(cs, ctrl[di], zs - k.t, z[di], k.scope[a + k.r]);
                const float wa = k.w[a + k.r];
                for (int p = 0; p < nacc; ++p) {
                    const float d = p < 3 ? in.p[p][di] : ctrl[di];
                    acc[p] = acc[p] + wa * (b ? d - s[p] : 0.0f);
                }
            }
            for (int p = 0; p < 4; ++p) out.p[p][si] = acc[p];
        }
}

//! The reference of the two passes: src -> tmp (horizontal) -> dst (vertical).
template <BleedRule R>
void passes_reference(const BleedPlanes& src, BleedPlanes& tmp, BleedPlanes& dst, const BleedKernel& k, Border border) {
    pass_reference<R>(src, src.p[3], src.p[4], tmp, true, k, border);
    pass_reference<R>(tmp, tmp.p[3], src.p[4], dst, false, k, border);
}

}  // namespace

void bleed(ImageF& dst, const ImageF& color, const ImageF& depth, const ImageF& ctrl, BleedRule rule,
           const BleedParams& p, const Exec& ex) {
    const bool need_depth = rule != BleedRule::Naive;
    toolkit::check_input(&color, 4, toolkit::Channels::Exactly, "bleed", "color");
    toolkit::check_input(&ctrl, 4, toolkit::Channels::Exactly, "bleed", "ctrl_abstraction");
    toolkit::check_same_size(ctrl, color, "bleed", "ctrl_abstraction", "color");
    if (need_depth || !depth.empty()) {
        toolkit::check_input(&depth, 1, toolkit::Channels::Exactly, "bleed", "depth");
        toolkit::check_same_size(depth, color, "bleed", "depth", "color");
    }
    if (p.radius < 1 || p.radius > 40) throw Error("bleed: radius must be in [1, 40]");
    if (!(p.sigma > 0.0f)) throw Error("bleed: sigma must be > 0");
    const int w = color.width(), h = color.height();
    const int wr = p.half_res ? half_size(w) : w, hr = p.half_res ? half_size(h) : h;

    // Scratch planes reused by the calling thread across calls (never shared between threads).
    // (Bound to references: a lambda body naming a thread_local would use the worker's instance.)
    thread_local BleedPlanes tl_src, tl_tmp, tl_out;
    BleedPlanes& src = tl_src;
    BleedPlanes& tmp = tl_tmp;
    BleedPlanes& out = tl_out;
    src.alloc(wr, hr, 5);
    const std::size_t kc = control::kAbstractionBleeding.channel;  // ctrl.abstraction.b = bleeding (spec §1)
    if (p.half_res) {
        // Half resolution: each plane row resampled straight from the full-size inputs
        // (toolkit::RowResampler, the convention of toolkit::resample: the same values), the colour
        // row through a small buffer: no half-size interleaved images written and read back. Where
        // both sizes are even (every axis halves exactly) the fast traversal does the same
        // operations eight outputs at a time (halve_into_planes); the tabled rows are its reference.
        const toolkit::ResampleAxis ax(wr, w), ay(hr, h);
        if (ax.pairs && ay.pairs && ex.traversal != Traversal::Reference) {
            bleed_halve_into_planes(src, color.data(), ctrl.data(), depth.empty() ? nullptr : depth.data(), w, ax, ay, ex);
        } else {
            toolkit::for_each_row_block(ex, hr, [&](int y0, int y1) {
                toolkit::RowResampler<4> uc(color.data(), w, wr, ax, ay);
                toolkit::RowResampler<1, 4> uk(ctrl.data() + kc, w, wr, ax, ay);
                std::optional<toolkit::RowResampler<1>> uz;
                if (!depth.empty()) uz.emplace(depth.data(), w, wr, ax, ay);
                std::vector<float> row(std::size_t(wr) * 4);
                for (int y = y0; y < y1; ++y) {
                    const std::size_t r0 = std::size_t(y) * wr;
                    uc.row(y, row.data());
                    for (std::size_t x = 0; x < std::size_t(wr); ++x) {
                        src.p[0][r0 + x] = row[4 * x];
                        src.p[1][r0 + x] = row[4 * x + 1];
                        src.p[2][r0 + x] = row[4 * x + 2];
                    }
                    uk.row(y, src.p[3].data() + r0);
                    if (uz) uz->row(y, src.p[4].data() + r0);
                    else std::fill_n(src.p[4].data() + r0, wr, 0.0f);
                }
            });
        }
    } else {
        const float* cd = color.data();
        const float* kd = ctrl.data() + kc;
        const float* zd = depth.empty() ? nullptr : depth.data();
        toolkit::for_each_row_block(ex, hr, [&](int y0, int y1) {
            for (std::size_t i = std::size_t(y0) * wr; i < std::size_t(y1) * wr; ++i) {
                src.p[0][i] = cd[4 * i];
                src.p[1][i] = cd[4 * i + 1];
                src.p[2][i] = cd[4 * i + 2];
                src.p[3][i] = kd[4 * i];
                src.p[4][i] = zd ? zd[i] : 0.0f;
            }
        });
    }
    BleedKernel k;
    k.r = p.radius;
    k.w = gaussian_weights(p.radius, p.sigma);
    k.t = p.depth_threshold;
    k.scope.resize(k.w.size());
    for (int a = -k.r; a <= k.r; ++a) k.scope[std::size_t(a + k.r)] = float(std::abs(a)) / float(k.r);

    tmp.alloc(wr, hr, 4);
    out.alloc(wr, hr, 4);
    if (ex.traversal != Traversal::Reference) {
        bleed_passes_fast(rule, src, tmp, out, k, p.border, ex);
    } else {
        switch (rule) {
            case BleedRule::Naive: passes_reference<BleedRule::Naive>(src, tmp, out, k, p.border); break;
            case BleedRule::JointBilateral: passes_reference<BleedRule::JointBilateral>(src, tmp, out, k, p.border); break;
            case BleedRule::Mnpr: passes_reference<BleedRule::Mnpr>(src, tmp, out, k, p.border); break;
        }
    }
    toolkit::ensure_output(dst, wr, hr, 4);
    float* o = dst.data();
    toolkit::for_each_row_block(ex, hr, [&](int y0, int y1) {
        for (std::size_t i = std::size_t(y0) * wr; i < std::size_t(y1) * wr; ++i)
            for (int c = 0; c < 4; ++c) o[4 * i + c] = out.p[c][i];
    });
}

namespace {
void add_bleed(Registry& r, const char* variant, BleedRule rule, bool half_default, bool sigma_param, const char* doc) {
    using P = BleedParams;
    ParamTable<P> t;
    t.i("radius", &P::radius, 1, 40, "kernel radius r, taps = 2r + 1 (WC17: 21 taps)");
    if (sigma_param) t.f("sigma", &P::sigma, 0.1, 100, "Gaussian sigma (WC17: 20)");
    if (rule != BleedRule::Naive) t.f("depth_threshold", &P::depth_threshold, 0, 1, "T on normalised depth (MNPR 0.0002)");
    t.b("half_res", &P::half_res, "run at half resolution (WC17 as published)");
    t.border(&P::border);
    std::vector<Port> inputs = {{"color", "color.density", 4, false}};
    if (rule != BleedRule::Naive) inputs.push_back({"depth", "depth", 1, false, SizeRule::Same, "color"});
    inputs.push_back({"ctrl_abstraction", target::kCtrlAbstraction, 4, false, SizeRule::Same, "color"});
    StageVariant v = declare({.stage = "bleed",
                              .variant = variant,
                              .doc = doc,
                              .inputs = inputs,
                              .outputs = {{"bleed", "bleed", 4, false}},
                              .reference = StageVariant::Reference::PlainLoop},
                             t, [rule, sigma_param](StageIO& io, P p, const Exec& ex) {
                                 if (!sigma_param) p.sigma = 2.0f * float(p.radius);  // MNPR: sigma = 2r
                                 static const ImageF kNoDepth;
                                 const bool naive = rule == BleedRule::Naive;
                                 bleed(*io.out[0], *io.in[0], naive ? kNoDepth : *io.in[1], *io.in[naive ? 1 : 2], rule, p, ex);
                             });
    for (auto& d : v.params)
        if (d.name == "half_res") d.def = half_default ? 1.0 : 0.0;
    r.add(std::move(v));
}
}  // namespace

void register_bleed(Registry& r) {
    add_bleed(r, "naive", BleedRule::Naive, false, true,
              "WC16: 21x21 separable Gaussian (sigma 20) of the whole colour image, mask = painted control");
    add_bleed(r, "joint_bilateral", BleedRule::JointBilateral, true, true,
              "WC17 Algorithm 1: 21 taps sigma 20, depth threshold, two rules, H pass expands the mask; half res");
    add_bleed(r, "mnpr", BleedRule::Mnpr, false, false,
              "MNPR colorBleeding: full res, r = 10, sigma = 2r, tap a when max(ctrl_d, ctrl_s) >= |a|/r");
}

}  // namespace aq::stylize
