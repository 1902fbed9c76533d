// shadow_layer_common.glsl — the body of both shadow_layer twins (shadow_layer.multiplicative.glsl,
// shadow_layer.over.glsl), which define MUL.
//@include ld06_wash.glsl

void main() {
#if defined(PASS_h)
    o_color = vec4(ld06_blur(s_shadow, pixel(), ivec2(1, 0), u_radius, u_sigma));
#elif defined(PASS_v)
    o_color = vec4(ld06_blur(s_h, pixel(), ivec2(0, 1), u_radius, u_sigma));
#else
    vec4 c = fetch(s_color, pixel());
    float h = fetch(s_paper, pixel()).b;
    float p = ld06_wash(resample(s_shadow).r, resample(s_v).r, h, u_kappa, u_width, u_edge, u_border, u_granulation, true, false);
    o_color = vec4(ld06_glaze(c.rgb, vec3(u_color_r, u_color_g, u_color_b), sat(u_alpha * p), MUL), c.a);
#endif
}
