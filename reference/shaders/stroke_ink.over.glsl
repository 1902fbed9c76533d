// stroke_ink/over — LD06 §4.4: the strokes' ink coverage (resampled bilinearly) painted last over
// the picture: mix(dst, ink colour, sat(alpha x coverage)); alpha of the picture kept.
//@pass ink out=4 size=color in=color,ink:linear
//@include ld06_wash.glsl

void main() {
    vec4 c = fetch(s_color, pixel());
    float cov = same_or_resample(s_ink).r;
    o_color = vec4(ld06_glaze(c.rgb, vec3(u_color_r, u_color_g, u_color_b), sat(u_alpha * cov), false), c.a);
}
