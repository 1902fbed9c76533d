// substrate_distort/mnpr — WC17 §3.3 / MNPR substrateDistortion (spec §4.9): sample the colour at
// the pixel centre + n * distortion * 5 k pixels, n = paper.rg * 2 - 1 (clamped to [-1, 1]),
// k = sat(ctrl.substrate.r + 0.2); keep the pixel's own colour when the destination lies in front
// (depth(x) - depth(dest) > threshold; both_sides: |difference|). Bilinear colour with clamp to
// edge (texture()) or aq's mirror rule (manual bilinear) for border = 1; the destination depth is
// sampled the same way (MNPR reads it through its linear sampler).
//@pass distort out=4 in=color:linear,depth:linear,ctrl_substrate,paper

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

void main() {
    ivec2 p = pixel();
    vec4 col = fetch(s_color, p);
#if HAS_paper
    vec2 tex = fetch(s_paper, p).rg;
#else
    vec2 tex = vec2(0.5);
#endif
    vec2 n = clamp(tex * 2.0 - 1.0, -1.0, 1.0);
    float k = sat(fetch(s_ctrl_substrate, p).r + 0.2);
    vec2 offset = n * (u_distortion * 5.0 * k);
    vec2 dest = vec2(p) + 0.5 + offset;
    float z = fetch(s_depth, p).r;
    float zd = bilinear_b(s_depth, dest).r;
    float dz = z - zd;
    bool refused = u_both_sides ? abs(dz) > u_depth_threshold : dz > u_depth_threshold;
    o_color = refused ? col : bilinear_b(s_color, dest);
}
