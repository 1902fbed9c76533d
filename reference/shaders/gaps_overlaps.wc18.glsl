// gaps_overlaps/wc18 — WC18 §3.2 Algorithm 1 with MNPR's thresholds (spec §4.7): on painted pixels
// (alpha > 0.1) outside bleeding (mask < 0.01) inside the extended edges (E_e > 0.1), march up to
// p = ctrl.edge.b * m pixels along the normalised gradient G of E_e. Overlaps (p > 0.1): the first
// colour differing by more than 0.33 (RGBA) is mixed in RYB unless it is the substrate; a march that
// reaches m mixes with the colour at x - G (Algorithm 1 "direct edge"). Gaps (p < -0.1): a pixel on
// the edge (E_e > 2/m) or whose march meets E_e > 1/m becomes the substrate colour (or alpha 0).
// Colours along the march are bilinear: texture() with clamp to edge, or a manual bilinear with
// aq's mirror rule when border = 1 (GL_MIRRORED_REPEAT repeats the edge texel; aq's mirror does not).
//@pass go out=4 in=color:linear,edges:linear,ctrl_edge,bleed:linear
//@include ryb.glsl

const float kCtrlThreshold = 0.1;  // MNPR: |p| must exceed this

vec4 bilinear_b(sampler2D s, vec2 pos) {
    if (u_border == 0) return bilinear_clamp(s, pos);  // texture(), or exact taps (common.glsl)
    vec2 f = pos - 0.5;
    vec2 f0 = floor(f);
    vec2 t = f - f0;
    ivec2 p0 = ivec2(f0);
    vec4 a = fetch_mirror(s, p0), b = fetch_mirror(s, p0 + ivec2(1, 0));
    vec4 c = fetch_mirror(s, p0 + ivec2(0, 1)), d = fetch_mirror(s, p0 + ivec2(1, 1));
    return mix(mix(a, b, t.x), mix(c, d, t.x), t.y);
}

float e_at(ivec2 p) { return fetch_b(s_edges, p, u_border).r; }

bool gradient(ivec2 p, out vec2 g) {
    float r = e_at(p + ivec2(1, 0)), l = e_at(p + ivec2(-1, 0));
    float d = e_at(p + ivec2(0, 1)), u = e_at(p + ivec2(0, -1));
    float tr = e_at(p + ivec2(1, -1)), tl = e_at(p + ivec2(-1, -1));
    float dr = e_at(p + ivec2(1, 1)), dl = e_at(p + ivec2(-1, 1));
    vec2 grad = vec2((r + 0.5 * (tr + dr)) - (l + 0.5 * (tl + dl)),
                     (d + 0.5 * (dr + dl)) - (u + 0.5 * (tr + tl)));
    float len = length(grad);
    if (!(len > 1e-12) || isinf(len)) return false;   // flat edge field: no direction to march
    g = grad / len;
    return true;
}

void main() {
    ivec2 p = pixel();
    vec4 col = fetch(s_color, p);
    o_color = col;
#if HAS_bleed
    float bleed = same_or_resample(s_bleed).a;
#else
    float bleed = 0.0;
#endif
    float ee = fetch(s_edges, p).r;
    if (!(col.a > u_alpha_threshold) || !(bleed < u_bleed_threshold) || !(ee > u_edge_threshold)) return;
    float m = float(u_steps);
    float go = fetch(s_ctrl_edge, p).b * m;
    vec2 centre = vec2(p) + 0.5;
    vec2 g;
    if (go > kCtrlThreshold) {                       // overlaps
        if (!gradient(p, g)) return;
        for (int i = 1; i <= u_steps; ++i) {
            if (go < float(i)) return;               // "if (p < i) break": nothing to overlap
            vec4 cn = bilinear_b(s_color, centre + float(i) * g);
            if (length(cn - col) > u_color_difference) {
                if (length(cn.rgb - u_substrate_color) < u_substrate_proximity) return;
                o_color = vec4(mix_ryb(col.rgb, cn.rgb, 0.5, u_mix_brightness), col.a);
                return;
            }
        }
        vec4 cn = bilinear_b(s_color, centre - g);  // loop reached m: direct edge, negate G
        o_color = vec4(mix_ryb(col.rgb, cn.rgb, 0.5, u_mix_brightness), col.a);
    } else if (go < -kCtrlThreshold) {              // gaps
        bool gap = ee > 2.0 / m;
        if (!gap) {
            if (!gradient(p, g)) return;
            for (int i = 1; i <= u_steps && float(i) <= -go; ++i)
                if (bilinear_b(s_edges, centre + float(i) * g).r > 1.0 / m) { gap = true; break; }
        }
        if (gap) o_color = u_transparent_gaps ? vec4(col.rgb, 0.0) : vec4(u_substrate_color, col.a);
    }
}
