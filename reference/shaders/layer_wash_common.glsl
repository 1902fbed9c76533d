// layer_wash_common.glsl — the passes of both layer_wash twins (layer_wash.multiplicative.glsl,
// layer_wash.additive.glsl), which define ADDITIVE and declare the passes.
//@include ld06_wash.glsl

#if defined(PASS_wash)
float layer_wash(sampler2D I, sampler2D R, float h) {
    return ld06_wash(resample(I).r, resample(R).r, h, u_kappa, u_width, u_edge, u_border, u_granulation, u_paper_before, ADDITIVE);
}
void main() {
    float h = fetch(s_paper, pixel()).b;
    vec4 o = vec4(0.0);
    o.x = layer_wash(s_layer0, s_v0, h);
#if HAS_layer1
    o.y = layer_wash(s_layer1, s_v1, h);
#endif
#if HAS_layer2
    o.z = layer_wash(s_layer2, s_v2, h);
#endif
#if HAS_layer3
    o.w = layer_wash(s_layer3, s_v3, h);
#endif
    o_color = o;
}
#elif defined(PASS_h0)
void main() {
#if HAS_layer0
    o_color = vec4(ld06_blur(s_layer0, pixel(), ivec2(1, 0), u_radius, u_sigma));
#else
    o_color = vec4(0.0);
#endif
}
#elif defined(PASS_v0)
void main() {
#if HAS_h0
    o_color = vec4(ld06_blur(s_h0, pixel(), ivec2(0, 1), u_radius, u_sigma));
#else
    o_color = vec4(0.0);
#endif
}
#elif defined(PASS_h1)
void main() {
#if HAS_layer1
    o_color = vec4(ld06_blur(s_layer1, pixel(), ivec2(1, 0), u_radius, u_sigma));
#else
    o_color = vec4(0.0);
#endif
}
#elif defined(PASS_v1)
void main() {
#if HAS_h1
    o_color = vec4(ld06_blur(s_h1, pixel(), ivec2(0, 1), u_radius, u_sigma));
#else
    o_color = vec4(0.0);
#endif
}
#elif defined(PASS_h2)
void main() {
#if HAS_layer2
    o_color = vec4(ld06_blur(s_layer2, pixel(), ivec2(1, 0), u_radius, u_sigma));
#else
    o_color = vec4(0.0);
#endif
}
#elif defined(PASS_v2)
void main() {
#if HAS_h2
    o_color = vec4(ld06_blur(s_h2, pixel(), ivec2(0, 1), u_radius, u_sigma));
#else
    o_color = vec4(0.0);
#endif
}
#elif defined(PASS_h3)
void main() {
#if HAS_layer3
    o_color = vec4(ld06_blur(s_layer3, pixel(), ivec2(1, 0), u_radius, u_sigma));
#else
    o_color = vec4(0.0);
#endif
}
#elif defined(PASS_v3)
void main() {
#if HAS_h3
    o_color = vec4(ld06_blur(s_h3, pixel(), ivec2(0, 1), u_radius, u_sigma));
#else
    o_color = vec4(0.0);
#endif
}
#endif
