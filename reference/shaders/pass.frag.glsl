// pass.frag.glsl — fragment stage of the LD06 raster-pass twin (raster/pass.cpp fragment()):
// the depth test mode (binary in GL's depth buffer; blurred LD06 eq. 1-2 against a depth map,
// optionally through the RGBA8 coding of eq. 3-4), the value (normalised depth, (1 + n.l) / 2,
// coverage, shadow intensity 1 - f_s of eq. 5) and the weight the blend mode needs. Blending itself
// is GL's: replace (none), add (ONE, ONE; clamped on readback: every contribution is >= 0, so the
// clamped sum equals the sequential clamp of eq. 12), over (ONE, ONE_MINUS_SRC_ALPHA).
#version 450 core
#include_ld06_common
#include_texture_filter
in vec3 v_view_pos;
in vec3 v_normal;
in vec2 v_uv;
in vec4 v_color;
out vec4 o_color;

uniform int u_value;        // 0 depth, 1 lighting, 2 coverage, 3 shadow, 4 intensity texture
uniform int u_test;         // 0 binary, 1 blurred, 2 blurred_rgba8
uniform int u_blend;        // 0 replace, 1 add, 2 over
uniform float u_delta, u_beta, u_alpha;
uniform float u_depth_near, u_depth_far;  // eye depth -> 0..1
uniform vec2 u_size;
uniform sampler2D s_depth;  // blurred depth map of this view
uniform vec3 u_light_view;  // unit light direction, pass view space
// Shadow value: view -> light view, the light's orthographic half extents and depth range.
uniform mat4 u_view_to_light;
uniform vec2 u_light_mag;
uniform float u_light_near, u_light_far;
uniform sampler2D s_shadow;
uniform int u_shadow_test;
uniform float u_shadow_delta, u_shadow_beta;
// Alpha mask (glTF MASK materials): base alpha x texture alpha x COLOR_0 alpha >= cutoff.
uniform bool u_alpha_mask;
uniform float u_alpha_cutoff, u_base_alpha;
uniform bool u_has_base_tex;
uniform sampler2D s_base;
// LD06 §4.3 intensity texture of the material (channel u_channel), 0 without one.
uniform bool u_has_intensity;
uniform int u_channel;
uniform sampler2D s_intensity;

// ld06_step, visibility, rgba8: ld06_common.glsl

void main() {
    if (u_alpha_mask) {
        float a = u_base_alpha * v_color.a;
        if (u_has_base_tex) a *= textureLod(s_base, v_uv, 0.0).a;  // level 0, as material_alpha
        if (a < u_alpha_cutoff) discard;
    }
    float fd = (-v_view_pos.z - u_depth_near) / (u_depth_far - u_depth_near);
    float fv = 1.0;
    if (u_test != 0) {
        float D = texture(s_depth, gl_FragCoord.xy / u_size).r;
        if (u_test == 2) D = rgba8(D);
        fv = visibility(D, fd, u_delta, u_beta);
    }
    float v = 1.0;
    if (u_value == 0) {
        v = clamp(fd, 0.0, 1.0);
    } else if (u_value == 1) {
        vec3 n = v_normal;
        float l2 = dot(n, n);
        n = l2 > 0.0 ? n * (1.0 / sqrt(l2)) : vec3(0.0, 0.0, 1.0);
        if (!gl_FrontFacing) n = -n;
        v = clamp((1.0 + dot(n, u_light_view)) * 0.5, 0.0, 1.0);
    } else if (u_value == 3) {
        vec4 p = u_view_to_light * vec4(v_view_pos, 1.0);
        vec2 uv = vec2(p.x / u_light_mag.x + 1.0, 1.0 - p.y / u_light_mag.y) * 0.5;
        float ld = (-p.z - u_light_near) / (u_light_far - u_light_near);
        float D = texture(s_shadow, uv).r;
        if (u_shadow_test == 2) D = rgba8(D);
        v = 1.0 - visibility(D, ld, u_shadow_test == 0 ? 0.0 : u_shadow_delta, u_shadow_beta);
    } else if (u_value == 4) {
        v = u_has_intensity ? aq_texture(s_intensity, v_uv)[u_channel] : 0.0;
    }
    if (u_blend == 2) {
        float a = fv * u_alpha;
        o_color = vec4(v * a, 0.0, 0.0, a);
    } else {
        o_color = vec4(fv * v, 0.0, 0.0, 0.0);
    }
}
