// stylize/stages/gaps_overlaps.cpp — WC18 Algorithm 1 (see gaps_overlaps.h). Each output pixel reads
// a neighbourhood of at most m+1 pixels of its inputs and writes only itself: reference and fast
// traversals are bit-exact. Marches are bounded by the integer parameter m, never by float->int
// conversions of image values; a zero or non-finite gradient leaves the pixel unchanged.
#include "stylize/stages/gaps_overlaps.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <vector>

#include "stylize/kernels.h"
#include "stylize/ryb.h"

namespace aq::stylize {

using namespace toolkit;

namespace {

struct GoKernel {
    View<const glm::vec4> c;
    Plane e, ctrl, bleed;
    const Resampler* up;
    int w, h;
    glm::vec3 substrate;
    GapsOverlapsParams p;
    Border b;

    float bleed_at(int x, int y) const {
        return up->sample(bleed, x, y);
    }

    //! Normalised gradient of the extended edges; false if it is zero or not finite.
    bool gradient(int x, int y, glm::vec2& g) const {
        const float r = e.at(x + 1, y, b), l = e.at(x - 1, y, b), d = e.at(x, y + 1, b), u = e.at(x, y - 1, b);
        const float tr = e.at(x + 1, y - 1, b), tl = e.at(x - 1, y - 1, b);
        const float dr = e.at(x + 1, y + 1, b), dl = e.at(x - 1, y + 1, b);
        const float gu = (r + 0.5f * (tr + dr)) - (l + 0.5f * (tl + dl));
        const float gv = (d + 0.5f * (dr + dl)) - (u + 0.5f * (tr + tl));
        const float len = std::sqrt(gu * gu + gv * gv);
        if (!(len > 1e-12f) || !std::isfinite(len)) return false;
        g = {gu / len, gv / len};
        return true;
    }

    glm::vec4 colour_at(float px, float py) const { return aq::stylize::sample_bilinear(c, px, py, b); }

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
    unsigned active8(int x, int y, v8f& ee, v8f& go) const {
        using simd::bits8;
        const Plane alpha{&c.data->w, 4, 4 * c.stride, c.width, c.height};  // c's fourth channel
        ee = plane8(e, x, y);
        go = plane8(ctrl, x, y) * float(p.steps);
        unsigned act = bits8(plane8(alpha, x, y) > p.alpha_threshold) & bits8(ee > p.edge_threshold) &
                       bits8((go > kGoCtrlThreshold) | (go < -kGoCtrlThreshold));
        if (act) act &= bits8(up->sample8(bleed, x, y) < p.bleed_threshold);
        return act;
    }

    //! Of the pixels x + i in `lanes`, those whose gap march (paint's, below) finds an edge: bit i
    //! set when pixel x + i is a gap. For pixels that passed the activity tests with go < -0.1 and
    //! ee <= 2/m, x >= 1, x + 9 <= w and 1 <= y < h - 1 (the gradient's taps inside the image).
    //! Lane by lane the operations of gradient() and of the scalar march; the march's bilinear taps
    //! gathered, a lane whose footprint leaves the image sampled by sample_bilinear (the border rule).
    unsigned gaps8(int x, int y, unsigned lanes, v8f go) const {
        using simd::bits8;
        using simd::v8i;
        auto at8 = [&](int dx, int dy) { return plane8(e, x + dx, y + dy); };
        const v8f r = at8(1, 0), l = at8(-1, 0), d = at8(0, 1), u = at8(0, -1);
        const v8f tr = at8(1, -1), tl = at8(-1, -1), dr = at8(1, 1), dl = at8(-1, 1);
        const v8f gu = (r + 0.5f * (tr + dr)) - (l + 0.5f * (tl + dl));
        const v8f gv = (d + 0.5f * (dr + dl)) - (u + 0.5f * (tr + tl));
        const v8f len = simd::sqrt8(gu * gu + gv * gv);
        lanes &= bits8((len > 1e-12f) & (len < std::numeric_limits<float>::infinity()));  // gradient()'s test
        const v8f gx = gu / len, gy = gv / len;
        const v8i iota = simd::kLaneIndex8;
        const v8f cx = (float(x) + __builtin_convertvector(iota, v8f)) + 0.5f;  // float(x + i) + 0.5f, exact
        const float cy = float(y) + 0.5f;
        const v8f ag = -go;
        const float above = 1.0f / float(p.steps);
        // The march's taps lie within steps + 1 rows of y: gathered relative to the first of them.
        const int ybase = std::max(0, y - p.steps - 1);
        const float* base = e.p + std::ptrdiff_t(ybase) * e.row;
        const int px = int(e.px), row = int(e.row);
        unsigned still = lanes, gap = 0;
        for (int i = 1; i <= p.steps; ++i) {
            still &= ~bits8(ag < float(i));  // not enough gap parameter
            if (!still) break;
            const v8i on = ((v8i{} + int(still)) >> iota & 1) != 0;
            const v8f sx = on ? cx + float(i) * gx : cx, sy = on ? cy + float(i) * gy : v8f{} + cy;
            // sample_bilinear(e, sx, sy, b) lane by lane
            const v8f fx = sx - 0.5f, fy = sy - 0.5f;
            const v8f x0f = simd::floor8(fx), y0f = simd::floor8(fy);
            const v8f tx = fx - x0f, ty = fy - y0f;
            const v8i x0 = __builtin_convertvector(x0f, v8i), y0 = __builtin_convertvector(y0f, v8i);
            const v8i inside = (x0 >= 0) & (x0 + 1 < w) & (y0 >= 0) & (y0 + 1 < h);
            const v8i idx = (on & inside) ? (y0 - ybase) * row + x0 * px : v8i{};
            const v8f a = simd::gather8(base, idx), c = simd::gather8(base, idx + px);
            const v8f dd = simd::gather8(base, idx + row), ed = simd::gather8(base, idx + row + px);
            const v8f top = a + (c - a) * tx;
            const v8f bot = dd + (ed - dd) * tx;
            v8f val = top + (bot - top) * ty;
            for (unsigned out = still & ~bits8(inside); out; out &= out - 1) {
                const int k = __builtin_ctz(out);
                val[k] = sample_bilinear(e, sx[k], sy[k], b);
            }
            const unsigned hit = still & bits8(val > above);
            gap |= hit;
            still &= ~hit;
        }
        return gap;
    }

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

//! Rows a pixel's taps reach: the march of up to `steps` pixels along the unit gradient (its
//! rounding can add a little), the bilinear footprint and the 3 x 3 gradient one more each.
int gaps_overlaps_reach(const GapsOverlapsParams& p) { return p.steps + 2; }

//! The fast schedule: a pixel whose extended edge is not above the threshold (NaN included) is
//! its colour, the kernel's second test: 64-pixel chunks without such an edge (the background) are
//! copied whole, their one-channel edges tested eight at a time. In place those chunks are not
//! touched, and the chunks with an edge are computed first, the pixels whose value changes kept
//! per row (their x and value: most active pixels fail a later test and keep their colour) and
//! written once every row is done (write_later).
struct GoFast {
    static constexpr int kChunk = 64;
    struct RowValues {
        std::vector<int> xs;
        std::vector<glm::vec4> values;
    };
    //! A row's overlaps, mixed together at its end: their colours' RYB inverses (most of an
    //! overlap's cost, 2 to 12 Gauss-Newton steps each) four at a time (rgb_to_ryb_many).
    struct Overlaps {
        std::vector<int> xs;
        std::vector<glm::vec3> rgb, ryb;  // per overlap: the pixel's colour, then the one it meets
    };

    const GoKernel& k;
    View<glm::vec4> o;
    const float* ed;  //!< the one-channel edges, or null (the chunk test is skipped)
    bool in_place;
    std::vector<RowValues> later;  //!< in place: per row, the changed pixels

    //! Pixel x of row y gets v: written, or in place kept for later when it changes, bit for bit.
    void put(int x, int y, const glm::vec4& v) {
        if (!in_place) {
            o(x, y) = v;
        } else if (std::memcmp(&v, &k.c(x, y), sizeof v) != 0) {
            RowValues& r = later[std::size_t(y)];
            r.xs.push_back(x);
            r.values.push_back(v);
        }
    }

    //! Pixels [xs, xe) of row y, a chunk with an edge: the activity tests eight pixels at a time;
    //! the pixels that pass are painted one by one, overlaps decided here (into ov) and mixed at
    //! the row's end. Gaps that need a march (not direct edges) are marched eight at a time where
    //! the gradient's taps are inside the image.
    void chunk(int y, int xs, int xe, Overlaps& ov) {
        const int w = k.w, h = k.h;
        const bool rows_inside = y >= 1 && y + 1 < h;
        const float direct = 2.0f / float(k.p.steps);
        int x = xs;
        for (; x + 8 <= xe; x += 8) {
            v8f ee, go;
            unsigned act = k.active8(x, y, ee, go);
            if (!in_place) std::memcpy(&o(x, y), &k.c(x, y), 8 * sizeof(glm::vec4));
            if (!act) continue;
            if (rows_inside && x >= 1 && x + 9 <= w) {
                const unsigned march = act & simd::bits8(go < -kGoCtrlThreshold) & ~simd::bits8(ee > direct);
                if (march) {
                    for (unsigned g = k.gaps8(x, y, march, go); g; g &= g - 1) {
                        const int i = __builtin_ctz(g);
                        put(x + i, y, k.gap_colour(k.c(x + i, y)));
                    }
                    act &= ~march;  // the others keep their colour
                }
            }
            for (; act; act &= act - 1) {
                const int i = __builtin_ctz(act);
                const glm::vec4 col = k.c(x + i, y);
                const GoKernel::Painted d = k.decide(x + i, y, col, ee[i], go[i]);
                if (!d.mix) {
                    put(x + i, y, d.value);
                    continue;
                }
                ov.xs.push_back(x + i);
                ov.rgb.push_back(glm::vec3(col));
                ov.rgb.push_back(d.with);
            }
        }
        for (; x < xe; ++x) put(x, y, k(x, y));
    }

    //! Pixels [x0, x1) of row y: background chunks copied (or untouched in place), the others
    //! computed, then the row's overlaps mixed.
    void row(int y, int x0, int x1) {
        thread_local Overlaps ov;
        ov.xs.clear();
        ov.rgb.clear();
        for (int xs = x0; xs < x1; xs += kChunk) {
            const int xe = std::min(x1, xs + kChunk);
            if (ed && !any_above(ed + std::size_t(y) * k.w + xs, std::size_t(xe - xs), k.p.edge_threshold)) {
                if (!in_place) stream_copy(&o(xs, y).x, &k.c(xs, y).x, 4 * std::size_t(xe - xs));
                continue;
            }
            chunk(y, xs, xe, ov);
        }
        ov.ryb.resize(ov.rgb.size());
        rgb_to_ryb_many(ov.rgb.data(), ov.ryb.data(), ov.rgb.size());
        for (std::size_t i = 0; i < ov.xs.size(); ++i) {
            const int x = ov.xs[i];
            put(x, y, k.overlap_colour(k.c(x, y), ov.rgb[2 * i + 1], ov.ryb[2 * i], ov.ryb[2 * i + 1]));
        }
        if (!in_place) stream_fence();  // the copied chunks' non-temporal stores, before the row is done
    }

    //! In place, after every row: the changed pixels written.
    void write_later(const Exec& ex) {
        for_each_row(ex, k.w, k.h, [&](int y, int, int) {
            const RowValues& r = later[std::size_t(y)];
            for (std::size_t i = 0; i < r.xs.size(); ++i) o(r.xs[i], y) = r.values[i];
        });
    }
};

}  // namespace

void gaps_overlaps(ImageF& dst, const ImageF& color, const ImageF& edges_ext, const ImageF& ctrl_edge,
                   const ImageF* bleed, glm::vec3 substrate, const GapsOverlapsParams& p,  const Exec& ex) {
    const std::string st = "gaps_overlaps/wc18";
    check_input(&color, 4, Channels::Exactly, st, "color");
    check_input(&edges_ext, 1, Channels::AtLeast, st, "edges");
    check_same_size(edges_ext, color, st, "edges", "color");
    check_input(&ctrl_edge, 3, Channels::AtLeast, st, "ctrl_edge");
    check_same_size(ctrl_edge, color, st, "ctrl_edge", "color");
    check_bleed_mask(bleed, color, st);
    if (p.steps < 1 || p.steps > 16) throw Error(st + ": steps must be in [1, 16]");
    check_not_alias(dst, &edges_ext, st, "edges");
    check_not_alias(dst, &ctrl_edge, st, "ctrl_edge");
    check_not_alias(dst, bleed, st, "bleed");
    // In place (dst is color: StageVariant::in_place_input): a pixel reads its neighbours' colours
    // (the overlap march), so nothing is written until every changed pixel is computed from the
    // unchanged image; pixels without an edge are not written at all.
    const bool in_place = &dst == &color;
    const int w = color.width(), h = color.height();
    ensure_output(dst, w, h, 4);
    static const float kZero = 0.0f;
    const Resampler up = bleed ? Resampler(w, h, bleed->width(), bleed->height()) : Resampler(w, h, w, h);
    const GoKernel k{color.view<glm::vec4>(),
                     plane(edges_ext, 0),
                     plane(ctrl_edge, control::kEdgeTransition.channel),
                     bleed ? plane(*bleed, bleed->channels() == 4 ? 3 : 0) : constant_plane(&kZero, w, h),
                     &up,
                     w,
                     h,
                     substrate,
                     p,
                     p.border};
    const View<glm::vec4> o = dst.view<glm::vec4>();
    if (ex.traversal == Traversal::Reference) {  // the kernel pixel by pixel
        if (in_place) {  // on a copy of the colour: every pixel reads the unchanged image
            const ImageF before = color;
            GoKernel kc = k;
            kc.c = before.view<glm::vec4>();
            plain_loop(w, h, [&](int x, int y) { o(x, y) = kc(x, y); });
            return;
        }
        plain_loop(w, h, [&](int x, int y) { o(x, y) = k(x, y); });
        return;
    }
    GoFast fast{.k = k,
                .o = o,
                .ed = edges_ext.channels() == 1 ? edges_ext.data() : nullptr,
                .in_place = in_place,
                .later = std::vector<GoFast::RowValues>(in_place ? std::size_t(h) : 0)};
    for_each_row(ex, w, h, [&](int y, int x0, int x1) { fast.row(y, x0, x1); });
    if (in_place) fast.write_later(ex);
}

void register_gaps_overlaps(Registry& r) {
    using P = GapsOverlapsParams;
    static const ParamTable<P> t = ParamTable<P>()
        .i("steps", &P::steps, 1, 16, "m: widest gap/overlap in pixels (WC18 5); p = ctrl.edge.b * m")
        .f("color_difference", &P::color_difference, 0, 2, "RGBA distance that ends the march (MNPR 0.33)")
        .f("substrate_proximity", &P::substrate_proximity, 0, 2, "no overlap with colours this close to the substrate (MNPR 0.1)")
        .f("alpha_threshold", &P::alpha_threshold, 0, 1, "only pixels with alpha above (MNPR 0.1)")
        .f("bleed_threshold", &P::bleed_threshold, 0, 1, "only pixels with bleeding mask below (MNPR 0.01)")
        .f("edge_threshold", &P::edge_threshold, 0, 1, "only pixels with extended edge above (MNPR 0.1, WC18 0.2)")
        .f("mix_brightness", &P::mix_brightness, 0, 2, "brightness scale of the RYB mix (1 preserves; MNPR 0.9)")
        .b("transparent_gaps", &P::transparent_gaps, "gaps zero alpha instead of painting the substrate colour")
        .border(&P::border);
    r.add(declare({.stage = "gaps_overlaps",
                   .variant = "wc18",
                   .doc = "WC18 Algorithm 1: march along the extended-edge gradient; overlaps mix in RYB, gaps show the substrate",
                   .inputs = {{"color", target::kColor, 4, false},
                              {"edges", "edges.extended", 1, false},
                              {"ctrl_edge", target::kCtrlEdge, 4, false},
                              {"bleed", "bleed", 4, true}},
                   .outputs = {{"color", "color.gaps_overlaps", 4, false}},
                   .reference = StageVariant::Reference::SharedMaths,
                   .in_place_input = "color",  // pixels without an edge are left as they are
                   .in_place_output = "color",
                   .row_halo = [](const ParamValues& pv) { return gaps_overlaps_reach(t.from(pv)); }},
                  t, [](StageIO& io, const P& p, const Exec& ex) {
                      gaps_overlaps(*io.out[0], *io.in[0], *io.in[1], *io.in[2], io.in.size() > 3 ? io.in[3] : nullptr,
                                    globals_of(io).substrate_color, p, ex);
                  }));
}

}  // namespace aq::stylize
