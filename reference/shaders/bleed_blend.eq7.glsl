// bleed_blend/eq7 — WC17 eq. 7: I_cb = Ctrl (B - I) + I with Ctrl = sat(gain * bleed.a)
// (gain 1: WC17; 5: MNPR blendFromAlpha). A half-resolution bleed target is upsampled by GL
// bilinear filtering (texture(), clamp to edge).
//@pass blend out=4 in=color,bleed:linear

void main() {
    vec4 i = fetch(s_color, pixel());
    vec4 b = same_or_resample(s_bleed);
    float k = sat(u_gain * b.a);
    o_color = vec4(k * (b.rgb - i.rgb) + i.rgb, i.a);
}
