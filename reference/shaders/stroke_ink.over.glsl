// stroke_ink/over — LD06 §4.4: the strokes' ink coverage (resampled bilinearly) painted last over
// the picture: mix(dst, ink colour, sat(alpha x coverage)); alpha of the picture kept, and the
// colour itself where the opacity is 0 (stylize/stages/stroke_ink.h ink_opacity).
//@pass ink out=4 size=color in=color,ink:linear
//@include ld06_wash.glsl

void main() {
    vec4 c = fetch(s_color, pixel());
    float cov = same_or_resample(s_ink).r;
    float k = sat(u_alpha * cov);
    o_color = k == 0.0 ? c : vec4(ld06_glaze(c.rgb, vec3(u_color_r, u_color_g, u_color_b), k, false), c.a);
}
