// edge_darken/dog — WC17 eq. 8: I_ed = I_cb^(1 + Ctrl * max_rgb(I_b - I_cb)), I_b the (half-
// resolution) Gaussian blur upsampled by GL bilinear filtering; the DoG edge E is modulated by a
// smoothstep (the paper names it; the edges smooth_low/smooth_high are ours): E * smoothstep(E).
// Ctrl = intensity * max(0, ctrl_bias + ctrl.edge.r).
//@pass dark out=4 in=color,blurred:linear,ctrl_edge

void main() {
    vec4 c = fetch(s_color, pixel());
    vec3 ib = same_or_resample(s_blurred).rgb;
    vec3 dog = ib - c.rgb;
    float e = max(0.0, max(dog.r, max(dog.g, dog.b)));
    float em = e * smoothstep(u_smooth_low, u_smooth_high, e);
    float k = max(0.0, u_ctrl_bias + fetch(s_ctrl_edge, pixel()).r) * u_intensity * em;
    o_color = k > 0.0 ? vec4(cpow(c.rgb, 1.0 + k), c.a) : c;
}
