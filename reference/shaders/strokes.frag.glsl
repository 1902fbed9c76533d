// strokes.frag.glsl — fragment stage of the LD06 stroke twin (raster/strokes.h, LD06 §4.4),
// written from docs/ld06.md "Strokes": a pixel is covered when its centre lies within half the
// width of the projected segment; the nearest segment of the stroke wins through the depth test
// (gl_FragDepth grows with the squared distance; GL_LESS keeps the first segment on a tie). Its
// alpha: alpha x f_v (eq. 2 against the depth map at the pixel) x the distance fade x the n.v fade
// (segments with normals) x, for hatching strokes, the n.l fade; depth and normal at the nearest
// point, perspective-correct along the segment.
#version 450 core
#include_ld06_common
flat in vec3 v_pa, v_pb, v_na, v_nb;
flat in vec4 v_seg;
flat in float v_has_normal;

uniform vec2 u_size;
uniform float u_r2;  // (half width)^2
uniform bool u_ortho;
uniform float u_depth_near, u_depth_far;
uniform int u_test;  // 0 binary, 1 blurred, 2 blurred_rgba8
uniform bool u_has_depth;
uniform float u_delta, u_beta, u_alpha;
uniform float u_fade_near, u_fade_far, u_nv_lo, u_nv_hi, u_nl_lo, u_nl_hi;
uniform bool u_hatching;
uniform vec3 u_light_view;
uniform sampler2D s_depth;

layout(location = 0) out vec4 o_color;

void main() {
    vec2 p = gl_FragCoord.xy;  // pixel centre (x + 0.5, y + 0.5), y down (see strokes.vert.glsl)
    vec2 a = v_seg.xy, d = v_seg.zw - v_seg.xy;
    float len2 = dot(d, d);
    float u = len2 > 0.0 ? clamp(dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
    vec2 e = a + d * u - p;
    float d2 = dot(e, e);
    if (d2 > u_r2) discard;
    gl_FragDepth = d2 / (u_r2 + 1.0);
    float t = u;
    if (!u_ortho) {
        float za = -v_pa.z, zb = -v_pb.z;
        t = (u / zb) / ((1.0 - u) / za + u / zb);
    }
    vec3 pv = mix(v_pa, v_pb, t);
    float fd = (-pv.z - u_depth_near) / (u_depth_far - u_depth_near);
    float fv = 1.0;
    if (u_has_depth) {
        // The texel itself at equal sizes (the toolkit's resampling identity rule), else bilinear.
        float D = textureSize(s_depth, 0) == ivec2(u_size) ? texelFetch(s_depth, ivec2(p), 0).r
                                                           : texture(s_depth, p / u_size).r;
        if (u_test == 2) D = rgba8(D);
        fv = visibility(D, fd, u_test == 0 ? 0.0 : u_delta, u_beta);
    }
    float alpha = u_alpha * fv * (1.0 - smoothstep(u_fade_near, u_fade_far, fd));
    if (v_has_normal > 0.5) {
        vec3 n = mix(v_na, v_nb, t);
        float ln = length(n);
        n = ln > 0.0 ? n / ln : n;
        vec3 view = u_ortho ? vec3(0.0, 0.0, 1.0) : normalize(-pv);
        alpha *= smoothstep(u_nv_lo, u_nv_hi, abs(dot(n, view)));
        if (u_hatching) alpha *= 1.0 - smoothstep(u_nl_lo, u_nl_hi, dot(n, u_light_view));
    }
    o_color = vec4(alpha, 0.0, 0.0, 1.0);
}
