// raster/vertex.cpp — vertex stage (see vertex.h). WC17 eq. 1-2 (hand tremor, MNPR form, spec §2)
// and WC17 §3.2 bleeding displacement; GL clip conventions; fixed-point snap.
#include "raster/vertex.h"

#include <bit>
#include <cmath>
#include <limits>

#include <immintrin.h>

#include "core/sine.h"

namespace aq::raster {

namespace {
inline float sat(float x) { return std::min(std::max(x, 0.0f), 1.0f); }
inline glm::vec3 normalize3(glm::vec3 v) {
    const float l2 = v.x * v.x + v.y * v.y + v.z * v.z;
    if (!(l2 > 0.0f)) return v;
    return v * (1.0f / std::sqrt(l2));
}
// MNPR constants of its tremor form (spec §2): time and frequency scalings, N.V gain.
constexpr float kTremorSpeedScale = 100.0f;
constexpr float kTremorFreqScale = 10.0f;
constexpr float kTremorNdotVGain = 1.2f;
// MNPR bleeding displacement: threshold 0.7, distance 0.5 object units at full bleed.
constexpr float kBleedThreshold = 0.7f;
constexpr float kBleedDistance = 0.5f;
}  // namespace

glm::mat4 projection_matrix(const scene::Camera& cam, float image_aspect) {
    glm::mat4 p(0.0f);
    const float n = cam.znear, f = cam.zfar;
    if (cam.orthographic) {
        p[0][0] = 1.0f / cam.xmag;
        p[1][1] = 1.0f / cam.ymag;
        p[2][2] = 2.0f / (n - f);
        p[3][2] = (f + n) / (n - f);
        p[3][3] = 1.0f;
    } else {
        const float aspect = cam.aspect ? *cam.aspect : image_aspect;
        const float t = 1.0f / std::tan(0.5f * cam.yfov);
        p[0][0] = t / aspect;
        p[1][1] = t;
        p[2][2] = (f + n) / (n - f);
        p[3][2] = (2.0f * f * n) / (n - f);
        p[2][3] = -1.0f;
    }
    return p;
}

glm::vec2 tremor_offset_px(const TremorParams& p, float time_s, glm::vec3 p_obj, glm::vec3 n_view,
                           glm::vec3 v_view) {
    const float ndv = n_view.x * v_view.x + n_view.y * v_view.y + n_view.z * v_view.z;
    const float w = std::min(sat(kTremorNdotVGain * ndv), 1.0f - p.front);
    // No tremor where the weight is 0 (silhouettes, back faces) or NaN (a NaN normal must not
    // turn a valid position into a dropped one).
    if (!(w > 0.0f)) return {0.0f, 0.0f};
    const float phase = (time_s * p.speed) * kTremorSpeedScale;
    const float sx = sine(phase + (p_obj.x * p.frequency) * kTremorFreqScale);
    const float sy = sine(phase + (p_obj.y * p.frequency) * kTremorFreqScale);
    return {(sx * p.tremor_px) * w, (sy * p.tremor_px) * w};
}

glm::vec3 bleed_displace(glm::vec3 p_obj, glm::vec3 n_obj, float ctrl_bleed) {
    const float k = sat(ctrl_bleed - kBleedThreshold) * kBleedDistance;
    return p_obj + n_obj * k;
}

std::uint32_t outcode(const glm::vec4& c, const Viewport& vp) {
    if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z) || !std::isfinite(c.w))
        return kOutNonFinite;
    std::uint32_t code = 0;
    const double w = c.w;
    if (double(c.z) < -w) code |= kOutNear;
    if (double(c.z) > w) code |= kOutFar;
    if (double(c.x) < -vp.gb_x * w) code |= kOutLeft;
    if (double(c.x) > vp.gb_x * w) code |= kOutRight;
    if (double(c.y) < -vp.gb_y * w) code |= kOutBottom;
    if (double(c.y) > vp.gb_y * w) code |= kOutTop;
    // w <= 0 with z >= -w implies z >= |w| >= ... ; a vertex at or behind the eye is always
    // outside near for a perspective projection (z = -w*(f+n)/(f-n)... ) — but guard anyway.
    if (!(c.w > 0.0f)) code |= kOutNear;
    return code;
}

namespace {
// snap_vertex written field by field into its destination: the vertex loop stored the returned
// struct piecewise and re-read it as one vector (a store-forwarding stall per vertex).
// std::llrint == cvtsd2si under the default (round-to-nearest-even) MXCSR, inlined.
inline void snap_into(const glm::vec4& c, float depth, const Viewport& vp, SnapVertex& s) {
    // Double precision: at the guard band (2^21 px) a float would only resolve 1/4 px.
    const double iw = 1.0 / double(c.w);
    const double sx = (double(c.x) * iw + 1.0) * (0.5 * vp.width);
    const double sy = (1.0 - double(c.y) * iw) * (0.5 * vp.height);
    s.x = std::int32_t(_mm_cvtsd_si64(_mm_set_sd(sx * kSubpixelOne)));
    s.y = std::int32_t(_mm_cvtsd_si64(_mm_set_sd(sy * kSubpixelOne)));
    s.inv_w = float(iw);
    s.depth = depth;
    s.code = 0;
}
}  // namespace

namespace {
// A vertex outside a clip plane or non-finite: only its outcode is read (setup clips or drops it).
inline void snap_outside(std::uint32_t code, SnapVertex& s) {
    s.x = 0;
    s.y = 0;
    s.inv_w = 0.0f;
    s.depth = 0.0f;
    s.code = code;
}
}  // namespace

SnapVertex snap_vertex(const glm::vec4& c, float depth, const Viewport& vp) {
    SnapVertex s;
    snap_into(c, depth, vp, s);
    return s;
}

namespace {

// The per-draw constants of the vertex stage.
struct VertexConsts {
    const scene::Primitive* prim;
    const std::vector<glm::vec4>* ctrl_abs;
    float bleed_const;
    bool do_bleed, do_tremor, has_normals, has_tan, perspective;
    float px_x, px_y, phase;
    TremorParams tp;
    glm::mat4 mv, proj;
    glm::mat3 nm;
    Viewport vp;
};

VertexConsts vertex_consts(const FrameParams& fp, const glm::mat4& mv, const glm::mat3& nm, const DrawVertices& dv) {
    VertexConsts k;
    k.prim = dv.prim;
    const RenderSettings& rs = *fp.settings;
    k.ctrl_abs = &dv.prim->control[scene::kCtrlAbstraction];
    k.bleed_const = dv.mat->wc.control[scene::kCtrlAbstraction].b;
    k.do_bleed = rs.bleed_displacement;
    k.do_tremor = rs.tremor.enabled && rs.tremor.tremor_px != 0.0f;
    k.has_normals = dv.prim->normals.size() == dv.prim->positions.size();
    k.has_tan = !dv.view_tangent.empty();
    k.perspective = fp.perspective;
    k.px_x = 2.0f / float(fp.out_width);
    k.px_y = 2.0f / float(fp.out_height);
    k.tp = rs.tremor;
    k.phase = (fp.time_s * k.tp.speed) * kTremorSpeedScale;
    k.mv = mv;
    k.proj = fp.proj;
    k.nm = nm;
    k.vp = fp.vp;
    return k;
}

// The tangent of vertex i (rare: normal-mapped primitives only).
inline void transform_tangent(const VertexConsts& k, DrawVertices& dv, std::size_t i) {
    const glm::vec4 t = k.prim->tangents[i];
    dv.view_tangent[i] = glm::vec4(normalize3(glm::mat3(k.mv) * glm::vec3(t)), t.w);
}

// Vertex i: the maths of the vertex stage, one vertex at a time (the definition; transform8 is
// the same operations on eight vertices).
inline void transform_one(const VertexConsts& k, DrawVertices& dv, std::size_t i) {
    const scene::Primitive& prim = *k.prim;
    const TremorParams& tp = k.tp;
    const glm::vec3 p = prim.positions[i];
    const glm::vec3 n = k.has_normals ? prim.normals[i] : glm::vec3(0, 0, 1);
    glm::vec3 pd = p;
    if (k.do_bleed) {
        float cb = k.bleed_const + (k.ctrl_abs->empty() ? 0.0f : (*k.ctrl_abs)[i].b);
        cb = std::min(std::max(cb, -1.0f), 1.0f);
        pd = bleed_displace(p, n, cb);
    }
    const glm::vec4 v = k.mv * glm::vec4(pd, 1.0f);
    glm::vec4 c = k.proj * v;
    const glm::vec3 nv = normalize3(k.nm * n);
    if (k.do_tremor) {
        const glm::vec3 vdir = k.perspective ? normalize3(-glm::vec3(v)) : glm::vec3(0, 0, 1);
        // tremor_offset_px inlined, with both sines always evaluated and the zero weight
        // selected afterwards: the weight test mispredicted along silhouettes (same values;
        // keep in step with tremor_offset_px).
        const float ndv = nv.x * vdir.x + nv.y * vdir.y + nv.z * vdir.z;
        const float w = std::min(sat(kTremorNdotVGain * ndv), 1.0f - tp.front);
        const float sx = sine(k.phase + (p.x * tp.frequency) * kTremorFreqScale);
        const float sy = sine(k.phase + (p.y * tp.frequency) * kTremorFreqScale);
        const bool on = w > 0.0f;
        const glm::vec2 off(on ? (sx * tp.tremor_px) * w : 0.0f, on ? (sy * tp.tremor_px) * w : 0.0f);
        // Pixels -> clip units: one output pixel is 2/W in NDC, times w to survive the divide.
        c.x = c.x + (off.x * k.px_x) * c.w;
        c.y = c.y + (off.y * k.px_y) * c.w;
    }
    dv.clip[i] = c;
    dv.view[i].pos = glm::vec3(v);
    dv.view[i].normal = nv;
    if (k.has_tan) transform_tangent(k, dv, i);
    const std::uint32_t code = outcode(c, k.vp);
    SnapVertex& sv = dv.snap[i];
    if (code == 0) snap_into(c, -v.z, k.vp, sv);
    else snap_outside(code, sv);
}

#ifdef __AVX2__
// Eight vertices [i, i + 8) with the operations of transform_one, lane by lane and in the same
// order (IEEE operations round the same in a vector lane; no FMA is emitted, -mno-fma): the same
// values, except that the payload of a NaN may come from another operand. The sines eight at a
// time (core/sine.h sine8: the bits of sine()).
using V = __m256;
inline V bc(float x) { return _mm256_set1_ps(x); }
inline V add(V a, V b) { return _mm256_add_ps(a, b); }
inline V sub(V a, V b) { return _mm256_sub_ps(a, b); }
inline V mul(V a, V b) { return _mm256_mul_ps(a, b); }
// std::max(x, lo) = (x < lo) ? lo : x and std::min(x, hi) = (hi < x) ? hi : x, NaN x kept.
inline V max_of(V x, V lo) { return _mm256_max_ps(lo, x); }
inline V min_of(V x, V hi) { return _mm256_min_ps(hi, x); }
inline V sat8(V x) { return min_of(max_of(x, bc(0.0f)), bc(1.0f)); }
inline void normalize8(V& x, V& y, V& z) {
    const V l2 = add(add(mul(x, x), mul(y, y)), mul(z, z));
    const V s = _mm256_div_ps(bc(1.0f), _mm256_sqrt_ps(l2));
    const V ok = _mm256_cmp_ps(l2, bc(0.0f), _CMP_GT_OQ);
    x = _mm256_blendv_ps(x, mul(x, s), ok);
    y = _mm256_blendv_ps(y, mul(y, s), ok);
    z = _mm256_blendv_ps(z, mul(z, s), ok);
}
// Row r of m * (x, y, z, w) as glm computes it: (m0 x + m1 y) + (m2 z + m3 w).
inline V mat4_row(const glm::mat4& m, int r, V x, V y, V z, V w) {
    return add(add(mul(bc(m[0][r]), x), mul(bc(m[1][r]), y)), add(mul(bc(m[2][r]), z), mul(bc(m[3][r]), w)));
}
// Row r of m * (x, y, z) as glm computes it: (m0 x + m1 y) + m2 z.
inline V mat3_row(const glm::mat3& m, int r, V x, V y, V z) {
    return add(add(mul(bc(m[0][r]), x), mul(bc(m[1][r]), y)), mul(bc(m[2][r]), z));
}

// Eight consecutive vec3 (24 floats) as three registers: three loads, six blends, three
// permutes. (Eight scalar stores to a stack array and one vector load per component stalled
// every load on a failed store forward.)
static_assert(sizeof(glm::vec3) == 3 * sizeof(float));
inline void load_xyz8(const glm::vec3* p, V& x, V& y, V& z) {
    const float* f = &p->x;
    const V m0 = _mm256_loadu_ps(f), m1 = _mm256_loadu_ps(f + 8), m2 = _mm256_loadu_ps(f + 16);
    // m0 = x0 y0 z0 x1 y1 z1 x2 y2, m1 = z2 x3 y3 z3 x4 y4 z4 x5, m2 = y5 z5 x6 y6 z6 x7 y7 z7
    x = _mm256_permutevar8x32_ps(_mm256_blend_ps(_mm256_blend_ps(m0, m1, 0b10010010), m2, 0b00100100),
                                 _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
    y = _mm256_permutevar8x32_ps(_mm256_blend_ps(_mm256_blend_ps(m0, m1, 0b00100100), m2, 0b01001001),
                                 _mm256_setr_epi32(1, 4, 7, 2, 5, 0, 3, 6));
    z = _mm256_permutevar8x32_ps(_mm256_blend_ps(_mm256_blend_ps(m0, m1, 0b01001001), m2, 0b10010010),
                                 _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
}

// Eight vec4 (x[l], y[l], z[l], w[l]) to p[0..7]: a 4 x 4 transposition per 128-bit half, four
// 32-byte stores.
static_assert(sizeof(glm::vec4) == 4 * sizeof(float));
inline void store_xyzw8(glm::vec4* p, V x, V y, V z, V w) {
    const V t0 = _mm256_unpacklo_ps(x, y), t1 = _mm256_unpackhi_ps(x, y);  // x0 y0 x1 y1 | x4 y4 x5 y5
    const V t2 = _mm256_unpacklo_ps(z, w), t3 = _mm256_unpackhi_ps(z, w);
    const V v0 = _mm256_shuffle_ps(t0, t2, 0x44), v1 = _mm256_shuffle_ps(t0, t2, 0xee);  // vertex 0 | 4, 1 | 5
    const V v2 = _mm256_shuffle_ps(t1, t3, 0x44), v3 = _mm256_shuffle_ps(t1, t3, 0xee);  // 2 | 6, 3 | 7
    float* f = &p->x;
    _mm256_storeu_ps(f, _mm256_permute2f128_ps(v0, v1, 0x20));
    _mm256_storeu_ps(f + 8, _mm256_permute2f128_ps(v2, v3, 0x20));
    _mm256_storeu_ps(f + 16, _mm256_permute2f128_ps(v0, v1, 0x31));
    _mm256_storeu_ps(f + 24, _mm256_permute2f128_ps(v2, v3, 0x31));
}

// Eight (position, normal) records: per group of four vertices the float pairs (p.x, p.y),
// (p.z, n.x), (n.y, n.z) as 64-bit lanes A, B, C, interleaved A0 B0 C0 A1 | B1 C1 A2 B2 | C2 A3 B3
// C3 by one permutation of each and two blends per store.
static_assert(sizeof(DrawVertices::Shading) == 6 * sizeof(float));
inline void store_shading8(DrawVertices::Shading* p, V px, V py, V pz, V nx, V ny, V nz) {
    auto pairs = [](V a, V b, bool high) {  // (a[l], b[l]) for l in the low or the high four lanes
        const V lo = _mm256_unpacklo_ps(a, b), hi = _mm256_unpackhi_ps(a, b);
        return _mm256_castps_pd(high ? _mm256_permute2f128_ps(lo, hi, 0x31) : _mm256_permute2f128_ps(lo, hi, 0x20));
    };
    float* f = &p->pos.x;
    for (int g = 0; g < 2; ++g, f += 24) {
        const __m256d a = _mm256_permute4x64_pd(pairs(px, py, g), 0x6c);  // A0 A3 A2 A1
        const __m256d b = _mm256_permute4x64_pd(pairs(pz, nx, g), 0xb1);  // B1 B0 B3 B2
        const __m256d c = _mm256_permute4x64_pd(pairs(ny, nz, g), 0xc6);  // C2 C1 C0 C3
        _mm256_storeu_pd(reinterpret_cast<double*>(f), _mm256_blend_pd(_mm256_blend_pd(a, b, 0b0010), c, 0b0100));
        _mm256_storeu_pd(reinterpret_cast<double*>(f + 8), _mm256_blend_pd(_mm256_blend_pd(b, c, 0b0010), a, 0b0100));
        _mm256_storeu_pd(reinterpret_cast<double*>(f + 16), _mm256_blend_pd(_mm256_blend_pd(c, a, 0b0010), b, 0b0100));
    }
}

void transform8(const VertexConsts& k, DrawVertices& dv, std::size_t i) {
    const scene::Primitive& prim = *k.prim;
    const TremorParams& tp = k.tp;
    V px, py, pz, nx = bc(0.0f), ny = bc(0.0f), nz = bc(1.0f);
    load_xyz8(&prim.positions[i], px, py, pz);
    if (k.has_normals) load_xyz8(&prim.normals[i], nx, ny, nz);
    V dx = px, dy = py, dz = pz;
    if (k.do_bleed) {
        V ctrl = bc(0.0f);
        if (!k.ctrl_abs->empty()) {
            const glm::vec4* c = &(*k.ctrl_abs)[i];
            ctrl = _mm256_setr_ps(c[0].b, c[1].b, c[2].b, c[3].b, c[4].b, c[5].b, c[6].b, c[7].b);
        }
        V cb = add(bc(k.bleed_const), ctrl);
        cb = min_of(max_of(cb, bc(-1.0f)), bc(1.0f));
        const V kk = mul(sat8(sub(cb, bc(kBleedThreshold))), bc(kBleedDistance));
        dx = add(px, mul(nx, kk));
        dy = add(py, mul(ny, kk));
        dz = add(pz, mul(nz, kk));
    }
    const V one = bc(1.0f);
    const V vx = mat4_row(k.mv, 0, dx, dy, dz, one), vy = mat4_row(k.mv, 1, dx, dy, dz, one);
    const V vz = mat4_row(k.mv, 2, dx, dy, dz, one), vw = mat4_row(k.mv, 3, dx, dy, dz, one);
    V cx = mat4_row(k.proj, 0, vx, vy, vz, vw), cy = mat4_row(k.proj, 1, vx, vy, vz, vw);
    const V cz = mat4_row(k.proj, 2, vx, vy, vz, vw), cw = mat4_row(k.proj, 3, vx, vy, vz, vw);
    V mx = mat3_row(k.nm, 0, nx, ny, nz), my = mat3_row(k.nm, 1, nx, ny, nz), mz = mat3_row(k.nm, 2, nx, ny, nz);
    normalize8(mx, my, mz);
    if (k.do_tremor) {
        V ux = bc(0.0f), uy = bc(0.0f), uz = bc(1.0f);
        if (k.perspective) {
            const V sign = bc(-0.0f);
            ux = _mm256_xor_ps(vx, sign), uy = _mm256_xor_ps(vy, sign), uz = _mm256_xor_ps(vz, sign);
            normalize8(ux, uy, uz);
        }
        const V ndv = add(add(mul(mx, ux), mul(my, uy)), mul(mz, uz));
        const V w = min_of(sat8(mul(bc(kTremorNdotVGain), ndv)), bc(1.0f - tp.front));
        const V on = _mm256_cmp_ps(w, bc(0.0f), _CMP_GT_OQ);
        // The sines only where a lane has tremor (back faces and silhouettes have none).
        alignas(32) float ax[8] = {}, ay[8] = {};
        if (!_mm256_testz_ps(on, on)) {
            _mm256_store_ps(ax, add(bc(k.phase), mul(mul(px, bc(tp.frequency)), bc(kTremorFreqScale))));
            _mm256_store_ps(ay, add(bc(k.phase), mul(mul(py, bc(tp.frequency)), bc(kTremorFreqScale))));
            sine8(ax, ax);
            sine8(ay, ay);
        }
        const V offx = _mm256_and_ps(on, mul(mul(_mm256_load_ps(ax), bc(tp.tremor_px)), w));
        const V offy = _mm256_and_ps(on, mul(mul(_mm256_load_ps(ay), bc(tp.tremor_px)), w));
        cx = add(cx, mul(mul(offx, bc(k.px_x)), cw));
        cy = add(cy, mul(mul(offy, bc(k.px_y)), cw));
    }
    // Outcodes (outcode()): non-finite alone, else the planes in double, then w <= 0 as near.
    const V inf = bc(std::numeric_limits<float>::infinity()), abs_mask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    auto finite = [&](V x) { return _mm256_cmp_ps(_mm256_and_ps(x, abs_mask), inf, _CMP_LT_OQ); };
    const V fin = _mm256_and_ps(_mm256_and_ps(finite(cx), finite(cy)), _mm256_and_ps(finite(cz), finite(cw)));
    alignas(32) std::int32_t code[8], sxi[8], syi[8];
    alignas(32) float iwf[8];
    for (int h = 0; h < 2; ++h) {
        auto half = [&](V x) { return _mm256_cvtps_pd(h ? _mm256_extractf128_ps(x, 1) : _mm256_castps256_ps128(x)); };
        const __m256d x = half(cx), y = half(cy), z = half(cz), w = half(cw);
        const __m256d gx = _mm256_mul_pd(_mm256_set1_pd(k.vp.gb_x), w), gy = _mm256_mul_pd(_mm256_set1_pd(k.vp.gb_y), w);
        const __m256d ngx = _mm256_mul_pd(_mm256_set1_pd(-k.vp.gb_x), w), ngy = _mm256_mul_pd(_mm256_set1_pd(-k.vp.gb_y), w);
        const __m256d nw = _mm256_xor_pd(w, _mm256_set1_pd(-0.0));
        auto bit = [](__m256d m, std::int32_t b) {  // b where the comparison holds, else 0
            const __m128i one = _mm256_cvtpd_epi32(_mm256_and_pd(m, _mm256_set1_pd(1.0)));  // 1 or 0
            return _mm_and_si128(_mm_sub_epi32(_mm_setzero_si128(), one), _mm_set1_epi32(b));
        };
        __m128i c4 = bit(_mm256_cmp_pd(z, nw, _CMP_LT_OQ), kOutNear);
        c4 = _mm_or_si128(c4, bit(_mm256_cmp_pd(z, w, _CMP_GT_OQ), kOutFar));
        c4 = _mm_or_si128(c4, bit(_mm256_cmp_pd(x, ngx, _CMP_LT_OQ), kOutLeft));
        c4 = _mm_or_si128(c4, bit(_mm256_cmp_pd(x, gx, _CMP_GT_OQ), kOutRight));
        c4 = _mm_or_si128(c4, bit(_mm256_cmp_pd(y, ngy, _CMP_LT_OQ), kOutBottom));
        c4 = _mm_or_si128(c4, bit(_mm256_cmp_pd(y, gy, _CMP_GT_OQ), kOutTop));
        c4 = _mm_or_si128(c4, bit(_mm256_cmp_pd(w, _mm256_setzero_pd(), _CMP_NGT_UQ), kOutNear));
        _mm_store_si128(reinterpret_cast<__m128i*>(code + 4 * h), c4);
        // The snap (snap_into), computed in every lane and kept where the code is 0.
        const __m256d iw = _mm256_div_pd(_mm256_set1_pd(1.0), w);
        const __m256d sx = _mm256_mul_pd(_mm256_add_pd(_mm256_mul_pd(x, iw), _mm256_set1_pd(1.0)),
                                         _mm256_set1_pd(0.5 * k.vp.width));
        const __m256d sy = _mm256_mul_pd(_mm256_sub_pd(_mm256_set1_pd(1.0), _mm256_mul_pd(y, iw)),
                                         _mm256_set1_pd(0.5 * k.vp.height));
        // cvtpd2dq rounds as cvtsd2si (MXCSR, nearest even): inside the guard band the values fit
        // in 32 bits; other lanes (code != 0) convert to INT_MIN and are not kept.
        const __m256d one_px = _mm256_set1_pd(double(kSubpixelOne));
        _mm_store_si128(reinterpret_cast<__m128i*>(sxi + 4 * h), _mm256_cvtpd_epi32(_mm256_mul_pd(sx, one_px)));
        _mm_store_si128(reinterpret_cast<__m128i*>(syi + 4 * h), _mm256_cvtpd_epi32(_mm256_mul_pd(sy, one_px)));
        _mm_store_ps(iwf + 4 * h, _mm256_cvtpd_ps(iw));
    }
    store_xyzw8(&dv.clip[i], cx, cy, cz, cw);
    store_shading8(&dv.view[i], vx, vy, vz, mx, my, mz);
    alignas(32) float vzs[8], fins[8];
    _mm256_store_ps(vzs, vz);
    _mm256_store_ps(fins, fin);
    for (int l = 0; l < 8; ++l) {
        const std::size_t j = i + l;
        if (k.has_tan) transform_tangent(k, dv, j);
        SnapVertex& sv = dv.snap[j];
        const bool finite_lane = std::bit_cast<std::uint32_t>(fins[l]) != 0u;
        const std::uint32_t c = finite_lane ? std::uint32_t(code[l]) : kOutNonFinite;
        if (c == 0) {
            sv.x = sxi[l];
            sv.y = syi[l];
            sv.inv_w = iwf[l];
            sv.depth = -vzs[l];
            sv.code = 0;
        } else {
            snap_outside(c, sv);
        }
    }
}
#endif

}  // namespace

void transform_vertex(const FrameParams& fp, const glm::mat4& mv, const glm::mat3& nm, DrawVertices& dv,
                      std::size_t i) {
    transform_one(vertex_consts(fp, mv, nm, dv), dv, i);
}

void transform_vertices(const FrameParams& fp, const glm::mat4& mv, const glm::mat3& nm,
                        DrawVertices& dv, std::size_t begin, std::size_t end) {
    const VertexConsts k = vertex_consts(fp, mv, nm, dv);
    std::size_t i = begin;
#ifdef __AVX2__
    for (; i + 8 <= end; i += 8) transform8(k, dv, i);
#endif
    for (; i < end; ++i) transform_one(k, dv, i);
}

}  // namespace aq::raster
