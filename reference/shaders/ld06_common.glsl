// ld06_common.glsl — LD06 eq. 1-4 shared by the raster-pass twins (pass.frag.glsl,
// particles.frag.glsl): Δstep with the binary limit, the blurred-test visibility, the RGBA8 depth
// coding. Inserted after the #version line by reference/pass_twin.cpp.
float ld06_step(float l, float u, float v) { return u > l ? smoothstep(l, u, v) : (v >= l ? 1.0 : 0.0); }
float visibility(float D, float fd, float delta, float beta) { return ld06_step(-delta, delta, (D - fd) + beta); }
float rgba8(float d) {
    d = clamp(d, 0.0, 1.0);
    float s = 0.0;
    for (int k = 0; k < 4; ++k) s += round(clamp(4.0 * d - float(k), 0.0, 1.0) * 255.0) / 255.0;
    return s / 4.0;
}
