// raster/material.cpp — the watercolor material (spec §3; WC17 eq. 3-6). See material.h.
#include "raster/material.h"

#include <cmath>

namespace aq::raster {

namespace {
constexpr float kMinDiluteArea = 0.01f;  // WC17: dA in (0, 1]
inline float clamp1(float v) { return std::min(std::max(v, -1.0f), 1.0f); }

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
    return t.image.empty() ? nullptr : &t;
}


glm::vec3 base_color_to_working(glm::vec3 C, bool linear_color, WorkingSpace ws) {
    if (linear_color && ws == WorkingSpace::Display)
        return {linear_to_srgb(sat(C.x)), linear_to_srgb(sat(C.y)), linear_to_srgb(sat(C.z))};
    if (!linear_color && ws == WorkingSpace::Linear)
        return {srgb_to_linear(C.x), srgb_to_linear(C.y), srgb_to_linear(C.z)};
    return C;
}

float diffuse_factor(float n_dot_l, float shade_wrap, float k) {
    const float wrapped = sat((n_dot_l + shade_wrap) / (1.0f + shade_wrap));
    return 1.0f + (wrapped - 1.0f) * k;
}

float dilute_area(float l_dot_n, float dA) {
    const float a = std::min(std::max(dA, kMinDiluteArea), 1.0f);
    return std::max((l_dot_n + (a - 1.0f)) / a, 0.0f);
}

glm::vec3 cangiante(glm::vec3 C, float DA, float c) { return C + glm::vec3(DA * c); }

glm::vec3 dilution(glm::vec3 Cc, float DA, float d, glm::vec3 Cp) {
    const float k = d * DA;
    return k * (Cp - Cc) + Cc;
}

glm::vec3 reflectance(glm::vec3 C, float l_dot_n, float dA, float c, float d, glm::vec3 Cp) {
    const float DA = dilute_area(l_dot_n, dA);
    return dilution(cangiante(C, DA, c), DA, d, Cp);
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
//! The sampling maths, once for both texel stores: fetch(x, y) is the widened RGBA texel.
template <class Fetch>
inline glm::vec4 sample_with(int w, int h, const scene::Sampler& s, glm::vec2 uv, const Fetch& fetch) {
    const float u = safe_coord(uv.x) * float(w), v = safe_coord(uv.y) * float(h);
    if (s.mag == scene::Filter::Nearest) {
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
    const glm::vec4 top = lerp4(fetch(x0, y0), fetch(x1, y0), tx);
    const glm::vec4 bot = lerp4(fetch(x0, y1), fetch(x1, y1), tx);
    return lerp4(top, bot, ty);
}
}  // namespace

glm::vec4 sample_texture(const ImageF& img, const scene::Sampler& s, glm::vec2 uv) {
    return sample_with(img.width(), img.height(), s, uv, [&](int x, int y) { return texel(img, x, y); });
}

glm::vec4 sample_texture(const scene::Texture& t, const scene::Sampler& s, glm::vec2 uv) {
    const ImageF& img = t.image;
    if (t.codes.empty()) return sample_texture(img, s, uv);
    const std::uint8_t* codes = t.codes.codes.data();
    const auto& lut = t.codes.lut;
    const int w = img.width();
    return sample_with(w, img.height(), s, uv, [&](int x, int y) {
        const std::uint8_t* c = codes + 4 * (std::size_t(y) * std::size_t(w) + std::size_t(x));
        return glm::vec4(lut[0][c[0]], lut[1][c[1]], lut[2][c[2]], lut[3][c[3]]);
    });
}

ViewLight default_view_light() {
    return {normalize3(glm::vec3(-0.5f, 0.5f, 1.0f)), glm::vec3(1.0f)};
}

float material_alpha(const ShadeContext& ctx, const scene::Material& m, const FragmentInput& in) {
    float a = m.base_color.a;
    if (in.has_uv)
        if (const scene::Texture* t = texture_of(ctx, m.base_color_texture))
            a = a * sample_texture(*t, m.base_color_texture.sampler, in.uv).a;
    return a * in.color.a;
}

namespace {
// Step 1 of the material, inlined into shade_fragment (the per-fragment path).
[[gnu::always_inline]] inline glm::vec3 base_color_step(const ShadeContext& ctx, const scene::Material& m,
                                                        const FragmentInput& in) {
    glm::vec3 C(m.base_color);
    if (in.has_uv)
        if (const scene::Texture* t = texture_of(ctx, m.base_color_texture))
            C = C * glm::vec3(sample_texture(*t, m.base_color_texture.sampler, in.uv));
    C = C * glm::vec3(in.color);
    return base_color_to_working(C, m.linear_color, ctx.working_space);
}
}  // namespace

glm::vec3 base_color_working(const ShadeContext& ctx, const scene::Material& m, const FragmentInput& in) {
    return base_color_step(ctx, m, in);
}

FragmentOutput shade_fragment(const ShadeContext& ctx, const scene::Material& m,
                              const FragmentInput& in) {
    FragmentOutput out;
    const scene::WatercolorMaterial& wc = m.wc;
    // 1. Base colour: factor x texture x COLOR_0, then into the working space (docs/look.md).
    const glm::vec3 C = in.base ? *in.base : base_color_step(ctx, m, in);

    // 2. Normal: normalise, tangent-space normal map, double-sided back faces flipped.
    glm::vec3 N = normalize3(in.normal);
    if (in.has_uv && in.has_tangent)
        if (const scene::Texture* t = texture_of(ctx, m.normal_texture)) {
            const glm::vec4 s = sample_texture(*t, m.normal_texture.sampler, in.uv);
            const float sc = m.normal_texture.scale;
            const glm::vec3 tn((s.x * 2.0f - 1.0f) * sc, (s.y * 2.0f - 1.0f) * sc, s.z * 2.0f - 1.0f);
            const glm::vec3 T = normalize3(glm::vec3(in.tangent));
            const glm::vec3 Bt = glm::cross(N, T) * (in.tangent.w < 0.0f ? -1.0f : 1.0f);
            N = normalize3((T * tn.x + Bt * tn.y) + N * tn.z);
        }
    if (in.back && m.double_sided) N = -N;
    const glm::vec3 V = ctx.perspective ? normalize3(-in.view_pos) : glm::vec3(0, 0, 1);

    // 3. Lights: MNPR diffuse factor per light, Blinn-Phong specular.
    glm::vec3 diffuse = ctx.ambient;
    glm::vec3 spec(0.0f);
    float ndl0 = 0.0f, df0 = 1.0f, spec0 = 0.0f;
    for (std::size_t l = 0; l < ctx.lights.size(); ++l) {
        const ViewLight& L = ctx.lights[l];
        const float ndl = dot3(N, L.dir);
        const float df = diffuse_factor(ndl, wc.shade_wrap, wc.diffuse_factor);
        diffuse = diffuse + L.radiance * df;
        float s = 0.0f;
        if (wc.specular > 0.0f) {
            const glm::vec3 H = normalize3(L.dir + V);
            s = wc.specular * std::pow(sat(dot3(N, H)), wc.specular_power);
            spec = spec + L.radiance * s;
        }
        if (l == 0) {
            ndl0 = ndl;
            df0 = df;
            spec0 = s;
        }
    }
    // 4. Lit colour with the shade colour on the unlit side of the key light.
    const glm::vec3 Clit = C * diffuse + wc.shade_color * (1.0f - df0);
    // 5. WC17 reflectance (eq. 3-5) with the key light, then specular, then clamp.
    const glm::vec3 Cd = reflectance(Clit, ndl0, wc.dilute_area, wc.cangiante, wc.dilute, ctx.substrate);
    glm::vec3 Cs = sat(Cd + spec);

    // Control values: interpolated vertex + material constant + control texture (2 t - 1).
    for (int k = 0; k < scene::kNumControlTargets; ++k) {
        glm::vec3 c = in.ctrl[k] + glm::vec3(wc.control[k]);
        if (in.has_uv)
            if (const scene::Texture* t = texture_of(ctx, wc.control_texture[k])) {
                const glm::vec4 s = sample_texture(*t, wc.control_texture[k].sampler, in.uv);
                c = c + (glm::vec3(s) * 2.0f - 1.0f);
            }
        out.ctrl[k] = {clamp1(c.x), clamp1(c.y), clamp1(c.z)};
    }
    // 6. Object-space turbulence / fading (WC17 eq. 6) when selected.
    if (ctx.object_space_turbulence)
        Cs = sat(turbulence(Cs, wc17_turbulence_ctrl(out.ctrl[scene::kCtrlPigment].z), ctx.substrate));

    out.color = glm::vec4(Cs, 1.0f);
    out.normal = N;
    out.diffuse = sat(ndl0);
    out.specular = spec0;
    return out;
}

}  // namespace aq::raster
