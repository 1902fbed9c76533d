// shadow_layer/over — LD06 §3.3: the shadow intensity map as a wash (Gaussian blur H, V at its
// own size; resampled; smoothstep, edge, paper: ld06_wash.glsl, edge multiplicative, paper before)
// in the shadow colour at opacity sat(alpha x amount), glazed with alpha over onto the picture.
//@pass h out=1 in=shadow
//@pass v out=1 in=h
//@pass layer out=4 size=color in=color,shadow:linear,v:linear,paper
//@output color=layer
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
    o_color = vec4(ld06_glaze(c.rgb, vec3(u_color_r, u_color_g, u_color_b), sat(u_alpha * p), false), c.a);
#endif
}
