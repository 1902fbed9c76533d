// texture_filter.glsl — raster/material.h sample_texture's filtering on the CPU's own mip levels
// (uploaded by Texture::upload(level0, mips)): the footprint of aniso_footprint, i.e. N probes
// along the major axis, N = min(ceil(P_max / P_min), 16), each textureLod at
// lambda = log2(P_max / N), averaged; log2(P_max) <= 0 is magnification (textureLod at 0), one
// probe GL's isotropic filtering (GL applies the sampler's c there itself). Not mirrored: the
// CPU's c = 0.5 of NEAREST_MIPMAP_* samplers with several probes and 0 < log2(P_max) <= 0.5
// (GLSL cannot read a sampler's filters); the CPU magnifies, this probes. The derivatives are
// GL's differences (dFdx/dFdy over the 2x2 quad); the CPU's are analytic (docs/reference.md).
const int kMaxAnisotropy = 16;  // raster/material.h kMaxAnisotropy
vec4 aq_texture(sampler2D s, vec2 uv) {
    vec2 size = vec2(textureSize(s, 0));
    vec2 dx = dFdx(uv), dy = dFdy(uv);
    float px = length(dx * size), py = length(dy * size);
    bool x_major = !(py > px);
    float pmax = x_major ? px : py, pmin = x_major ? py : px;
    vec2 major = x_major ? dx : dy;
    float ratio = pmax / max(pmin, pmax * (1.0 / float(kMaxAnisotropy)));
    int n = ratio > 1.0 ? min(kMaxAnisotropy, int(ceil(ratio))) : 1;
    float iso_lod = log2(pmax);
    if (!(iso_lod > 0.0)) return textureLod(s, uv, 0.0);  // magnified (-inf, NaN too): magFilter
    if (n == 1) return textureLod(s, uv, iso_lod);
    float lod = log2(pmax / float(n));
    lod = lod > 0.0 ? lod : 0.0;
    vec4 sum = vec4(0.0);
    for (int i = 0; i < n; ++i) sum += textureLod(s, uv + major * ((float(i) + 0.5) / float(n) - 0.5), lod);
    return sum / float(n);
}
