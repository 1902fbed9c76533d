// pigment_apply/wc17 — WC17 §3.3 eq. 9, granulation: I_g = I (I - P_iv) + (1 - I) I^(1 + Ctrl d P_iv)
// with P_iv = 1 - Hr the inverted paper height, Hr = (H - 0.5) r + 0.5, Ctrl = max(ctrl.pigment.g, 0).
// `literal` subtracts P_iv as printed; otherwise the controlled amount Ctrl d P_iv plus the paper
// texture term t P_iv (t = paper_texture), so that Ctrl = 0 and t = 0 leave the colour unchanged.
// Result clamped to [0, 1]; alpha < 0.01 untouched (MNPR) unless t > 0 (not literal): the bare
// paper then gets the texture term only (its control is 0).
//@pass apply out=4 in=color,ctrl_pigment,paper

void main() {
    vec4 c = fetch(s_color, pixel());
    o_color = c;
    bool covered = c.a >= 0.01;
    if (!covered && (u_literal || !(u_paper_texture > 0.0))) return;
#if HAS_paper
    float height = fetch(s_paper, pixel()).b;
#else
    float height = 0.5;   // flat paper
#endif
    float hr = (height - 0.5) * u_roughness + 0.5;
    float piv = 1.0 - hr;
    float k = covered ? max(fetch(s_ctrl_pigment, pixel()).g, 0.0) * u_density * piv : 0.0;
    float tex = u_paper_texture * piv;
    if (!u_literal && k == 0.0 && tex == 0.0) return;
    float sub = u_literal ? piv : k + tex;
    vec3 i = c.rgb;
    o_color = vec4(sat(i * (i - sub) + (1.0 - i) * cpow(i, 1.0 + k)), c.a);
}
