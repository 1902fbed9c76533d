// ld06_wash.glsl — LD06 watercolor layer maths for the twins of layer_wash and shadow_layer
// (../shared/spec/ld06.md §4), written from the spec, not from stylize/.
// wash(I, rho, h): a = smoothstep(kappa - w, kappa + w, rho + border (h - 1/2)) (paper before) or
// the band a(1-a) perturbed afterwards; edge e = edge max(I - rho, 0); p = a (1 + e) or a + e;
// granulation p (1 - 2 granulation (h - 1/2)), >= 0.
float ld06_wash(float I, float rho, float h, float kappa, float width, float edge, float border, float gran,
                bool paper_before, bool additive) {
    float hp = h - 0.5;
    float r = paper_before ? rho + border * hp : rho;
    float a = smoothstep(kappa - width, kappa + width, r);
    if (!paper_before) a = clamp(a + 4.0 * border * hp * a * (1.0 - a), 0.0, 1.0);
    float e = edge * max(I - rho, 0.0);
    float p = additive ? a + e : a * (1.0 + e);
    return max(p * (1.0 - 2.0 * gran * hp), 0.0);
}
// One Gaussian tap sum (weights normalised over -radius..radius) along dir, clamp to edge.
float ld06_blur(sampler2D s, ivec2 p, ivec2 dir, int radius, float sigma) {
    float norm = 0.0;
    for (int o = -radius; o <= radius; ++o) norm += gauss(float(o), sigma);
    float sum = 0.0;
    for (int o = -radius; o <= radius; ++o) sum += (gauss(float(o), sigma) / norm) * fetch_clamp(s, p + o * dir).r;
    return sum;
}
// Glazing of colour c at opacity k over dst: multiplicative dst (1 - k (1 - c)), or over.
vec3 ld06_glaze(vec3 dst, vec3 c, float k, bool multiplicative) {
    return multiplicative ? dst * (1.0 - k * (1.0 - c)) : mix(dst, c, k);
}
