// Shared body of the bleed twins (spec §4.4 "Bleeding"). BLEED_RULE: 0 naive (WC16 Gaussian),
// 1 joint bilateral (WC17 Algorithm 1), 2 MNPR (Algorithm 1 + control scope max(c_d, c_s) >= |a|/r).
// Passes: `src` builds (r, g, b, bleeding control) at the working resolution (bilinear
// downsampling when half_res), `z` the depth there, `h` and `v` the two 1-D passes of
// Algorithm 1: out = sum_a W[a] * (bleed(a) ? I(x + a) : I(x)), the control filtered the same way
// (the expanded mask; naive keeps the painted mask).

#ifdef PASS_src
void main() {
    vec4 c = u_half_res ? resample(s_color) : fetch(s_color, pixel());
    vec4 k = u_half_res ? resample(s_ctrl_abstraction) : fetch(s_ctrl_abstraction, pixel());
    o_color = vec4(c.rgb, k.b);   // ctrl.abstraction.b = bleeding
}
#endif

#ifdef PASS_z
void main() { o_color = u_half_res ? resample(s_depth) : fetch(s_depth, pixel()); }
#endif

#if defined(PASS_h) || defined(PASS_v)
#ifdef PASS_h
#define SRC s_src
const ivec2 kDir = ivec2(1, 0);
#else
#define SRC s_h
const ivec2 kDir = ivec2(0, 1);
#endif

#if BLEED_RULE == 2
float sigma() { return 2.0 * float(u_radius); }   // MNPR: sigma = 2r
#else
float sigma() { return u_sigma; }
#endif

void main() {
    ivec2 p = pixel();
    vec4 s = fetch(SRC, p);
    float norm = 0.0;
    for (int a = -u_radius; a <= u_radius; ++a) norm += gauss(float(a), sigma());
#if BLEED_RULE != 0
    float zs = fetch(s_z, p).r;
#endif
    vec4 sum = vec4(0.0);
    for (int a = -u_radius; a <= u_radius; ++a) {
        ivec2 q = p + a * kDir;
        vec4 d = fetch_b(SRC, q, u_border);
        float w = gauss(float(a), sigma()) / norm;
#if BLEED_RULE == 0
        bool bleed = true;
#else
        float zd = fetch_b(s_z, q, u_border).r;
        bool source_behind = (zs - u_depth_threshold) > zd;
        bool bleed = (d.a > 0.0 && source_behind) || (s.a > 0.0 && !source_behind);
#if BLEED_RULE == 2
        bleed = bleed && max(d.a, s.a) >= float(abs(a)) / float(u_radius);
#endif
#endif
        sum += w * (bleed ? d : s);
    }
#if BLEED_RULE == 0
    sum.a = s.a;   // naive: the mask is the painted control, not blurred
#endif
    o_color = sum;
}
#endif
