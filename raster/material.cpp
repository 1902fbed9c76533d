// raster/material.cpp — the watercolor material (spec §3; WC17 eq. 3-6). See material.h.
#include "raster/material.h"

#include <cmath>
#include <limits>

#include "core/color.h"
#include "core/maths.h"
#include "core/simd.h"

namespace aq::raster {

namespace {
constexpr float kMinDiluteArea = 0.01f;  // WC17: dA in (0, 1]

inline glm::vec4 texel(const ImageF& img, int x, int y) {
    const float* p = img.data() + (std::size_t(y) * img.width() + x) * img.channels();
    switch (img.channels()) {
        case 1: return {p[0], p[0], p[0], 1.0f};
        case 2: return {p[0], p[1], 0.0f, 1.0f};
        case 3: return {p[0], p[1], p[2], 1.0f};
        default: return {p[0], p[1], p[2], p[3]};
    }
}
inline glm::vec4 lerp4(glm::vec4 a, glm::vec4 b, float t) { return a + (b - a) * t; }
// Keeps float -> int conversions defined for huge texture coordinates.
inline float safe_coord(float x) {
    if (!std::isfinite(x)) return 0.0f;
    return std::min(std::max(x, -1.0e7f), 1.0e7f);
}
}  // namespace

const scene::Texture* texture_of(const ShadeContext& ctx, const scene::TextureRef& r) {
    if (r.texture < 0 || !ctx.scene || r.texture >= int(ctx.scene->textures.size())) return nullptr;
    const scene::Texture& t = ctx.scene->textures[r.texture];
    return t.empty() ? nullptr : &t;
}


glm::vec3 base_color_to_working(glm::vec3 C, bool linear_color, WorkingSpace ws) {
    if (linear_color && ws == WorkingSpace::Display)
        return {linear_to_srgb(sat(C.x)), linear_to_srgb(sat(C.y)), linear_to_srgb(sat(C.z))};
    if (!linear_color && ws == WorkingSpace::Linear)
        return {srgb_to_linear(C.x), srgb_to_linear(C.y), srgb_to_linear(C.z)};
    return C;
}

glm::vec3 turbulence(glm::vec3 C, float ctrl, glm::vec3 Cp) {
    if (ctrl < 0.5f) {
        const float e = 3.0f - ctrl * 4.0f;
        return {std::pow(std::max(C.x, 0.0f), e), std::pow(std::max(C.y, 0.0f), e),
                std::pow(std::max(C.z, 0.0f), e)};
    }
    const float k = (ctrl - 0.5f) * 2.0f;
    return k * (Cp - C) + C;
}

int wrap_texel(int i, int n, scene::Wrap w) {
    switch (w) {
        case scene::Wrap::ClampToEdge: return std::min(std::max(i, 0), n - 1);
        case scene::Wrap::MirroredRepeat: {
            const int period = 2 * n;
            int m = i % period;
            if (m < 0) m += period;
            return m < n ? m : period - 1 - m;
        }
        default: {
            int m = i % n;
            return m < 0 ? m + n : m;
        }
    }
}

namespace {
//! wrap_texel of i and i + 1 (a bilinear footprint). Inside the texture every wrap mode is the
//! identity, so the common case takes no integer division (Repeat and MirroredRepeat divide:
//! sample_texture was a fifth of a textured model's G-buffer time).
inline void wrap_pair(int i, int n, scene::Wrap w, int& a, int& b) {
    if (i >= 0 && i < n - 1) {
        a = i;
        b = i + 1;
        return;
    }
    a = wrap_texel(i, n, w);
    b = wrap_texel(i + 1, n, w);
}
}  // namespace

namespace {
//! The sampling maths of one level with filter f, once for every texel store: fetch(x, y) is the
//! widened RGBA texel.
template <class Fetch>
inline glm::vec4 sample_with(int w, int h, scene::Filter f, const scene::Sampler& s, glm::vec2 uv, const Fetch& fetch) {
    const float u = safe_coord(uv.x) * float(w), v = safe_coord(uv.y) * float(h);
    if (f == scene::Filter::Nearest) {
        const int x = wrap_texel(int(std::floor(u)), w, s.wrap_s);
        const int y = wrap_texel(int(std::floor(v)), h, s.wrap_t);
        return fetch(x, y);
    }
    const float fx = u - 0.5f, fy = v - 0.5f;
    const float flx = std::floor(fx), fly = std::floor(fy);
    const float tx = fx - flx, ty = fy - fly;
    const int ix = int(flx), iy = int(fly);
    int x0, x1, y0, y1;
    wrap_pair(ix, w, s.wrap_s, x0, x1);
    wrap_pair(iy, h, s.wrap_t, y0, y1);
    return maths::bilerp(fetch(x0, y0), fetch(x1, y0), fetch(x0, y1), fetch(x1, y1), tx, ty);
}
}  // namespace

namespace {
glm::vec4 sample_image(const ImageF& img, scene::Filter f, const scene::Sampler& s, glm::vec2 uv) {
    return sample_with(img.width(), img.height(), f, s, uv, [&](int x, int y) { return texel(img, x, y); });
}
//! Level 0 of a scene texture with filter f, through its 8-bit codes where it has them.
glm::vec4 sample_level0(const scene::Texture& t, scene::Filter f, const scene::Sampler& s, glm::vec2 uv) {
    if (t.codes.empty()) return sample_image(t.image, f, s, uv);
    return sample_with(t.codes.width, t.codes.height, f, s, uv, [&](int x, int y) { return t.codes.texel(x, y); });
}
//! GL's c: the level of detail above which a texture is minified.
inline float minification_threshold(const scene::Sampler& s) {
    return s.mag == scene::Filter::Linear && s.min == scene::Filter::Nearest && s.mip != scene::MipFilter::None ? 0.5f
                                                                                                                 : 0.0f;
}
}  // namespace

glm::vec4 sample_texture(const ImageF& img, const scene::Sampler& s, glm::vec2 uv) {
    return sample_image(img, s.mag, s, uv);
}

glm::vec4 sample_texture(const scene::Texture& t, const scene::Sampler& s, glm::vec2 uv) {
    return sample_level0(t, s.mag, s, uv);
}

namespace {
//! One minified sample at level of detail `lod` (> c): GL's minification filter `min` within a
//! level and `mip` between levels.
glm::vec4 sample_minified(const scene::Texture& t, const scene::Sampler& s, glm::vec2 uv, float lod) {
    const int q = int(t.mips.size());
    auto level = [&](int d) {
        if (d == 0) return sample_level0(t, s.min, s, uv);
        if (d == 1 && t.level1_computed)
            return sample_with(std::max(1, t.width() / 2), std::max(1, t.height() / 2), s.min, s, uv,
                               [&](int x, int y) { return t.level1_texel(x, y); });
        return sample_image(t.mips[std::size_t(d - 1)], s.min, s, uv);
    };
    switch (s.mip) {
        case scene::MipFilter::None: return level(0);
        case scene::MipFilter::Nearest:
            if (!(lod < float(q))) return level(q);
            return level(lod <= 0.5f ? 0 : std::min(q, int(std::ceil(lod + 0.5f)) - 1));
        default: {
            if (!(lod < float(q))) return level(q);
            if (!(lod > 0.0f)) return level(0);
            const float fl = std::floor(lod);
            const int d = int(fl);
            return lerp4(level(d), level(d + 1), lod - fl);
        }
    }
}
}  // namespace

AnisoFootprint aniso_footprint(int w, int h, const UvGrad& g) {
    const glm::vec2 sz{float(w), float(h)};
    const glm::vec2 a = g.dx * sz, b = g.dy * sz;
    const float px = std::sqrt(a.x * a.x + a.y * a.y), py = std::sqrt(b.x * b.x + b.y * b.y);
    const bool x_major = !(py > px);
    const float pmax = x_major ? px : py, pmin = x_major ? py : px;
    AnisoFootprint f;
    f.major = x_major ? g.dx : g.dy;
    const float ratio = pmax / std::max(pmin, pmax * (1.0f / float(kMaxAnisotropy)));
    f.samples = ratio > 1.0f ? std::min(kMaxAnisotropy, int(std::ceil(ratio))) : 1;  // NaN: 1
    f.lod = std::log2(pmax / float(f.samples));
    f.iso_lod = std::log2(pmax);
    return f;
}

namespace {
//! sample_texture with the pixel's footprint (aniso_footprint) computed already.
glm::vec4 sample_footprint(const scene::Texture& t, const scene::Sampler& s, glm::vec2 uv, const AnisoFootprint& f) {
    if (!(f.iso_lod > minification_threshold(s))) return sample_level0(t, s.mag, s, uv);  // NaN too
    if (f.samples == 1) return sample_minified(t, s, uv, f.lod);
    // Anisotropic: samples spread evenly along the footprint's major axis, each at the level of
    // the minor axis (lod <= 0: level 0 with the minification filter), averaged.
    glm::vec4 sum(0.0f);
    const float inv = 1.0f / float(f.samples);
    for (int i = 0; i < f.samples; ++i) {
        const float o = (float(i) + 0.5f) * inv - 0.5f;
        sum += sample_minified(t, s, uv + f.major * o, f.lod);
    }
    return sum * inv;
}
}  // namespace

glm::vec4 sample_texture(const scene::Texture& t, const scene::Sampler& s, glm::vec2 uv, const UvGrad& g) {
    return sample_footprint(t, s, uv, aniso_footprint(t.width(), t.height(), g));
}

namespace {
//! sample_texture of the n (1-8) uvs and derivatives into out[0, n): the magnified lanes (level 0)
//! whose bilinear footprint lies inside the texture (every wrap mode is the identity there, the
//! common case) in one register — the
//! operations of sample_with in their order, lane by lane: safe_coord, floor, the three lerps of
//! lerp4 — and the other lanes, Nearest filtering and textures other than 8-bit codes or RGBA
//! floats through sample_texture. Schedule only: each lane's value is sample_texture's.
void sample_texture8(const scene::Texture& t, const scene::Sampler& s, const glm::vec2* uv, const UvGrad* g, int n,
                     glm::vec4* out) {
    const ImageF& img = t.image;
    const int w = t.width(), h = t.height();
    AnisoFootprint fp[FragmentLanes::kLanes];
    for (int i = 0; i < n; ++i) fp[i] = aniso_footprint(w, h, g[i]);
#ifdef __AVX2__
    const bool codes = !t.codes.empty();
    // Minified lanes (mip levels) are sampled one by one; the rest read level 0 here.
    std::uint32_t magnified = 0;
    const float c = minification_threshold(s);
    for (int i = 0; i < n; ++i) magnified |= std::uint32_t(!(fp[i].iso_lod > c)) << i;
    if (magnified && s.mag == scene::Filter::Linear && w >= 2 && h >= 2 && (codes || img.channels() == 4)) {
        alignas(32) float us[8], vs[8];
        for (int i = 0; i < 8; ++i) {
            const glm::vec2 q = uv[i < n ? i : 0];
            us[i] = q.x, vs[i] = q.y;
        }
        // safe_coord: +0 for a non-finite coordinate, else clamped to [-1e7, 1e7].
        auto safe = [](__m256 x) {
            const __m256 finite = _mm256_cmp_ps(_mm256_andnot_ps(_mm256_set1_ps(-0.0f), x),
                                                _mm256_set1_ps(std::numeric_limits<float>::infinity()), _CMP_LT_OQ);
            const __m256 c = _mm256_min_ps(_mm256_max_ps(x, _mm256_set1_ps(-1.0e7f)), _mm256_set1_ps(1.0e7f));
            return _mm256_and_ps(finite, c);
        };
        const __m256 half = _mm256_set1_ps(0.5f);
        const __m256 fx = _mm256_sub_ps(_mm256_mul_ps(safe(_mm256_load_ps(us)), _mm256_set1_ps(float(w))), half);
        const __m256 fy = _mm256_sub_ps(_mm256_mul_ps(safe(_mm256_load_ps(vs)), _mm256_set1_ps(float(h))), half);
        const __m256 flx = _mm256_floor_ps(fx), fly = _mm256_floor_ps(fy);
        const __m256 tx = _mm256_sub_ps(fx, flx), ty = _mm256_sub_ps(fy, fly);
        // int(flx) as cvttss2si: out of range gives INT_MIN, which is not inside (the scalar path).
        const __m256i ix = _mm256_cvttps_epi32(flx), iy = _mm256_cvttps_epi32(fly);
        const __m256i minus1 = _mm256_set1_epi32(-1);
        const __m256i inside = _mm256_and_si256(
            _mm256_and_si256(_mm256_cmpgt_epi32(ix, minus1), _mm256_cmpgt_epi32(_mm256_set1_epi32(w - 1), ix)),
            _mm256_and_si256(_mm256_cmpgt_epi32(iy, minus1), _mm256_cmpgt_epi32(_mm256_set1_epi32(h - 1), iy)));
        const std::uint32_t lanes = std::uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(inside))) & magnified;
        if (lanes) {
            // Texel indices of the footprint (0 in the lanes computed by sample_texture).
            const __m256i i00 = _mm256_and_si256(inside, _mm256_add_epi32(_mm256_mullo_epi32(iy, _mm256_set1_epi32(w)), ix));
            const __m256i i10 = _mm256_add_epi32(i00, _mm256_and_si256(inside, _mm256_set1_epi32(1)));
            const __m256i i01 = _mm256_add_epi32(i00, _mm256_and_si256(inside, _mm256_set1_epi32(w)));
            const __m256i i11 = _mm256_add_epi32(i01, _mm256_and_si256(inside, _mm256_set1_epi32(1)));
            const __m256i idx[4] = {i00, i10, i01, i11};
            __m256 tex[4][4];  // [texel][channel]
            for (int k = 0; k < 4; ++k) {
                if (codes) {
                    const __m256i dw = _mm256_i32gather_epi32(reinterpret_cast<const int*>(t.codes.codes.data()), idx[k], 4);
                    for (int c = 0; c < 4; ++c) {
                        const __m256i b = _mm256_and_si256(_mm256_srli_epi32(dw, 8 * c), _mm256_set1_epi32(0xff));
                        tex[k][c] = _mm256_i32gather_ps(t.codes.lut[std::size_t(c)].data(), b, 4);
                    }
                } else {
                    const __m256i v4 = _mm256_slli_epi32(idx[k], 2);
                    for (int c = 0; c < 4; ++c) tex[k][c] = _mm256_i32gather_ps(img.data() + c, v4, 4);
                }
            }
            auto lerp = [](__m256 a, __m256 b, __m256 f) { return _mm256_add_ps(a, _mm256_mul_ps(_mm256_sub_ps(b, a), f)); };
            alignas(32) float r[4][8];
            for (int c = 0; c < 4; ++c)
                _mm256_store_ps(r[c], lerp(lerp(tex[0][c], tex[1][c], tx), lerp(tex[2][c], tex[3][c], tx), ty));
            for (int i = 0; i < n; ++i)
                out[i] = (lanes >> i) & 1u ? glm::vec4(r[0][i], r[1][i], r[2][i], r[3][i]) : sample_footprint(t, s, uv[i], fp[i]);
            return;
        }
    }
#endif
    for (int i = 0; i < n; ++i) out[i] = sample_footprint(t, s, uv[i], fp[i]);
}
}  // namespace

ViewLight default_view_light() {
    return {normalize3(glm::vec3(-0.5f, 0.5f, 1.0f)), glm::vec3(1.0f)};
}

float material_alpha(const ShadeContext& ctx, const scene::Material& m, const FragmentInput& in) {
    float a = m.base_color.a;
    if (in.has_uv)
        if (const scene::Texture* t = texture_of(ctx, m.base_color_texture))
            a = a * sample_texture(*t, m.base_color_texture.sampler, in.uv).a;  // level 0: docs/raster.md
    return a * in.color.a;
}

namespace {
//! The textures a material samples (texture_of of each reference), looked up once per batch.
struct MaterialTextures {
    const scene::Texture* base = nullptr;
    const scene::Texture* normal = nullptr;
    const scene::Texture* ctrl[scene::kNumControlTargets] = {};
    MaterialTextures(const ShadeContext& ctx, const scene::Material& m)
        : base(texture_of(ctx, m.base_color_texture)), normal(texture_of(ctx, m.normal_texture)) {
        for (int k = 0; k < scene::kNumControlTargets; ++k) ctrl[k] = texture_of(ctx, m.wc.control_texture[k]);
    }
};

// Step 1 of the material, inlined into the shading paths (per fragment). `sample`: the base
// colour texture's value at in.uv when the caller sampled it already (shade_fragments), else null.
// base_color_product: the step before its conversion to the working space (shade_fragments
// converts eight lanes at once).
[[gnu::always_inline]] inline glm::vec3 base_color_product(const scene::Material& m, const scene::Texture* base_texture,
                                                           const FragmentInput& in, const glm::vec4* sample) {
    glm::vec3 C(m.base_color);
    if (in.has_uv)
        if (const scene::Texture* t = base_texture)
            C = C * glm::vec3(sample ? *sample : sample_texture(*t, m.base_color_texture.sampler, in.uv, in.uv_grad));
    return C * glm::vec3(in.color);
}
[[gnu::always_inline]] inline glm::vec3 base_color_step(const ShadeContext& ctx, const scene::Material& m,
                                                        const scene::Texture* base_texture, const FragmentInput& in,
                                                        const glm::vec4* sample = nullptr) {
    return base_color_to_working(base_color_product(m, base_texture, in, sample), m.linear_color, ctx.working_space);
}
}  // namespace

glm::vec3 base_color_working(const ShadeContext& ctx, const scene::Material& m, const FragmentInput& in) {
    return base_color_step(ctx, m, texture_of(ctx, m.base_color_texture), in);
}

// ---- The material, lane-generic ------------------------------------------------------------
// The maths of shade_fragment is written once (shade_lanes) over a lane type: one fragment in
// float / glm::vec3, or eight fragments in simd::v8f / lanes::Lanes3 (shade_fragments). Every lane
// operation is the scalar one (element-wise IEEE, operands in the same order, branches as
// selects of both computed values), so a batch gives each fragment the bits shade_fragment gives
// it. Texture fetches and powf stay per fragment (scalar calls on each lane).
namespace {

// The lane vocabulary (core/lanes.h): scalar and eight-lane forms of one set of functions.
using simd::v8f;
using simd::v8i;
using namespace lanes;

// The WC17 / MNPR pure functions of material.h, lane-generic (the float forms call these).
template <class F> inline F diffuse_factor_of(F n_dot_l, float shade_wrap, float k) {
    const F wrapped = sat((n_dot_l + shade_wrap) / (1.0f + shade_wrap));
    return 1.0f + (wrapped - 1.0f) * k;
}
template <class F> inline F dilute_area_of(F l_dot_n, float dA) {
    const float a = std::min(std::max(dA, kMinDiluteArea), 1.0f);
    return max_of((l_dot_n + (a - 1.0f)) / a, F{});
}
template <class F, class V> inline V cangiante_of(const V& C, F DA, float c) {
    const F k = DA * c;
    return {C.x + k, C.y + k, C.z + k};  // C + vec3(DA * c)
}
template <class F, class V> inline V dilution_of(const V& Cc, F DA, float d, glm::vec3 Cp) {
    const F k = d * DA;
    return k * (Cp - Cc) + Cc;
}
template <class F, class V>
inline V reflectance_of(const V& C, F l_dot_n, float dA, float c, float d, glm::vec3 Cp) {
    const F DA = dilute_area_of(l_dot_n, dA);
    return dilution_of(cangiante_of(C, DA, c), DA, d, Cp);
}

//! What shade_lanes reads: per-lane values prepared by the caller (gathers and texture fetches).
template <class F, class V, class M>
struct LaneInput {
    V C;               //!< base colour in the working space (step 1)
    V normal;          //!< interpolated, not normalised
    V view_pos;
    M back;            //!< back face
    bool normal_map = false;  //!< the fields below hold a normal-map sample and the tangent
    V nmap;            //!< normal texture sample (rgb)
    V tangent;         //!< interpolated tangent xyz
    F tangent_w{};
    V ctrl[scene::kNumControlTargets];      //!< interpolated per-vertex control
    V ctrl_tex[scene::kNumControlTargets];  //!< control texture samples (rgb) where the material has them
    bool has_ctrl_tex[scene::kNumControlTargets] = {};
};

template <class F, class V>
struct LaneOutput {
    V color;  //!< rgb (alpha 1)
    V ctrl[scene::kNumControlTargets];
    V normal;
    F diffuse, specular;
};

//! Steps 2-6 of the material (docs/raster.md "Material") on one fragment or eight.
template <class F, class V, class M>
LaneOutput<F, V> shade_lanes(const ShadeContext& ctx, const scene::Material& m, const LaneInput<F, V, M>& in) {
    LaneOutput<F, V> out;
    const scene::WatercolorMaterial& wc = m.wc;
    // 2. Normal: normalise, tangent-space normal map, double-sided back faces flipped.
    V N = normalize3(in.normal);
    if (in.normal_map) {
        const V& s = in.nmap;
        const float sc = m.normal_texture.scale;
        const V tn{(s.x * 2.0f - 1.0f) * sc, (s.y * 2.0f - 1.0f) * sc, s.z * 2.0f - 1.0f};
        const V T = normalize3(in.tangent);
        const V Bt = cross3(N, T) * sign_of(in.tangent_w);
        N = normalize3((T * tn.x + Bt * tn.y) + N * tn.z);
    }
    if (m.double_sided) N = select(in.back, -N, N);
    const V V_ = ctx.perspective ? normalize3(-in.view_pos) : V{splat<F>(0.0f), splat<F>(0.0f), splat<F>(1.0f)};

    // 3. Lights: MNPR diffuse factor per light, Blinn-Phong specular.
    V diffuse{splat<F>(ctx.ambient.x), splat<F>(ctx.ambient.y), splat<F>(ctx.ambient.z)};
    V spec{F{}, F{}, F{}};
    F ndl0{}, df0 = splat<F>(1.0f), spec0{};
    for (std::size_t l = 0; l < ctx.lights.size(); ++l) {
        const ViewLight& L = ctx.lights[l];
        const F ndl = (N.x * L.dir.x + N.y * L.dir.y) + N.z * L.dir.z;  // dot3(N, L.dir)
        const F df = diffuse_factor_of(ndl, wc.shade_wrap, wc.diffuse_factor);
        diffuse = diffuse + L.radiance * df;
        F s{};
        if (wc.specular > 0.0f) {
            const V H = normalize3(L.dir + V_);
            const F c = sat(dot3(N, H));
            s = wc.specular * each_lane(c, [&](float v, int) { return std::pow(v, wc.specular_power); });
            spec = spec + L.radiance * s;
        }
        if (l == 0) {
            ndl0 = ndl;
            df0 = df;
            spec0 = s;
        }
    }
    // 4. Lit colour with the shade colour on the unlit side of the key light.
    const V Clit = in.C * diffuse + wc.shade_color * (1.0f - df0);
    // 5. WC17 reflectance (eq. 3-5) with the key light, then specular, then clamp.
    const V Cd = reflectance_of(Clit, ndl0, wc.dilute_area, wc.cangiante, wc.dilute, ctx.substrate);
    out.color = sat(Cd + spec);

    // Control values: interpolated vertex + material constant + control texture (2 t - 1).
    for (int k = 0; k < scene::kNumControlTargets; ++k) {
        const glm::vec3 mc(wc.control[k]);
        V c = in.ctrl[k] + mc;
        if (in.has_ctrl_tex[k]) {
            const V& s = in.ctrl_tex[k];
            c = c + V{s.x * 2.0f - 1.0f, s.y * 2.0f - 1.0f, s.z * 2.0f - 1.0f};
        }
        out.ctrl[k] = {clamp1_of(c.x), clamp1_of(c.y), clamp1_of(c.z)};
    }
    out.normal = N;
    out.diffuse = sat(ndl0);
    out.specular = spec0;
    return out;
}

//! Which textures the fragments of a draw sample besides the base colour (normal map, control
//! textures): the material's textures where the fragment has uv (and tangents for the normal map).
struct SampledTextures {
    const scene::Texture* normal = nullptr;
    const scene::Texture* ctrl[scene::kNumControlTargets] = {};
    SampledTextures(const MaterialTextures& tex, const FragmentInput& in) {
        if (in.has_uv && in.has_tangent) normal = tex.normal;
        for (int k = 0; k < scene::kNumControlTargets; ++k) ctrl[k] = in.has_uv ? tex.ctrl[k] : nullptr;
    }
};

//! A fragment's texture values sampled already (shade_fragments samples a batch at once); a null
//! pointer: fill_lane samples that texture itself.
struct LaneSamples {
    const glm::vec4* base = nullptr;
    const glm::vec4* normal = nullptr;
    const glm::vec4* ctrl[scene::kNumControlTargets] = {};
};

//! Lane i of the inputs of shade_lanes from fragment `in`: step 1 (the base colour) and the
//! texture samples of `st` (the caller sets the uniform flags from the same `st`), taken from `ls`
//! where given. `unconverted`: step 1 without its conversion to the working space where the lane
//! computes it (no draw constant); the caller converts.
template <class F, class V, class M, class Put>
void fill_lane(const ShadeContext& ctx, const scene::Material& m, const MaterialTextures& tex,
               const SampledTextures& st, const FragmentInput& in, LaneInput<F, V, M>& li, Put&& put,
               const LaneSamples& ls = {}, bool unconverted = false) {
    put(li.C, in.base ? *in.base
                      : unconverted ? base_color_product(m, tex.base, in, ls.base)
                                    : base_color_step(ctx, m, tex.base, in, ls.base));
    put(li.normal, in.normal);
    put(li.view_pos, in.view_pos);
    if (st.normal) {
        put(li.nmap, glm::vec3(ls.normal ? *ls.normal : sample_texture(*st.normal, m.normal_texture.sampler, in.uv, in.uv_grad)));
        put(li.tangent, glm::vec3(in.tangent));
    }
    for (int k = 0; k < scene::kNumControlTargets; ++k) {
        put(li.ctrl[k], in.ctrl[k]);
        if (st.ctrl[k])
            put(li.ctrl_tex[k], glm::vec3(ls.ctrl[k] ? *ls.ctrl[k]
                                                    : sample_texture(*st.ctrl[k], m.wc.control_texture[k].sampler, in.uv,
                                                                     in.uv_grad)));
    }
}

//! put(field, _) on every field fill_lane writes for `st` (to copy a lane without recomputing it).
template <class F, class V, class M, class Put>
void fill_lane_copy(LaneInput<F, V, M>& li, Put&& put, const SampledTextures& st) {
    const glm::vec3 unused{};
    put(li.C, unused), put(li.normal, unused), put(li.view_pos, unused);
    if (st.normal) put(li.nmap, unused), put(li.tangent, unused);
    for (int k = 0; k < scene::kNumControlTargets; ++k) {
        put(li.ctrl[k], unused);
        if (st.ctrl[k]) put(li.ctrl_tex[k], unused);
    }
}

//! The uniform flags of shade_lanes' input from `st`.
template <class F, class V, class M>
void set_flags(const SampledTextures& st, LaneInput<F, V, M>& li) {
    li.normal_map = st.normal != nullptr;
    for (int k = 0; k < scene::kNumControlTargets; ++k) li.has_ctrl_tex[k] = st.ctrl[k] != nullptr;
}

//! 6. Object-space turbulence / fading (WC17 eq. 6) of one fragment, when selected.
glm::vec3 turbulence_step(const ShadeContext& ctx, glm::vec3 Cs, const glm::vec3 ctrl[]) {
    if (!ctx.object_space_turbulence) return Cs;
    return sat(turbulence(Cs, wc17_turbulence_ctrl(ctrl[scene::kCtrlPigment].z), ctx.substrate));
}

}  // namespace

float diffuse_factor(float n_dot_l, float shade_wrap, float k) { return diffuse_factor_of(n_dot_l, shade_wrap, k); }

float dilute_area(float l_dot_n, float dA) { return dilute_area_of(l_dot_n, dA); }

glm::vec3 cangiante(glm::vec3 C, float DA, float c) { return cangiante_of(C, DA, c); }

glm::vec3 dilution(glm::vec3 Cc, float DA, float d, glm::vec3 Cp) { return dilution_of(Cc, DA, d, Cp); }

glm::vec3 reflectance(glm::vec3 C, float l_dot_n, float dA, float c, float d, glm::vec3 Cp) {
    return reflectance_of(C, l_dot_n, dA, c, d, Cp);
}

FragmentOutput shade_fragment(const ShadeContext& ctx, const scene::Material& m, const FragmentInput& in) {
    const MaterialTextures tex(ctx, m);
    const SampledTextures st(tex, in);
    LaneInput<float, glm::vec3, bool> li;
    set_flags(st, li);
    li.back = in.back;
    li.tangent_w = in.tangent.w;
    fill_lane(ctx, m, tex, st, in, li, [](glm::vec3& d, glm::vec3 v) { d = v; });
    const LaneOutput<float, glm::vec3> lo = shade_lanes(ctx, m, li);
    FragmentOutput out;
    for (int k = 0; k < scene::kNumControlTargets; ++k) out.ctrl[k] = lo.ctrl[k];
    out.color = glm::vec4(turbulence_step(ctx, lo.color, out.ctrl), 1.0f);
    out.normal = lo.normal;
    out.diffuse = lo.diffuse;
    out.specular = lo.specular;
    return out;
}

void shade_fragments(const ShadeContext& ctx, const scene::Material& m, const FragmentInput* in, int n,
                     FragmentLanes& out) {
    if (n < 1 || n > FragmentLanes::kLanes) throw Error("shade_fragments: 1 to 8 fragments");
    const MaterialTextures tex(ctx, m);
    // Which textures are sampled depends on the fragment's uv and tangents (per draw): a batch
    // whose fragments differ there is shaded one by one.
    for (int i = 1; i < n; ++i)
        if (in[i].has_uv != in[0].has_uv || in[i].has_tangent != in[0].has_tangent) {
            for (int j = 0; j < n; ++j) out.set(j, shade_fragment(ctx, m, in[j]));
            return;
        }
    const SampledTextures st(tex, in[0]);
    // The batch's textures sampled at once (sample_texture8): the base colour where a lane computes
    // it (no draw constant), the normal map and control textures of `st`.
    constexpr int L = FragmentLanes::kLanes;
    glm::vec2 uv[L];
    UvGrad grad[L];
    for (int i = 0; i < n; ++i) uv[i] = in[i].uv, grad[i] = in[i].uv_grad;
    bool base_needed = false;
    if (tex.base && in[0].has_uv)
        for (int i = 0; i < n && !base_needed; ++i) base_needed = in[i].base == nullptr;
    glm::vec4 base_s[L], normal_s[L], ctrl_s[scene::kNumControlTargets][L];
    if (base_needed) sample_texture8(*tex.base, m.base_color_texture.sampler, uv, grad, n, base_s);
    if (st.normal) sample_texture8(*st.normal, m.normal_texture.sampler, uv, grad, n, normal_s);
    for (int k = 0; k < scene::kNumControlTargets; ++k)
        if (st.ctrl[k]) sample_texture8(*st.ctrl[k], m.wc.control_texture[k].sampler, uv, grad, n, ctrl_s[k]);
    auto samples_of = [&](int i) {
        LaneSamples ls;
        ls.base = base_needed ? &base_s[i] : nullptr;
        ls.normal = st.normal ? &normal_s[i] : nullptr;
        for (int k = 0; k < scene::kNumControlTargets; ++k) ls.ctrl[k] = st.ctrl[k] ? &ctrl_s[k][i] : nullptr;
        return ls;
    };
    LaneInput<v8f, Lanes3, v8i> li;
    set_flags(st, li);
    v8i back{};
    v8f tangent_w{};
    // Step 1's sRGB encode of a linear material colour (base_color_to_working) in the lanes that
    // compute step 1: after the loop, eight lanes at once (linear_to_srgb8, the same bits).
    const bool encode_later = m.linear_color && ctx.working_space == WorkingSpace::Display;
    v8i encode{};
    for (int i = 0; i < FragmentLanes::kLanes; ++i) {
        // Lanes past n repeat lane 0 (their results are not used).
        if (i >= n) {
            auto copy0 = [&](Lanes3& d, glm::vec3) {
                d.x[i] = d.x[0], d.y[i] = d.y[0], d.z[i] = d.z[0];
            };
            fill_lane_copy(li, copy0, st);
            back[i] = back[0], tangent_w[i] = tangent_w[0], encode[i] = encode[0];
            continue;
        }
        encode[i] = encode_later && !in[i].base ? -1 : 0;
        fill_lane(ctx, m, tex, st, in[i], li, [i](Lanes3& d, glm::vec3 v) { d.x[i] = v.x, d.y[i] = v.y, d.z[i] = v.z; },
                  samples_of(i), encode[i] != 0);
        back[i] = in[i].back ? -1 : 0;
        tangent_w[i] = in[i].tangent.w;
    }
    if (!simd::all_zero(encode)) {
        Lanes3 e = sat(li.C);
        linear_to_srgb8(e.x, e.y, e.z);
        li.C = select(encode, e, li.C);
    }
    li.back = back;
    li.tangent_w = tangent_w;
    const LaneOutput<v8f, Lanes3> lo = shade_lanes(ctx, m, li);
    auto put = [](float* d, v8f v) { simd::store8(d, v); };
    put(out.color[0], lo.color.x), put(out.color[1], lo.color.y), put(out.color[2], lo.color.z);
    for (int k = 0; k < scene::kNumControlTargets; ++k)
        put(out.ctrl[k][0], lo.ctrl[k].x), put(out.ctrl[k][1], lo.ctrl[k].y), put(out.ctrl[k][2], lo.ctrl[k].z);
    put(out.normal[0], lo.normal.x), put(out.normal[1], lo.normal.y), put(out.normal[2], lo.normal.z);
    put(out.diffuse, lo.diffuse), put(out.specular, lo.specular);
    if (ctx.object_space_turbulence)
        for (int i = 0; i < n; ++i) {
            glm::vec3 ctrl[scene::kNumControlTargets];
            for (int k = 0; k < scene::kNumControlTargets; ++k)
                ctrl[k] = {out.ctrl[k][0][i], out.ctrl[k][1][i], out.ctrl[k][2][i]};
            const glm::vec3 Cs = turbulence_step(ctx, {out.color[0][i], out.color[1][i], out.color[2][i]}, ctrl);
            out.color[0][i] = Cs.x, out.color[1][i] = Cs.y, out.color[2][i] = Cs.z;
        }
}

}  // namespace aq::raster
