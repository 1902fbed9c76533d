// adjust/mnpr — spec §4.1 "Adjust / load" (MNPR quadAdjustLoad adjustLoadFrag): linear depth
// normalised between depth_near and depth_far (MNPR 8..50, unclamped; no geometry -> 1),
// saturation / contrast / brightness, atmosphere tint with depth, substrate colour where alpha = 0.
//@pass col out=4 in=color,depth
//@pass dep out=1 in=depth
//@output color=col
//@output depth=dep

bool no_geometry(float z) { return isinf(z) || isnan(z); }

#ifdef PASS_col
void main() {
    vec4 c = fetch(s_color, pixel());
    float z = fetch(s_depth, pixel()).r;
    float luma = luminance(c.rgb);
    vec3 rgb = mix(vec3(luma), c.rgb, u_saturation);           // MNPR lerp(luma, c, saturation)
    rgb = mix(vec3(0.5), rgb, u_contrast * 0.5 + 0.5);          // MNPR lerp(0.5, c, contrast*0.5+0.5)
    rgb = sat(rgb + (u_brightness - 1.0));                      // MNPR saturate(c + brightness - 1)
    if (u_atmosphere) {
        float zz = no_geometry(z) ? 1.0e9 : z;                  // MNPR: background is far away
        float t = sat((zz - u_atmosphere_start) / (u_atmosphere_end - u_atmosphere_start));
        rgb = mix(rgb, vec3(u_tint_r, u_tint_g, u_tint_b), t);
    }
    rgb = mix(u_substrate_color, rgb, c.a);                     // background shows the paper
    o_color = vec4(rgb, c.a);
}
#endif

#ifdef PASS_dep
void main() {
    float z = fetch(s_depth, pixel()).r;
    o_color = vec4(no_geometry(z) ? 1.0 : (z - u_depth_near) / (u_depth_far - u_depth_near));
}
#endif
