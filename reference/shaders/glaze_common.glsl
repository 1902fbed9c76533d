// glaze_common.glsl — the body of both glaze twins (glaze.multiplicative.glsl, glaze.over.glsl),
// which define MUL.
//@include ld06_wash.glsl

void main() {
#if HAS_color
    vec3 c = fetch(s_color, pixel()).rgb;
#else
    vec3 c = u_substrate_color;
#endif
    vec4 w = fetch(s_wash, pixel());
    vec4 r0 = same_or_resample(s_ramp0), r1 = same_or_resample(s_ramp1);
    vec4 r2 = same_or_resample(s_ramp2), r3 = same_or_resample(s_ramp3);
    c = ld06_glaze(c, r0.rgb, sat(r0.a * w.x), MUL);
    c = ld06_glaze(c, r1.rgb, sat(r1.a * w.y), MUL);
    c = ld06_glaze(c, r2.rgb, sat(r2.a * w.z), MUL);
    c = ld06_glaze(c, r3.rgb, sat(r3.a * w.w), MUL);
    o_color = vec4(c, 1.0);
}
