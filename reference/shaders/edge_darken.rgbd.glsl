// edge_darken/rgbd — WC18 §3.1 (MNPR gradientEdgesWC): C_dark = C^(1 + E_d),
// E_d = edge * intensity * (1 + ci) * sat(5 |C - Cs|) * sat(1 - 3 bleed), ci = ctrl.edge.r,
// x5 where positive; bleed = the bleeding mask (bleed.a, resampled when at half resolution).
// Ours: E_d / (1 + crowding * crowd), crowd = the local mean of the edges (optional input).
//@pass dark out=4 in=color,edges,ctrl_edge,bleed:linear,crowd:linear

void main() {
    vec4 c = fetch(s_color, pixel());
    float edge = fetch(s_edges, pixel()).r;
    float ci = fetch(s_ctrl_edge, pixel()).r;
    if (ci > 0.0) ci *= 5.0;
#if HAS_bleed
    float bleed = same_or_resample(s_bleed).a;
#else
    float bleed = 0.0;
#endif
    float e = edge * u_intensity * (1.0 + ci);
#if HAS_crowd
    e /= 1.0 + u_crowding * same_or_resample(s_crowd).r;
#endif
    e *= sat(length(c.rgb - u_substrate_color) * 5.0);
    e *= sat(1.0 - bleed * 3.0);
    o_color = e > 0.0 ? vec4(cpow(c.rgb, 1.0 + e), c.a) : c;
}
