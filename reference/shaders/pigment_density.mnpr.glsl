// pigment_density/mnpr — image-space pigment turbulence (WC18, MNPR pigmentDensityWC; spec §4.3):
// d = 1 + strength * ctrl.pigment.b; c' = |c|^d; out = lerp(substrate, c', sat(d)); alpha kept.
//@pass density out=4 in=color,ctrl_pigment

void main() {
    vec4 c = fetch(s_color, pixel());
    float d = 1.0 + u_strength * fetch(s_ctrl_pigment, pixel()).b;
    vec3 cd = cpow(c.rgb, d);
    o_color = vec4(mix(u_substrate_color, cd, sat(d)), c.a);
}
