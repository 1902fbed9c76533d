// glaze/over — LD06 §4.2 glazing (spec §4.7): starting from the picture (or the paper colour
// when there is none), layers 0..3 back to front, each its ramp colour at opacity
// sat(ramp alpha x wash amount); over: mix(dst, c, k). Ramps resampled bilinearly.
//@pass glaze out=4 size=wash in=color,wash,ramp0:linear,ramp1:linear,ramp2:linear,ramp3:linear
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
    c = ld06_glaze(c, r0.rgb, sat(r0.a * w.x), false);
    c = ld06_glaze(c, r1.rgb, sat(r1.a * w.y), false);
    c = ld06_glaze(c, r2.rgb, sat(r2.a * w.z), false);
    c = ld06_glaze(c, r3.rgb, sat(r3.a * w.w), false);
    o_color = vec4(c, 1.0);
}
