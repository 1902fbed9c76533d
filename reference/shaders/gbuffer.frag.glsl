// gbuffer.frag.glsl — the watercolor material of the G-buffer twin (spec §3; WC17 eq. 3-6):
// base colour factor x texture x COLOR_0 brought into the working space (glTF materials are linear
// and are clamped and sRGB-encoded for the display-referred space; display-valued materials are
// decoded for the linear space; docs/look.md); tangent-space normal map; double-sided back faces
// flipped; per light the MNPR diffuse factor DF = lerp(1, sat((N.L + wrap) / (1 + wrap)), k) and
// Blinn-Phong specular; lit colour C * sum(radiance DF) + ambient, shade colour on the unlit side of
// the key light; WC17 reflectance with the key light: DA = max((L.N + dA - 1) / dA, 0),
// Cc = C + DA c, Cd = d DA (Cp - Cc) + Cc; + specular, clamped; optional object-space turbulence
// (eq. 6). Control = interpolated vertex value + material constant + control texture (2t - 1),
// clamped to [-1, 1]. Textures are sampled with the scene's wrap and filters, mipmapped with the
// CPU's own levels (GL's level of detail from its derivatives; the CPU's are analytic).
#version 450 core
#include_texture_filter
in vec3 v_view_pos;
in vec3 v_normal;
in vec4 v_tangent;
in vec2 v_uv;
in vec4 v_color;
in vec3 v_ctrl[4];
in float v_depth;

layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_ctrl0;
layout(location = 2) out vec4 o_ctrl1;
layout(location = 3) out vec4 o_ctrl2;
layout(location = 4) out vec4 o_ctrl3;
layout(location = 5) out vec4 o_normal;
layout(location = 6) out vec4 o_misc;   // depth.linear, object_id, diffuse, specular

const int kMaxLights = 8;
uniform int u_num_lights;
uniform vec3 u_light_dir[kMaxLights];       // view space, towards the light
uniform vec3 u_light_radiance[kMaxLights];
uniform vec3 u_ambient;
uniform bool u_perspective;
uniform vec3 u_substrate;
uniform bool u_object_space_turbulence;
uniform bool u_working_linear;   // WorkingSpace::Linear (core/color.h)
uniform bool u_linear_color;     // Material::linear_color (glTF colour semantics)

uniform vec4 u_base_color;
uniform bool u_has_uv, u_has_tangent, u_double_sided, u_alpha_mask;
uniform float u_alpha_cutoff;
uniform bool u_has_base_tex, u_has_normal_tex;
uniform sampler2D s_base, s_normal;
uniform float u_normal_scale;
uniform bool u_has_ctrl_tex[4];
uniform sampler2D s_ctrl0, s_ctrl1, s_ctrl2, s_ctrl3;
uniform vec4 u_ctrl_const[4];

uniform float u_dilute, u_cangiante, u_diffuse_factor, u_dilute_area, u_shade_wrap;
uniform vec3 u_shade_color;
uniform float u_specular, u_specular_power;
uniform float u_object_id;

float sat(float x) { return clamp(x, 0.0, 1.0); }
vec3 safe_normalize(vec3 v) { float l2 = dot(v, v); return l2 > 0.0 ? v * (1.0 / sqrt(l2)) : v; }

// IEC 61966-2-1, as core/color.h.
float srgb_to_linear(float v) { return !(v > 0.04045) ? v / 12.92 : pow((v + 0.055) / (1.0 + 0.055), 2.4); }
float linear_to_srgb(float v) { return !(v > 0.0031308) ? v * 12.92 : (1.0 + 0.055) * pow(v, 1.0 / 2.4) - 0.055; }
vec3 base_color_to_working(vec3 c) {
    if (u_linear_color && !u_working_linear)
        return vec3(linear_to_srgb(sat(c.x)), linear_to_srgb(sat(c.y)), linear_to_srgb(sat(c.z)));
    if (!u_linear_color && u_working_linear) return vec3(srgb_to_linear(c.x), srgb_to_linear(c.y), srgb_to_linear(c.z));
    return c;
}

vec4 ctrl_tex(int k) {
    if (k == 0) return aq_texture(s_ctrl0, v_uv);
    if (k == 1) return aq_texture(s_ctrl1, v_uv);
    if (k == 2) return aq_texture(s_ctrl2, v_uv);
    return aq_texture(s_ctrl3, v_uv);
}

void main() {
    vec4 base = (u_has_uv && u_has_base_tex) ? aq_texture(s_base, v_uv) : vec4(1.0);
    // The alpha test reads level 0 (lod 0: the magnification filter), as raster/material.h material_alpha.
    float base_a = (u_has_uv && u_has_base_tex) ? textureLod(s_base, v_uv, 0.0).a : 1.0;
    if (u_alpha_mask && u_base_color.a * base_a * v_color.a < u_alpha_cutoff) discard;
    vec3 C = base_color_to_working(u_base_color.rgb * base.rgb * v_color.rgb);

    vec3 N = safe_normalize(v_normal);
    if (u_has_uv && u_has_tangent && u_has_normal_tex) {
        vec4 s = aq_texture(s_normal, v_uv);
        vec3 tn = vec3((s.xy * 2.0 - 1.0) * u_normal_scale, s.z * 2.0 - 1.0);
        vec3 T = safe_normalize(v_tangent.xyz);
        vec3 B = cross(N, T) * (v_tangent.w < 0.0 ? -1.0 : 1.0);
        N = safe_normalize(T * tn.x + B * tn.y + N * tn.z);
    }
    if (!gl_FrontFacing && u_double_sided) N = -N;
    vec3 V = u_perspective ? safe_normalize(-v_view_pos) : vec3(0.0, 0.0, 1.0);

    vec3 diffuse = u_ambient, spec = vec3(0.0);
    float ndl0 = 0.0, df0 = 1.0, spec0 = 0.0;
    for (int l = 0; l < u_num_lights; ++l) {
        float ndl = dot(N, u_light_dir[l]);
        float df = mix(1.0, sat((ndl + u_shade_wrap) / (1.0 + u_shade_wrap)), u_diffuse_factor);
        diffuse += u_light_radiance[l] * df;
        float s = 0.0;
        if (u_specular > 0.0) {
            vec3 H = safe_normalize(u_light_dir[l] + V);
            s = u_specular * pow(sat(dot(N, H)), u_specular_power);
            spec += u_light_radiance[l] * s;
        }
        if (l == 0) { ndl0 = ndl; df0 = df; spec0 = s; }
    }
    vec3 clit = C * diffuse + u_shade_color * (1.0 - df0);
    float dA = clamp(u_dilute_area, 0.01, 1.0);
    float DA = max((ndl0 + (dA - 1.0)) / dA, 0.0);                  // WC17 eq. 3
    vec3 cc = clit + vec3(DA * u_cangiante);                        // eq. 4
    vec3 cd = (u_dilute * DA) * (u_substrate - cc) + cc;            // eq. 5
    vec3 cs = clamp(cd + spec, 0.0, 1.0);

    vec3 ctrl[4];
    for (int k = 0; k < 4; ++k) {
        vec3 c = v_ctrl[k] + u_ctrl_const[k].rgb;
        if (u_has_uv && u_has_ctrl_tex[k]) c += ctrl_tex(k).rgb * 2.0 - 1.0;
        ctrl[k] = clamp(c, -1.0, 1.0);
    }
    if (u_object_space_turbulence) {                                // WC17 eq. 6
        float t = 0.5 - 0.5 * ctrl[0].z;
        cs = t < 0.5 ? pow(max(cs, vec3(0.0)), vec3(3.0 - t * 4.0)) : ((t - 0.5) * 2.0) * (u_substrate - cs) + cs;
        cs = clamp(cs, 0.0, 1.0);
    }
    o_color = vec4(cs, 1.0);
    o_ctrl0 = vec4(ctrl[0], 1.0);
    o_ctrl1 = vec4(ctrl[1], 1.0);
    o_ctrl2 = vec4(ctrl[2], 1.0);
    o_ctrl3 = vec4(ctrl[3], 1.0);
    o_normal = vec4(N, 0.0);
    o_misc = vec4(v_depth, u_object_id, sat(ndl0), spec0);
}
