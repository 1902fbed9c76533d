// raster/material.h — the watercolor material (fragment stage, spec §3): base colour, textures,
// normal maps, directional lights with MNPR's diffuse factor / shade wrap / shade colour,
// Blinn-Phong specular, the WC17 reflectance model (eq. 3-5) and the object-space pigment
// turbulence and fading (eq. 6).
//
// Every formula is a small pure function so tests and the GLSL twin (reference/) can mirror it;
// the order of operations is the one written here and in docs/raster.md ("Material"). All maths
// is float, no FMA (-ffp-contract=off), left-to-right as written.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "core/lanes.h"
#include "raster/raster.h"

namespace aq::raster {

// One-value forms of the lane vocabulary the material is written in (core/lanes.h).
using lanes::dot3;
using lanes::normalize3;
using lanes::sat;

//! The base colour (factor x texture x COLOR_0) in the working space: a glTF material
//! (linear_color) is clamped to [0, 1] and encoded to sRGB for the display-referred space; a
//! display-valued material (procedural, linear_color false) is decoded for the linear space;
//! otherwise unchanged.
glm::vec3 base_color_to_working(glm::vec3 C, bool linear_color, WorkingSpace ws);

// ---- WC17 / MNPR shading maths (pure) -------------------------------------------------------

//! MNPR diffuse factor with shade wrap: DF = lerp(1, sat((N.L + wrap) / (1 + wrap)), k),
//! lerp(a, b, t) = a + (b - a) * t.
float diffuse_factor(float n_dot_l, float shade_wrap, float k);

//! WC17 eq. 3, dilute area DA = (L.N + (dA - 1)) / dA, clamped below at 0 (docs/raster.md: with
//! dA < 1 the unclamped value goes to -(1 - dA)/dA - 1 on the dark side, which would push colours
//! away from the paper instead of leaving them undiluted). dA is clamped to [0.01, 1].
float dilute_area(float l_dot_n, float dA);

//! WC17 eq. 4, cangiante colour Cc = C + DA * c.
glm::vec3 cangiante(glm::vec3 C, float DA, float c);

//! WC17 eq. 5, dilution Cd = d * DA * (Cp - Cc) + Cc, evaluated as ((d * DA) * (Cp - Cc)) + Cc.
glm::vec3 dilution(glm::vec3 Cc, float DA, float d, glm::vec3 Cp);

//! WC17 eq. 3-5 composed: DA from (L.N, dA), then cangiante, then dilution. Not clamped.
glm::vec3 reflectance(glm::vec3 C, float l_dot_n, float dA, float cangiante_c, float dilute_d,
                      glm::vec3 Cp);

//! WC17 eq. 6 pigment turbulence / fading with the WC17 control value ctrl in [0, 1]:
//! ctrl < 0.5: C^(3 - ctrl*4) per channel (C clamped to >= 0); else ((ctrl - 0.5) * 2) * (Cp - C) + C.
glm::vec3 turbulence(glm::vec3 C, float ctrl, glm::vec3 Cp);

//! The WC17 turbulence control derived from ctrl.pigment.b (density, + accumulate / - dilute,
//! spec §1): ctrl = 0.5 - 0.5 * b. b = 0 is neutral (0.5), b = 1 accumulates fully (C^3),
//! b = -1 fades fully to the paper.
inline float wc17_turbulence_ctrl(float pigment_density) { return 0.5f - 0.5f * pigment_density; }

// ---- Textures ---------------------------------------------------------------------------------

struct ShadeContext;
//! The scene texture a reference names, or null (no texture, index out of range, empty image).
const scene::Texture* texture_of(const ShadeContext& ctx, const scene::TextureRef& r);

//! Integer texel coordinate with a glTF/GL wrap mode (MIRRORED_REPEAT mirrors with edge repeat,
//! period 2n).
int wrap_texel(int i, int n, scene::Wrap w);

//! Samples level 0 of a texture at uv with the magnification filter (GL conventions: texel
//! centres at (i + 0.5) / n, v = 0 at row 0). Linear: bilinear of the 4 nearest texels; Nearest:
//! floor(u * n). Non-finite uv reads texel (0, 0).
//! Channels are widened to RGBA: 1 -> (g, g, g, 1), 2 -> (r, g, 0, 1), 3 -> (r, g, b, 1).
glm::vec4 sample_texture(const ImageF& img, const scene::Sampler& s, glm::vec2 uv);
//! The same value for a scene texture, read through its 8-bit codes where it has them
//! (scene::TextureCodes: a quarter of the bytes, the same texel values).
glm::vec4 sample_texture(const scene::Texture& t, const scene::Sampler& s, glm::vec2 uv);

//! A fragment's texture-coordinate derivatives per pixel, d uv / d x and d uv / d y (the
//! rasterizer's analytic derivatives of the perspective-correct interpolation; zero: none).
struct UvGrad {
    glm::vec2 dx{0.0f}, dy{0.0f};
};

//! Most samples along an anisotropic footprint (GL's usual MAX_TEXTURE_MAX_ANISOTROPY).
inline constexpr int kMaxAnisotropy = 16;

//! The anisotropic footprint of a pixel (the GL anisotropic filtering extension's model): with
//! P_x = |dx * (w, h)| and P_y = |dy * (w, h)| in level-0 texels, `samples` N = min(ceil(P_max /
//! P_min), kMaxAnisotropy) probes along the major axis (`major`: dx or dy in uv), each at
//! lambda = log2(P_max / N). N = 1 is GL's isotropic filtering.
struct AnisoFootprint {
    int samples = 1;
    float lod = 0.0f;
    //! GL's isotropic level of detail (GL 4.6 §8.14.1, no bias), log2(P_max): <= c is
    //! magnification, whatever N; -inf for zero derivatives, NaN for non-finite ones.
    float iso_lod = 0.0f;
    glm::vec2 major{0.0f};
};
AnisoFootprint aniso_footprint(int w, int h, const UvGrad& g);

//! Samples a texture as GL does with mipmaps (GL 4.6 §8.14-8.15) and anisotropic filtering.
//! iso_lod (aniso_footprint) <= c (c = 0.5 for a LINEAR magnification with a NEAREST_MIPMAP_*
//! minification, else 0), or not a number: magnification, sample_texture above (no axis of the
//! footprint spans more than a texel). Otherwise, with one probe, the minification filter `min` within a level and `mip` between levels: None,
//! level 0; Nearest, level ceil(lambda + 1/2) - 1 (0 for lambda <= 1/2); Linear, levels
//! floor(lambda) and floor(lambda) + 1 blended by the fraction of lambda. Levels past the last
//! (Texture::mips) read the last. With N > 1 probes: the mean of N such minified samples at
//! uv + major * ((i + 1/2) / N - 1/2).
glm::vec4 sample_texture(const scene::Texture& t, const scene::Sampler& s, glm::vec2 uv, const UvGrad& g);

// ---- The fragment ------------------------------------------------------------------------------

//! Interpolated vertex data of one fragment (view space).
struct FragmentInput {
    glm::vec3 view_pos{0};
    glm::vec3 normal{0, 0, 1};     //!< interpolated, not yet normalised
    glm::vec4 tangent{0};          //!< interpolated xyz + handedness; valid if has_tangent
    glm::vec2 uv{0};
    UvGrad uv_grad;                //!< d uv / d x, d uv / d y (valid if has_uv)
    glm::vec4 color{1};            //!< COLOR_0 (1 if absent)
    glm::vec3 ctrl[scene::kNumControlTargets]{};  //!< interpolated per-vertex control RGB
    bool has_tangent = false, has_uv = false, back = false;
    //! base_color_working of this fragment computed once for its draw, where it cannot vary over
    //! the draw (no COLOR_0, no base colour texture or no uv: the draw's constant colour); null:
    //! computed per fragment. Schedule only: the same value either way.
    const glm::vec3* base = nullptr;
};

struct ViewLight {
    glm::vec3 dir;     //!< unit, view space, towards the light
    glm::vec3 radiance;//!< colour * intensity
};

//! Per-render constants of the fragment stage.
struct ShadeContext {
    const scene::Scene* scene = nullptr;
    std::vector<ViewLight> lights;  //!< at least one
    glm::vec3 ambient{0};
    bool perspective = true;
    glm::vec3 substrate{1};
    bool object_space_turbulence = false;
    WorkingSpace working_space = WorkingSpace::Display;  //!< see base_color_to_working
};

struct FragmentOutput {
    glm::vec4 color{0};
    glm::vec3 ctrl[scene::kNumControlTargets]{};
    glm::vec3 normal{0};
    float diffuse = 0, specular = 0;
};

//! Material alpha: base_color.a * texture.a * COLOR_0.a (for alpha mode MASK). The texture's
//! alpha is read from level 0 with the magnification filter, never from mip levels: averaged
//! alpha falls below the cutoff with distance and alpha-tested leaves would thin out and vanish
//! (docs/raster.md "Texture filtering").
float material_alpha(const ShadeContext& ctx, const scene::Material& m, const FragmentInput& in);

//! Step 1 of the material: base colour factor x texture x COLOR_0, in the working space.
glm::vec3 base_color_working(const ShadeContext& ctx, const scene::Material& m, const FragmentInput& in);

//! The full watercolor material (docs/raster.md "Material" lists the order of operations).
FragmentOutput shade_fragment(const ShadeContext& ctx, const scene::Material& m,
                              const FragmentInput& in);

//! The outputs of up to eight fragments, one array per component (lane i: fragment i).
struct FragmentLanes {
    static constexpr int kLanes = 8;
    float color[3][kLanes];  //!< rgb; alpha is 1
    float ctrl[scene::kNumControlTargets][3][kLanes];
    float normal[3][kLanes];
    float diffuse[kLanes], specular[kLanes];
    //! Lane i from one fragment's output.
    void set(int i, const FragmentOutput& o) {
        for (int c = 0; c < 3; ++c) color[c][i] = o.color[c], normal[c][i] = o.normal[c];
        for (int k = 0; k < scene::kNumControlTargets; ++k)
            for (int c = 0; c < 3; ++c) ctrl[k][c][i] = o.ctrl[k][c];
        diffuse[i] = o.diffuse;
        specular[i] = o.specular;
    }
};

//! shade_fragment of in[0 .. n) (1 <= n <= 8) of one material at once: lane i holds exactly
//! shade_fragment(ctx, m, in[i]) (the same maths, eight fragments per vector operation; texture
//! fetches and powf per fragment). The fast traversal's shading schedule.
void shade_fragments(const ShadeContext& ctx, const scene::Material& m, const FragmentInput* in, int n,
                     FragmentLanes& out);

//! Default light when the scene has none: white, intensity 1, view-space direction
//! normalize(-0.5, 0.5, 1) (from the upper left, in front).
ViewLight default_view_light();

}  // namespace aq::raster
