// raster/setup.cpp — homogeneous clipping (near, far, guard band) and fixed-point triangle setup.
#include "raster/setup.h"

#include <algorithm>
#include <bit>
#include <climits>
#include <cmath>
#include <cstddef>

#ifdef __AVX2__
#include <immintrin.h>
#endif

#include "core/image.h"

namespace aq::raster {

// TriSetup's pixel bounds are 16-bit: every raster grid is at most kMaxImageSide wide and high
// (make_frame checks it).
static_assert(kMaxImageSide - 1 <= INT16_MAX);

namespace {

constexpr std::int64_t kSmallTrianglePixels = 4;

template <class T>
inline T min3(T a, T b, T c) { return std::min(a, std::min(b, c)); }
template <class T>
inline T max3(T a, T b, T c) { return std::max(a, std::max(b, c)); }

// The snapped bounds of a triangle hold a pixel centre (c = 256 p + 128, xmin <= c <= xmax): the
// quick reject of setup_one and of the batch pre-pass (build() computes the clamped bounds).
inline bool bounds_hold_centre(const SnapVertex& a, const SnapVertex& b, const SnapVertex& c) {
    const std::int32_t xmin = min3(a.x, b.x, c.x), xmax = max3(a.x, b.x, c.x);
    const std::int32_t ymin = min3(a.y, b.y, c.y), ymax = max3(a.y, b.y, c.y);
    return (((xmin + kSubpixelOne / 2 - 1) >> kSubpixelBits) <= ((xmax - kSubpixelOne / 2) >> kSubpixelBits)) &
           (((ymin + kSubpixelOne / 2 - 1) >> kSubpixelBits) <= ((ymax - kSubpixelOne / 2) >> kSubpixelBits));
}

// Builds the setup of one snapped triangle; returns false when it covers no pixel centre, is
// degenerate after snapping or is culled. beta: original weights of the three vertices (clip
// path) or null (fast path, identity).
[[gnu::always_inline]] inline bool build(const SnapVertex (&sv)[3], const glm::vec3* beta, const Viewport& vp,
           const SetupOptions& opt, bool double_sided, TriSetup& t, ClipVerts& cv) {
    std::int64_t x[3] = {sv[0].x, sv[1].x, sv[2].x};
    std::int64_t y[3] = {sv[0].y, sv[1].y, sv[2].y};
    // Pixel bounds first (cheap, rejects most sub-pixel triangles): centres c = 256 p + 128 with
    // xmin <= c <= xmax.
    const std::int64_t xmin = min3(x[0], x[1], x[2]), xmax = max3(x[0], x[1], x[2]);
    const std::int64_t ymin = min3(y[0], y[1], y[2]), ymax = max3(y[0], y[1], y[2]);
    t.cover = std::uint8_t(cover_bits(xmin, xmax, ymin, ymax));
    std::int64_t px0 = (xmin - kSubpixelOne / 2 + kSubpixelOne - 1) >> kSubpixelBits;
    std::int64_t px1 = (xmax - kSubpixelOne / 2) >> kSubpixelBits;
    std::int64_t py0 = (ymin - kSubpixelOne / 2 + kSubpixelOne - 1) >> kSubpixelBits;
    std::int64_t py1 = (ymax - kSubpixelOne / 2) >> kSubpixelBits;
    px0 = std::max<std::int64_t>(px0, 0);
    py0 = std::max<std::int64_t>(py0, 0);
    px1 = std::min<std::int64_t>(px1, vp.width - 1);
    py1 = std::min<std::int64_t>(py1, vp.height - 1);
    // No pixel centre: dropped, or kept for the coverage pass when a centre is within a pixel
    // (the samples lie within 3/8 px of a centre).
    bool subpixel = px0 > px1 || py0 > py1;
    if (subpixel && !(opt.keep_subpixel && px0 <= px1 + 1 && py0 <= py1 + 1)) return false;
    const std::int64_t area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
    if (area == 0) return false;  // degenerate after snapping
    // y-down screen: counter-clockwise in NDC (glTF front face) has negative area here.
    const bool back = area > 0;
    if (back && opt.cull_backfaces && !double_sided) return false;
    // Sub-pixel triangles are kept for the silhouettes' samples: a closed mesh's silhouette is
    // covered by its front faces alone (a ray that hits it enters through one), so a single-sided
    // back face adds nothing there.
    if (subpixel && back && !double_sided) return false;
    int order[3] = {0, 1, 2};
    if (area < 0) {
        order[1] = 2;
        order[2] = 1;
    }
    std::int64_t X[3], Y[3];
    for (int j = 0; j < 3; ++j) {
        X[j] = x[order[j]];
        Y[j] = y[order[j]];
    }
    set_edges(X, Y, t);
    t.x0 = std::int16_t(px0);
    t.x1 = std::int16_t(px1);
    t.y0 = std::int16_t(py0);
    t.y1 = std::int16_t(py1);
    // Small-triangle fast path: most triangles of dense meshes cover at most a few pixel centres
    // of their bounds; a triangle that covers none is dropped here instead of being binned.
    if (!subpixel && (px1 - px0 + 1) * (py1 - py0 + 1) <= kSmallTrianglePixels) {
        bool any = false;
        for (int py = t.y0; py <= t.y1 && !any; ++py)
            for (int px = t.x0; px <= t.x1 && !any; ++px) {
                std::int64_t e[3];
                edge_values(t, px, py, e);
                any = inside(t, e);
            }
        if (!any && (!opt.keep_subpixel || (back && !double_sided))) return false;  // as above
        subpixel = !any;
    }
    for (int j = 0; j < 3; ++j) {
        t.inv_w[j] = sv[order[j]].inv_w;
        t.depth[j] = sv[order[j]].depth;
        if (beta) cv.beta[j] = beta[order[j]];
    }
    t.flags |= std::uint8_t((order[1] == 2 ? TriSetup::kPermBit : 0u) | (back ? TriSetup::kBackBit : 0u) |
                            (subpixel ? TriSetup::kSubpixelBit : 0u));
    return true;
}

struct ClipVertex {
    glm::dvec4 c;
    glm::dvec3 beta;
    double depth;
};

double plane_dist(const ClipVertex& v, int plane, const Viewport& vp) {
    const glm::dvec4& c = v.c;
    switch (plane) {
        case 0: return c.z + c.w;             // near
        case 1: return c.w - c.z;             // far
        case 2: return c.x + vp.gb_x * c.w;   // left
        case 3: return vp.gb_x * c.w - c.x;   // right
        case 4: return c.y + vp.gb_y * c.w;   // bottom
        default: return vp.gb_y * c.w - c.y;  // top
    }
}

// Sutherland-Hodgman against one plane. Intersections are always computed from the inside vertex
// towards the outside one, so the two triangles sharing an edge get the identical new vertex.
int clip_plane(const ClipVertex* in, int n, ClipVertex* out, int plane, const Viewport& vp) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
        const ClipVertex& p = in[i];
        const ClipVertex& q = in[(i + 1) % n];
        const double dp = plane_dist(p, plane, vp), dq = plane_dist(q, plane, vp);
        const bool pin = dp >= 0, qin = dq >= 0;
        if (pin) out[m++] = p;
        if (pin != qin) {
            const ClipVertex& a = pin ? p : q;  // inside
            const ClipVertex& b = pin ? q : p;  // outside
            const double da = pin ? dp : dq, db = pin ? dq : dp;
            const double s = da / (da - db);
            ClipVertex r;
            r.c = a.c + (b.c - a.c) * s;
            r.beta = a.beta + (b.beta - a.beta) * s;
            r.depth = a.depth + (b.depth - a.depth) * s;
            out[m++] = r;
        }
    }
    return m;
}

// The clip path (rare), out of line so that the fast path does not pay for its buffers.
[[gnu::noinline]] void setup_clipped(const DrawVertices& dv, std::uint32_t draw_index, std::uint32_t i0,
                                     std::uint32_t i1, std::uint32_t i2, std::uint32_t planes,
                                     const Viewport& vp, const SetupOptions& opt, std::vector<TriSetup>& out,
                                     std::vector<ClipVerts>& clip_out, SetupCounters& counters) {
    const bool double_sided = dv.mat->double_sided;
    TriSetup t;
    t.draw = draw_index;
    t.v[0] = i0, t.v[1] = i1, t.v[2] = i2;
    ClipVerts cv;
    // Clip path (rare): polygon of at most 3 + 6 vertices.
    ++counters.clipped;
    ClipVertex bufA[12], bufB[12];
    const std::uint32_t ids[3] = {i0, i1, i2};
    for (int j = 0; j < 3; ++j) {
        bufA[j].c = glm::dvec4(dv.clip[ids[j]]);
        bufA[j].beta = glm::dvec3(j == 0, j == 1, j == 2);
        bufA[j].depth = -double(dv.view[ids[j]].pos.z);
    }
    int n = 3;
    ClipVertex* cur = bufA;
    ClipVertex* nxt = bufB;
    for (int pl = 0; pl < 6 && n >= 3; ++pl) {
        if (!(planes & (1u << pl))) continue;
        n = clip_plane(cur, n, nxt, pl, vp);
        std::swap(cur, nxt);
    }
    if (n < 3) return;
    SnapVertex sv[12];
    glm::vec3 beta[12];
    for (int j = 0; j < n; ++j) {
        const glm::vec4 c(cur[j].c);
        const float depth = float(cur[j].depth);
        const bool ok = std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z) &&
                        std::isfinite(c.w) && c.w > 0.0f && std::isfinite(depth) &&
                        std::abs(double(c.x) / c.w) <= 2.0 * vp.gb_x &&
                        std::abs(double(c.y) / c.w) <= 2.0 * vp.gb_y;
        if (!ok) {
            ++counters.clip_unstable;
            return;
        }
        sv[j] = snap_vertex(c, depth, vp);
        beta[j] = glm::vec3(cur[j].beta);
    }
    for (int j = 1; j + 1 < n; ++j) {
        const SnapVertex tv[3] = {sv[0], sv[j], sv[j + 1]};
        const glm::vec3 tb[3] = {beta[0], beta[j], beta[j + 1]};
        TriSetup s = t;
        if (build(tv, tb, vp, opt, double_sided, s, cv)) {
            s.clip = std::int32_t(clip_out.size());
            clip_out.push_back(cv);
            out.push_back(s);
        }
    }
}

// The setup of one triangle (setup_triangle's definition; setup_triangles inlines it).
[[gnu::always_inline]] inline void setup_one(const DrawVertices& dv, std::uint32_t draw_index, std::uint32_t tri,
                                             const Viewport& vp, const SetupOptions& opt, std::vector<TriSetup>& out,
                                             std::vector<ClipVerts>& clip_out, SetupCounters& counters) {
    const auto& idx = dv.prim->indices;
    const std::uint32_t i0 = idx[3 * std::size_t(tri)], i1 = idx[3 * std::size_t(tri) + 1],
                        i2 = idx[3 * std::size_t(tri) + 2];
    const std::size_t nv = dv.clip.size();
    if (i0 >= nv || i1 >= nv || i2 >= nv) {
        ++counters.bad_index;
        return;
    }
    const SnapVertex& s0 = dv.snap[i0];
    const SnapVertex& s1 = dv.snap[i1];
    const SnapVertex& s2 = dv.snap[i2];
    const std::uint32_t c0 = s0.code, c1 = s1.code, c2 = s2.code;
    const bool double_sided = dv.mat->double_sided;
    if ((c0 | c1 | c2) & kOutNonFinite) {
        ++counters.non_finite;
        return;
    }
    if (c0 & c1 & c2) return;  // entirely outside one plane
    if ((c0 | c1 | c2) == 0) {
        ClipVerts unused;
        const SnapVertex sv[3] = {s0, s1, s2};
        // Quick reject of triangles whose bounds hold no pixel centre (most of a dense mesh),
        // before anything is written; build() repeats the exact computation.
        if (!opt.keep_subpixel && !bounds_hold_centre(s0, s1, s2)) return;
        // Built in place, uninitialised (build() writes every field it keeps): a stack copy
        // re-read right after its narrow stores stalls on store forwarding. Dropped on reject.
        TriSetup& t = out.emplace_back(TriSetup::NoInit{});
        t.draw = draw_index;
        t.v[0] = i0, t.v[1] = i1, t.v[2] = i2;
        t.clip = -1;
        if (!build(sv, nullptr, vp, opt, double_sided, t, unused)) out.pop_back();
        return;
    }
    setup_clipped(dv, draw_index, i0, i1, i2, c0 | c1 | c2, vp, opt, out, clip_out, counters);
}

// A triangle the batch pre-pass must hand to setup_one: any vertex index out of range, any vertex
// outside a clip plane or non-finite (setup_one counts, clips or drops it), or bounds that hold a
// pixel centre. False only for triangles setup_one drops without a trace (the quick reject).
[[gnu::always_inline]] inline bool needs_setup(const SnapVertex* snap, std::size_t nv, const std::uint32_t* ix) {
    const bool bad = (ix[0] >= nv) | (ix[1] >= nv) | (ix[2] >= nv);
    const SnapVertex& s0 = snap[bad ? 0 : ix[0]];
    const SnapVertex& s1 = snap[bad ? 0 : ix[1]];
    const SnapVertex& s2 = snap[bad ? 0 : ix[2]];
    return bad | ((s0.code | s1.code | s2.code) != 0) | bounds_hold_centre(s0, s1, s2);
}

#ifdef __AVX2__
// setup_one's quick reject and build()'s first checks for 8 triangles per register (schedule only,
// issue 13 item 5): a lane is set when setup_one surely drops its triangle without a trace — valid
// indices and every outcode 0 (its fast path), and bounds that hold no pixel centre, or (for a
// snapped extent below kVectorExtent, 64 px, in x and y, where the products fit int32 exactly:
// deltas < 2^14, centre offsets < 2^15) empty clamped bounds, zero area, a culled back face, or
// bounds of at most kSmallTrianglePixels holding no pixel centre inside (top-left rule). The
// others are left to setup_one. Every value is the scalar one: the edge function is evaluated in the exact form
// dx (sy - Ya) - dy (sx - Xa) = A sx + B sy + C.
constexpr std::int32_t kVectorExtent = 1 << 14;
static_assert(sizeof(SnapVertex) == 5 * sizeof(std::int32_t) && offsetof(SnapVertex, x) == 0 &&
              offsetof(SnapVertex, y) == 4 && offsetof(SnapVertex, code) == 8);

// x, y and code of the vertices v[0..7] (valid indices) in lanes: one 16-byte load per vertex
// (x, y, code, inv_w), transposed.
inline void load_xy_code8(const SnapVertex* snap, __m256i v, __m256i& x, __m256i& y, __m256i& code) {
    alignas(32) std::int32_t vi[8];
    _mm256_store_si256(reinterpret_cast<__m256i*>(vi), v);
    auto row = [&](int l) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(snap + vi[l])); };
    auto pair = [&](int l) { return _mm256_inserti128_si256(_mm256_castsi128_si256(row(l)), row(l + 4), 1); };
    const __m256i m0 = pair(0), m1 = pair(1), m2 = pair(2), m3 = pair(3);  // vertex l | vertex l + 4
    const __m256i t0 = _mm256_unpacklo_epi32(m0, m1), t1 = _mm256_unpacklo_epi32(m2, m3);  // x0 x1 y0 y1 | x4 ...
    const __m256i t2 = _mm256_unpackhi_epi32(m0, m1), t3 = _mm256_unpackhi_epi32(m2, m3);  // c0 c1 w0 w1 | c4 ...
    x = _mm256_unpacklo_epi64(t0, t1);
    y = _mm256_unpackhi_epi64(t0, t1);
    code = _mm256_unpacklo_epi64(t2, t3);
}

//! What surely_dropped8 leaves for the setup of the lanes it keeps: `simple` lanes (valid indices,
//! outcodes 0, extent < kVectorExtent, kept) have their re-ordered vertices, vertex indices (in
//! the index buffer's order) and clamped bounds here, the values build() computes for them.
struct Lanes8 {
    std::uint32_t simple = 0;
    std::uint32_t subpixel = 0;  //!< kept lanes that hold no pixel centre (keep_subpixel only)
    alignas(32) std::int32_t X[3][8], Y[3][8], vi[3][8], x0[8], x1[8], y0[8], y1[8], neg[8], cover[8];
};

// The vertex indices of 8 consecutive triangles (24 consecutive indices from ix): vertex j of
// triangle l in lane l of i[j]. Three loads, each lane's index taken from the load that holds it
// (a blend), then put in triangle order (a permutation).
inline void load_indices8(const std::uint32_t* ix, __m256i (&i)[3]) {
    const __m256i a = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(ix));
    const __m256i b = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(ix + 8));
    const __m256i c = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(ix + 16));
    // Index 3 l + j is element (3 l + j) % 8 of load (3 l + j) / 8.
    const __m256i v0 = _mm256_blend_epi32(_mm256_blend_epi32(a, b, 0b10010010), c, 0b00100100);  // a0 b1 c2 a3 b4 c5 a6 b7
    const __m256i v1 = _mm256_blend_epi32(_mm256_blend_epi32(a, b, 0b00100100), c, 0b01001001);  // c0 a1 b2 c3 a4 b5 c6 a7
    const __m256i v2 = _mm256_blend_epi32(_mm256_blend_epi32(a, b, 0b01001001), c, 0b10010010);  // b0 c1 a2 b3 c4 a5 b6 c7
    i[0] = _mm256_permutevar8x32_epi32(v0, _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
    i[1] = _mm256_permutevar8x32_epi32(v1, _mm256_setr_epi32(1, 4, 7, 2, 5, 0, 3, 6));
    i[2] = _mm256_permutevar8x32_epi32(v2, _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
}

// Eight triangles' vertices in lanes: indices (0 in lanes with an index out of range), snapped
// x and y, and `ok` where every index is valid and every outcode 0 (setup_one's fast path).
struct Tris8 {
    __m256i i[3], x[3], y[3], ok;
};

// ix: the 24 indices of 8 consecutive triangles.
[[gnu::always_inline]] inline Tris8 load_tris8(const SnapVertex* snap, std::int32_t nv, const std::uint32_t* ix) {
    Tris8 t;
    load_indices8(ix, t.i);
    const __m256i vnv = _mm256_set1_epi32(nv), minus1 = _mm256_set1_epi32(-1), zero = _mm256_setzero_si256();
    t.ok = minus1;
    for (int j = 0; j < 3; ++j) {  // 0 <= index < nv (an index >= 2^31 reads as negative)
        __m256i& v = t.i[j];
        const __m256i in = _mm256_and_si256(_mm256_cmpgt_epi32(vnv, v), _mm256_cmpgt_epi32(v, minus1));
        t.ok = _mm256_and_si256(t.ok, in);
        v = _mm256_and_si256(v, in);  // a valid index (0 in the lanes dropped here)
    }
    __m256i code = zero;
    for (int j = 0; j < 3; ++j) {
        __m256i c;
        load_xy_code8(snap, t.i[j], t.x[j], t.y[j], c);
        code = _mm256_or_si256(code, c);
    }
    t.ok = _mm256_and_si256(t.ok, _mm256_cmpeq_epi32(code, zero));
    return t;
}

// The snapped bounds, the pixel bounds of bounds_hold_centre (u*) and those clamped to the raster
// as build() clamps them (p*).
struct Bounds8 {
    __m256i xmin, xmax, ymin, ymax, ux0, uy0, ux1, uy1, px0, py0, px1, py1;
};

[[gnu::always_inline]] inline Bounds8 bounds8(const Tris8& t, const Viewport& vp) {
    Bounds8 b;
    b.xmin = _mm256_min_epi32(t.x[0], _mm256_min_epi32(t.x[1], t.x[2]));
    b.xmax = _mm256_max_epi32(t.x[0], _mm256_max_epi32(t.x[1], t.x[2]));
    b.ymin = _mm256_min_epi32(t.y[0], _mm256_min_epi32(t.y[1], t.y[2]));
    b.ymax = _mm256_max_epi32(t.y[0], _mm256_max_epi32(t.y[1], t.y[2]));
    const __m256i half_up = _mm256_set1_epi32(kSubpixelOne / 2 - 1), half = _mm256_set1_epi32(kSubpixelOne / 2);
    b.ux0 = _mm256_srai_epi32(_mm256_add_epi32(b.xmin, half_up), kSubpixelBits);
    b.uy0 = _mm256_srai_epi32(_mm256_add_epi32(b.ymin, half_up), kSubpixelBits);
    b.ux1 = _mm256_srai_epi32(_mm256_sub_epi32(b.xmax, half), kSubpixelBits);
    b.uy1 = _mm256_srai_epi32(_mm256_sub_epi32(b.ymax, half), kSubpixelBits);
    const __m256i zero = _mm256_setzero_si256();
    b.px0 = _mm256_max_epi32(b.ux0, zero), b.py0 = _mm256_max_epi32(b.uy0, zero);
    b.px1 = _mm256_min_epi32(b.ux1, _mm256_set1_epi32(vp.width - 1));
    b.py1 = _mm256_min_epi32(b.uy1, _mm256_set1_epi32(vp.height - 1));
    return b;
}

// Lanes where a pixel centre of the at most 4 x 4 pixels of the clamped bounds (bw x bh from px0,
// py0) lies inside the triangle X, Y (positive area, top-left rule).
[[gnu::always_inline]] inline __m256i any_centre_inside8(const __m256i (&X)[3], const __m256i (&Y)[3], const Bounds8& b,
                                                          __m256i bw, __m256i bh) {
    const __m256i zero = _mm256_setzero_si256(), one = _mm256_set1_epi32(1), half = _mm256_set1_epi32(kSubpixelOne / 2);
    __m256i dx[3], dy[3], bias_m1[3];  // bias - 1: inside is E > bias - 1
    for (int e = 0; e < 3; ++e) {
        const int a = (e + 1) % 3, c = (e + 2) % 3;
        dx[e] = _mm256_sub_epi32(X[c], X[a]);
        dy[e] = _mm256_sub_epi32(Y[c], Y[a]);
        const __m256i top_left = _mm256_or_si256(
            _mm256_and_si256(_mm256_cmpeq_epi32(dy[e], zero), _mm256_cmpgt_epi32(dx[e], zero)), _mm256_cmpgt_epi32(zero, dy[e]));
        bias_m1[e] = _mm256_andnot_si256(top_left, one);  // bias 0 or 1, minus 1
        bias_m1[e] = _mm256_sub_epi32(bias_m1[e], one);
    }
    __m256i any = zero;
    for (int oy = 0; oy < 4; ++oy)
        for (int ox = 0; ox < 4; ++ox) {
            const __m256i in_bounds = _mm256_and_si256(_mm256_cmpgt_epi32(bw, _mm256_set1_epi32(ox)),
                                                       _mm256_cmpgt_epi32(bh, _mm256_set1_epi32(oy)));
            const __m256i sx = _mm256_add_epi32(_mm256_slli_epi32(_mm256_add_epi32(b.px0, _mm256_set1_epi32(ox)), kSubpixelBits), half);
            const __m256i sy = _mm256_add_epi32(_mm256_slli_epi32(_mm256_add_epi32(b.py0, _mm256_set1_epi32(oy)), kSubpixelBits), half);
            __m256i inside = in_bounds;
            for (int e = 0; e < 3; ++e) {
                const int a = (e + 1) % 3;
                const __m256i E = _mm256_sub_epi32(_mm256_mullo_epi32(dx[e], _mm256_sub_epi32(sy, Y[a])),
                                                   _mm256_mullo_epi32(dy[e], _mm256_sub_epi32(sx, X[a])));
                inside = _mm256_and_si256(inside, _mm256_cmpgt_epi32(E, bias_m1[e]));
            }
            any = _mm256_or_si256(any, inside);
        }
    return any;
}

// The kept lanes' setup values into out (Lanes8).
[[gnu::always_inline]] inline void store_lanes8(const Tris8& t, const __m256i (&X)[3], const __m256i (&Y)[3], const Bounds8& b,
                                                __m256i neg, Lanes8& out) {
    auto put = [](std::int32_t* d, __m256i v) { _mm256_store_si256(reinterpret_cast<__m256i*>(d), v); };
    for (int j = 0; j < 3; ++j) {
        put(out.X[j], X[j]);
        put(out.Y[j], Y[j]);
    }
    // Vertex indices in the index buffer's order.
    for (int j = 0; j < 3; ++j) put(out.vi[j], t.i[j]);
    put(out.x0, b.px0);
    put(out.x1, b.px1);
    put(out.y0, b.py0);
    put(out.y1, b.py1);
    put(out.neg, neg);
    // TriSetup::cover (cover_bits over the lanes; a comparison is -1 where true).
    const __m256i rl = _mm256_set1_epi32(kSubpixelOne / 2 + kCoverageReach - (kSubpixelOne - 1));
    const __m256i rh = _mm256_set1_epi32(kSubpixelOne / 2 - kCoverageReach);
    auto bit = [](__m256i a, __m256i c, int k) { return _mm256_and_si256(_mm256_cmpeq_epi32(a, c), _mm256_set1_epi32(1 << k)); };
    put(out.cover, _mm256_or_si256(_mm256_or_si256(bit(_mm256_srai_epi32(_mm256_sub_epi32(b.xmin, rl), kSubpixelBits), b.ux0, 0),
                                                   bit(_mm256_srai_epi32(_mm256_sub_epi32(b.xmax, rh), kSubpixelBits), b.ux1, 1)),
                                   _mm256_or_si256(bit(_mm256_srai_epi32(_mm256_sub_epi32(b.ymin, rl), kSubpixelBits), b.uy0, 2),
                                                   bit(_mm256_srai_epi32(_mm256_sub_epi32(b.ymax, rh), kSubpixelBits), b.uy1, 3))));
}

// ix: the 24 indices of 8 consecutive triangles.
std::uint32_t surely_dropped8(const SnapVertex* snap, std::int32_t nv, const std::uint32_t* ix,
                              const Viewport& vp, bool cull, bool keep_subpixel, bool double_sided, Lanes8& out) {
    const Tris8 t = load_tris8(snap, nv, ix);
    const Bounds8 b = bounds8(t, vp);
    const __m256i zero = _mm256_setzero_si256(), one = _mm256_set1_epi32(1);
    __m256i ok = t.ok;
    // setup_one's quick reject (any extent): bounds that hold no pixel centre (with keep_subpixel:
    // no centre within a pixel, build()'s test on the clamped bounds below does the rest).
    const __m256i no_centre_in_bounds =
        keep_subpixel ? _mm256_setzero_si256()
                      : _mm256_and_si256(ok, _mm256_or_si256(_mm256_cmpgt_epi32(b.ux0, b.ux1), _mm256_cmpgt_epi32(b.uy0, b.uy1)));
    const __m256i ext = _mm256_set1_epi32(kVectorExtent);
    ok = _mm256_and_si256(ok, _mm256_and_si256(_mm256_cmpgt_epi32(ext, _mm256_sub_epi32(b.xmax, b.xmin)),
                                               _mm256_cmpgt_epi32(ext, _mm256_sub_epi32(b.ymax, b.ymin))));
    const __m256i empty = _mm256_or_si256(_mm256_cmpgt_epi32(b.px0, b.px1), _mm256_cmpgt_epi32(b.py0, b.py1));
    // build(): empty clamped bounds drop the triangle, or with keep_subpixel keep it as sub-pixel
    // when they are empty by at most one pixel.
    const __m256i beyond = _mm256_or_si256(_mm256_cmpgt_epi32(b.px0, _mm256_add_epi32(b.px1, one)),
                                           _mm256_cmpgt_epi32(b.py0, _mm256_add_epi32(b.py1, one)));
    const __m256i* x = t.x;
    const __m256i* y = t.y;
    const __m256i area = _mm256_sub_epi32(
        _mm256_mullo_epi32(_mm256_sub_epi32(x[1], x[0]), _mm256_sub_epi32(y[2], y[0])),
        _mm256_mullo_epi32(_mm256_sub_epi32(y[1], y[0]), _mm256_sub_epi32(x[2], x[0])));
    __m256i drop = _mm256_or_si256(keep_subpixel ? beyond : empty, _mm256_cmpeq_epi32(area, zero));
    if (cull) drop = _mm256_or_si256(drop, _mm256_cmpgt_epi32(area, zero));  // back faces
    // The small-triangle test on the re-ordered vertices (positive area: 1 and 2 swapped when
    // the area is negative), over the at most 4 pixels of the bounds.
    const __m256i bw = _mm256_add_epi32(_mm256_sub_epi32(b.px1, b.px0), one), bh = _mm256_add_epi32(_mm256_sub_epi32(b.py1, b.py0), one);
    const __m256i small = _mm256_andnot_si256(
        empty, _mm256_cmpgt_epi32(_mm256_set1_epi32(int(kSmallTrianglePixels) + 1), _mm256_mullo_epi32(bw, bh)));
    const __m256i neg = _mm256_cmpgt_epi32(zero, area);
    const __m256i X[3] = {x[0], _mm256_blendv_epi8(x[1], x[2], neg), _mm256_blendv_epi8(x[2], x[1], neg)};
    const __m256i Y[3] = {y[0], _mm256_blendv_epi8(y[1], y[2], neg), _mm256_blendv_epi8(y[2], y[1], neg)};
    const __m256i no_centre = _mm256_andnot_si256(any_centre_inside8(X, Y, b, bw, bh), small);
    __m256i subpixel = zero;
    if (keep_subpixel) {
        subpixel = _mm256_or_si256(empty, no_centre);
        // build(): a single-sided back face is not kept as sub-pixel.
        if (!double_sided) drop = _mm256_or_si256(drop, _mm256_and_si256(subpixel, _mm256_cmpgt_epi32(area, zero)));
    } else {
        drop = _mm256_or_si256(drop, no_centre);
    }
    drop = _mm256_or_si256(_mm256_and_si256(drop, ok), no_centre_in_bounds);
    const std::uint32_t dropped = std::uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(drop)));
    out.simple = std::uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(ok))) & ~dropped;
    out.subpixel = std::uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(subpixel))) & out.simple;
    if (out.simple) store_lanes8(t, X, Y, b, neg, out);
    return dropped;
}

// How many triangles ahead of the pre-pass the vertices are fetched (schedule only).
constexpr std::uint32_t kGatherAhead = 64;
// A group of 8 triangles whose 24 vertex indices lie within this many vertices of each other
// (320 KB of SnapVertex) is taken to come from a mesh in first-use vertex order (schedule only).
constexpr std::uint32_t kFrontierSpan = 16384;
// Prefetch hints for the snapped vertices of the 8 triangles whose indices start at ix (an index
// out of range is clamped: the hint must name memory of the array; it changes no result).
// Meshes whose vertices are numbered in order of first use (the Stanford dragons: 8 triangles'
// indices span 5k vertices at the median, 11k at the 90th percentile) bring about 4 new vertices
// per 8 triangles, at the largest index; the others were fetched for earlier triangles and are
// still cached. Such a group gets two hints, the largest index and 3 vertices before it (the
// 60 bytes of new vertices behind it may start on the line before); any other group gets all
// 24. 24 hints per group had the pre-pass wait on the prefetches themselves (a sixth of
// setup_triangles' samples on the 871k dragon before 9c32fa5; docs/performance.md "Rasterizer").
inline void prefetch_snap(const SnapVertex* snap, std::size_t nv, const std::uint32_t* ix) {
    const __m256i a = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(ix));
    const __m256i b = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(ix + 8));
    const __m256i c = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(ix + 16));
    const __m256i mx = _mm256_max_epu32(_mm256_max_epu32(a, b), c), mn = _mm256_min_epu32(_mm256_min_epu32(a, b), c);
    __m128i hi = _mm_max_epu32(_mm256_castsi256_si128(mx), _mm256_extracti128_si256(mx, 1));
    __m128i lo = _mm_min_epu32(_mm256_castsi256_si128(mn), _mm256_extracti128_si256(mn, 1));
    hi = _mm_max_epu32(hi, _mm_shuffle_epi32(hi, 0x4e));
    lo = _mm_min_epu32(lo, _mm_shuffle_epi32(lo, 0x4e));
    hi = _mm_max_epu32(hi, _mm_shuffle_epi32(hi, 0xb1));
    lo = _mm_min_epu32(lo, _mm_shuffle_epi32(lo, 0xb1));
    const std::uint32_t top = std::uint32_t(_mm_cvtsi128_si32(hi)), bottom = std::uint32_t(_mm_cvtsi128_si32(lo));
    if (top - bottom > kFrontierSpan) {
        for (int k = 0; k < 24; ++k) __builtin_prefetch(snap + std::min<std::size_t>(ix[k], nv - 1));
        return;
    }
    const std::size_t last = std::min<std::size_t>(top, nv - 1);
    __builtin_prefetch(snap + last);
    __builtin_prefetch(snap + (last >= 3 ? last - 3 : 0));
}

//! build()'s record for a lane surely_dropped8 kept as simple: set_edges of the re-ordered
//! vertices, the clamped bounds, 1/w and depth.
void build_simple(const SnapVertex* snap, const Lanes8& ln, int l, std::uint32_t draw_index,
                  std::vector<TriSetup>& out) {
    TriSetup& t = out.emplace_back(TriSetup::NoInit{});
    const std::int64_t X[3] = {ln.X[0][l], ln.X[1][l], ln.X[2][l]}, Y[3] = {ln.Y[0][l], ln.Y[1][l], ln.Y[2][l]};
    set_edges(X, Y, t);
    t.x0 = std::int16_t(ln.x0[l]), t.x1 = std::int16_t(ln.x1[l]);
    t.y0 = std::int16_t(ln.y0[l]), t.y1 = std::int16_t(ln.y1[l]);
    t.cover = std::uint8_t(ln.cover[l]);
    const bool neg = ln.neg[l] != 0;
    const std::uint32_t vi[3] = {std::uint32_t(ln.vi[0][l]), std::uint32_t(ln.vi[1][l]), std::uint32_t(ln.vi[2][l])};
    const std::uint32_t setup_order[3] = {vi[0], neg ? vi[2] : vi[1], neg ? vi[1] : vi[2]};
    for (int j = 0; j < 3; ++j) {
        const SnapVertex& v = snap[setup_order[j]];
        t.inv_w[j] = v.inv_w;
        t.depth[j] = v.depth;
        t.v[j] = vi[j];
    }
    t.draw = draw_index;
    t.clip = -1;
    // perm when the area is negative, back when it is positive (area 0 was dropped).
    t.flags |= neg ? TriSetup::kPermBit : TriSetup::kBackBit;
    if ((ln.subpixel >> l) & 1u) t.flags |= TriSetup::kSubpixelBit;
}

//! The SubpixelTri of a kept sub-pixel lane (its vertices in setup order and coverage_bounds).
void build_subpixel(const Lanes8& ln, int l, const Viewport& vp, std::vector<SubpixelTri>& out) {
    SubpixelTri& s = out.emplace_back();
    for (int j = 0; j < 3; ++j) s.X[j] = ln.X[j][l], s.Y[j] = ln.Y[j][l];
    const PixelRect r = coverage_bounds(ln.x0[l], ln.y0[l], ln.x1[l], ln.y1[l], unsigned(ln.cover[l]), vp.width, vp.height);
    s.x0 = std::int16_t(r.x0), s.y0 = std::int16_t(r.y0), s.x1 = std::int16_t(r.x1), s.y1 = std::int16_t(r.y1);
}
#endif

}  // namespace

void setup_triangle(const DrawVertices& dv, std::uint32_t draw_index, std::uint32_t tri,
                    const Viewport& vp, const SetupOptions& opt, std::vector<TriSetup>& out,
                    std::vector<ClipVerts>& clip_out, SetupCounters& counters) {
    setup_one(dv, draw_index, tri, vp, opt, out, clip_out, counters);
}

void setup_triangles(const DrawVertices& dv, std::uint32_t draw_index, std::uint32_t begin, std::uint32_t end,
                     const Viewport& vp, const SetupOptions& opt, std::vector<TriSetup>& out,
                     std::vector<ClipVerts>& clip_out, SetupCounters& counters,
                     std::vector<SubpixelTri>* subpixel_out) {
    // Two passes per batch: a branch-free pre-pass lists the triangles that need setup (on dense
    // meshes most bounds hold no pixel centre, and a per-triangle branch on that mispredicts),
    // then setup_one runs on the listed ones in order.
    const std::uint32_t* idx = dv.prim->indices.data();
    const std::size_t nv = dv.clip.size();
    const SnapVertex* snap = nv ? &dv.snap[0] : nullptr;
    std::uint32_t list[kSetupBatch];
    for (std::uint32_t b = begin; b < end;) {
        const std::uint32_t e = end - b > kSetupBatch ? b + kSetupBatch : end;
        std::uint32_t n = 0, t = b;
        if (nv == 0) {
            for (; t < e; ++t) list[n++] = t;
        }
#ifdef __AVX2__
        // 8 triangles per register: those setup_one surely drops without a trace never enter
        // the list (its checks are exact, so this changes nothing but the work).
        if (nv != 0 && nv <= std::size_t(INT32_MAX / 5) && 3 * std::size_t(e) <= std::size_t(INT32_MAX)) {
            const bool cull = opt.cull_backfaces && !dv.mat->double_sided;
            std::vector<SubpixelTri>* micro =
                opt.keep_subpixel && dv.mat->alpha_mode != scene::AlphaMode::Mask ? subpixel_out : nullptr;
            Lanes8 lanes;
            for (; t + 8 <= e; t += 8) {
                if (t + kGatherAhead + 8 <= end) prefetch_snap(snap, nv, idx + 3 * std::size_t(t + kGatherAhead));
                const std::uint32_t tris[8] = {t, t + 1, t + 2, t + 3, t + 4, t + 5, t + 6, t + 7};
                const std::uint32_t dropped =
                    surely_dropped8(snap, std::int32_t(nv), idx + 3 * std::size_t(t), vp, cull, opt.keep_subpixel,
                                    dv.mat->double_sided, lanes);
                if (lanes.simple == 0) {
                    for (int l = 0; l < 8; ++l) {
                        list[n] = tris[l];
                        n += (dropped >> l) & 1u ? 0u : 1u;
                    }
                    continue;
                }
                // Kept simple lanes are set up here, in order with the listed ones before them.
                for (std::uint32_t k = 0; k < n; ++k) setup_one(dv, draw_index, list[k], vp, opt, out, clip_out, counters);
                n = 0;
                // The kept lanes in order, by their bits (a branch per lane on whether it was kept
                // mispredicted: dense meshes keep about every other triangle).
                for (std::uint32_t keep = ~dropped & 0xffu; keep; keep &= keep - 1) {
                    const int l = std::countr_zero(keep);
                    if (!((lanes.simple >> l) & 1u)) setup_one(dv, draw_index, tris[l], vp, opt, out, clip_out, counters);
                    else if (micro && ((lanes.subpixel >> l) & 1u)) build_subpixel(lanes, l, vp, *micro);
                    else build_simple(snap, lanes, l, draw_index, out);
                }
            }
        }
#endif
        for (; t < e; ++t) {
            list[n] = t;
            n += opt.keep_subpixel || needs_setup(snap, nv, idx + 3 * std::size_t(t)) ? 1u : 0u;
        }
        for (std::uint32_t k = 0; k < n; ++k) setup_one(dv, draw_index, list[k], vp, opt, out, clip_out, counters);
        b = e;
    }
}

}  // namespace aq::raster
