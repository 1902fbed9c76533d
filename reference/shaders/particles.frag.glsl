// particles.frag.glsl — fragment stage of the LD06 particle twin: the blurred depth test of the
// sprite's depth (eq. 2, optionally RGBA8-coded, eq. 3-4), the round blotch shape, and the
// particle's class channel; GL's additive blending (ONE, ONE) sums, the readback clamps (eq. 12).
#version 450 core
#include_ld06_common
flat in float v_depth;
flat in int v_class;
out vec4 o_color;

uniform int u_test;  // 0 binary, 1 blurred, 2 blurred_rgba8
uniform float u_delta, u_beta;
uniform int u_shape;  // 0 round blotch, 1 square
uniform vec2 u_size;
uniform sampler2D s_depth;

// ld06_step, visibility, rgba8: ld06_common.glsl

void main() {
    float D = texture(s_depth, gl_FragCoord.xy / u_size).r;
    if (u_test == 2) D = rgba8(D);
    float fv = visibility(D, v_depth, u_test == 0 ? 0.0 : u_delta, u_beta);
    float shape = 1.0;
    if (u_shape == 0) shape = 1.0 - smoothstep(0.4, 0.5, length(gl_PointCoord - vec2(0.5)));
    vec4 c = vec4(0.0);
    c[v_class] = fv * shape;
    o_color = c;
}
