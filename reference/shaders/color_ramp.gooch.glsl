// color_ramp/gooch — LD06 §3.2 with Gooch et al. 1998: for layer K at lighting t,
// obj = tone (dark + (color - dark) t), w = 1 - keep_hue s (s: HSV saturation of obj),
// k_cool = w cool + cool_mix obj, k_warm = w warm + warm_mix obj,
// colour = sat(k_cool (1 - t) + k_warm t); alpha = the layer's alpha.
//@pass r0 out=4 in=lighting
//@pass r1 out=4 in=lighting
//@pass r2 out=4 in=lighting
//@pass r3 out=4 in=lighting
//@output ramp0=r0
//@output ramp1=r1
//@output ramp2=r2
//@output ramp3=r3

vec4 ramp(float t, vec3 color, vec3 dark, float alpha, float tone) {
    float u = sat(t);
    vec3 obj = tone * mix(dark, color, u);
    float mx = max(obj.r, max(obj.g, obj.b)), mn = min(obj.r, min(obj.g, obj.b));
    float w = 1.0 - u_keep_hue * (mx > 0.0 ? (mx - mn) / mx : 0.0);
    vec3 kc = w * vec3(u_cool_r, u_cool_g, u_cool_b) + u_cool_mix * obj;
    vec3 kw = w * vec3(u_warm_r, u_warm_g, u_warm_b) + u_warm_mix * obj;
    return vec4(sat(mix(kc, kw, u)), alpha);
}
void main() {
    float t = fetch(s_lighting, pixel()).r;
#if defined(PASS_r0)
    o_color = ramp(t, vec3(u_color0_r, u_color0_g, u_color0_b), vec3(u_dark0_r, u_dark0_g, u_dark0_b), u_alpha0, u_tone0);
#elif defined(PASS_r1)
    o_color = ramp(t, vec3(u_color1_r, u_color1_g, u_color1_b), vec3(u_dark1_r, u_dark1_g, u_dark1_b), u_alpha1, u_tone1);
#elif defined(PASS_r2)
    o_color = ramp(t, vec3(u_color2_r, u_color2_g, u_color2_b), vec3(u_dark2_r, u_dark2_g, u_dark2_b), u_alpha2, u_tone2);
#elif defined(PASS_r3)
    o_color = ramp(t, vec3(u_color3_r, u_color3_g, u_color3_b), vec3(u_dark3_r, u_dark3_g, u_dark3_b), u_alpha3, u_tone3);
#endif
}
