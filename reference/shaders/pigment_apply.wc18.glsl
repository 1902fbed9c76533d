// pigment_apply/wc18 — WC18 §4.1 eq. 1-4 (MNPR pigmentApplicationWC): Hr = (H - 0.5) r + 0.5;
// dry-brush where Hr < -a (a = ctrl.pigment.g, negative = dry-brush): C + sat(t_dry |Hr + a|)(Cs - C);
// otherwise granulation: d_g = |a| + d_min, d_g = lerp(d_g, 5 d_g, L), H_iv = 1 - (0.2 Hr + 0.8),
// d_a = 1 + d_g H_iv D, C^d_a, faded out near the substrate: lerp(C, C^d_a, sat(5 |C - Cs|)).
// Pixels with alpha < 0.01 are unchanged.
//@pass apply out=4 in=color,ctrl_pigment,paper

void main() {
    vec4 c = fetch(s_color, pixel());
    o_color = c;
    if (!(c.a >= 0.01)) return;
#if HAS_paper
    float height = fetch(s_paper, pixel()).b;
#else
    float height = 0.5;
#endif
    float a = fetch(s_ctrl_pigment, pixel()).g;
    float hr = (height - 0.5) * u_roughness + 0.5;            // eq. 1
    float dry = hr + a;
    if (dry < 0.0) {                                           // eq. 2, dry-brush
        o_color = vec4(mix(c.rgb, u_substrate_color, sat(-dry * u_dry_brush_threshold)), c.a);
        return;
    }
    float dg = abs(a) + u_granulation_min;
    dg = mix(dg, dg * 5.0, luminance(c.rgb));                  // eq. 3
    float hiv = 1.0 - (hr * 0.2 + 0.8);
    float da = 1.0 + dg * hiv * u_density;                     // eq. 4
    vec3 g = cpow(c.rgb, da);                                  // eq. 2, granulation
    o_color = vec4(mix(c.rgb, g, sat(length(c.rgb - u_substrate_color) * 5.0)), c.a);
}
