// raster/vertex.cpp — vertex stage (see vertex.h). WC17 eq. 1-2 (hand tremor, MNPR form, spec §2)
// and WC17 §3.2 bleeding displacement; GL clip conventions; fixed-point snap.
#include "raster/vertex.h"

#include <cmath>

#include <immintrin.h>

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
    const float sx = std::sin(phase + (p_obj.x * p.frequency) * kTremorFreqScale);
    const float sy = std::sin(phase + (p_obj.y * p.frequency) * kTremorFreqScale);
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

SnapVertex snap_vertex(const glm::vec4& c, float depth, const Viewport& vp) {
    SnapVertex s;
    snap_into(c, depth, vp, s);
    return s;
}

void transform_vertices(const FrameParams& fp, const glm::mat4& mv, const glm::mat3& nm,
                        DrawVertices& dv, std::size_t begin, std::size_t end) {
    const scene::Primitive& prim = *dv.prim;
    const RenderSettings& rs = *fp.settings;
    const auto& ctrl_abs = prim.control[scene::kCtrlAbstraction];
    const float bleed_const = dv.mat->wc.control[scene::kCtrlAbstraction].b;
    const bool do_bleed = rs.bleed_displacement;
    const bool do_tremor = rs.tremor.enabled && rs.tremor.tremor_px != 0.0f;
    const bool has_normals = prim.normals.size() == prim.positions.size();
    const bool has_tan = !dv.view_tangent.empty();
    const float px_x = 2.0f / float(fp.out_width), px_y = 2.0f / float(fp.out_height);
    const TremorParams& tp = rs.tremor;
    const float phase = (fp.time_s * tp.speed) * kTremorSpeedScale;
    for (std::size_t i = begin; i < end; ++i) {
        const glm::vec3 p = prim.positions[i];
        const glm::vec3 n = has_normals ? prim.normals[i] : glm::vec3(0, 0, 1);
        glm::vec3 pd = p;
        if (do_bleed) {
            float cb = bleed_const + (ctrl_abs.empty() ? 0.0f : ctrl_abs[i].b);
            cb = std::min(std::max(cb, -1.0f), 1.0f);
            pd = bleed_displace(p, n, cb);
        }
        const glm::vec4 v = mv * glm::vec4(pd, 1.0f);
        glm::vec4 c = fp.proj * v;
        const glm::vec3 nv = normalize3(nm * n);
        if (do_tremor) {
            const glm::vec3 vdir = fp.perspective ? normalize3(-glm::vec3(v)) : glm::vec3(0, 0, 1);
            // tremor_offset_px inlined, with both sines always evaluated and the zero weight
            // selected afterwards: the weight test mispredicted along silhouettes (same values;
            // keep in step with tremor_offset_px).
            const float ndv = nv.x * vdir.x + nv.y * vdir.y + nv.z * vdir.z;
            const float w = std::min(sat(kTremorNdotVGain * ndv), 1.0f - tp.front);
            const float sx = std::sin(phase + (p.x * tp.frequency) * kTremorFreqScale);
            const float sy = std::sin(phase + (p.y * tp.frequency) * kTremorFreqScale);
            const bool on = w > 0.0f;
            const glm::vec2 off(on ? (sx * tp.tremor_px) * w : 0.0f, on ? (sy * tp.tremor_px) * w : 0.0f);
            // Pixels -> clip units: one output pixel is 2/W in NDC, times w to survive the divide.
            c.x = c.x + (off.x * px_x) * c.w;
            c.y = c.y + (off.y * px_y) * c.w;
        }
        dv.clip[i] = c;
        dv.view[i].pos = glm::vec3(v);
        dv.view[i].normal = nv;
        if (has_tan) {
            const glm::vec4 t = prim.tangents[i];
            dv.view_tangent[i] = glm::vec4(normalize3(glm::mat3(mv) * glm::vec3(t)), t.w);
        }
        const std::uint32_t code = outcode(c, fp.vp);
        SnapVertex& sv = dv.snap[i];
        if (code == 0) {
            snap_into(c, -v.z, fp.vp, sv);
        } else {
            sv.x = 0;
            sv.y = 0;
            sv.inv_w = 0.0f;
            sv.depth = 0.0f;
            sv.code = code;
        }
    }
}

}  // namespace aq::raster
