// reference/shaders/common.glsl — shared GLSL helpers for the stage twins. Prepended to every
// fragment shader by aq::ref::assemble_fragment, after #version and the pass defines.
//
// Border rules are resolved here, not by the sampler: texelFetch ignores wrap modes, and
// GL_MIRRORED_REPEAT repeats the edge texel while aq::Border::Mirror reflects about the edge
// texel's centre (-1 -> 1, n -> n-2), see core/image.h.

precision highp float;
precision highp int;

layout(location = 0) out vec4 o_color;
uniform ivec2 u_out_size;            // size of the target being written
uniform vec3 u_substrate_color;      // paper colour Cp (Globals::substrate_color)

int aq_clamp_i(int i, int n) { return clamp(i, 0, n - 1); }
int aq_mirror_i(int i, int n) {
    if (i >= 0 && i < n) return i;
    if (n == 1) return 0;
    int period = 2 * (n - 1);
    // GLSL leaves % undefined for negative operands (llvmpipe computes it unsigned): fold first.
    int m = i < 0 ? (period - (-i) % period) % period : i % period;
    return m < n ? m : period - m;
}
ivec2 aq_clamp(ivec2 p, ivec2 n) { return ivec2(aq_clamp_i(p.x, n.x), aq_clamp_i(p.y, n.y)); }
ivec2 aq_mirror(ivec2 p, ivec2 n) { return ivec2(aq_mirror_i(p.x, n.x), aq_mirror_i(p.y, n.y)); }

// Exact taps with the stage's border rule.
vec4 fetch_clamp(sampler2D s, ivec2 p) { return texelFetch(s, aq_clamp(p, textureSize(s, 0)), 0); }
vec4 fetch_mirror(sampler2D s, ivec2 p) { return texelFetch(s, aq_mirror(p, textureSize(s, 0)), 0); }
vec4 fetch(sampler2D s, ivec2 p) { return texelFetch(s, p, 0); }  // p known to be inside

ivec2 pixel() { return ivec2(gl_FragCoord.xy); }

float sat(float x) { return clamp(x, 0.0, 1.0); }
vec3 sat(vec3 x) { return clamp(x, 0.0, 1.0); }
// Rec. 709 luma (MNPR luminance()).
float luminance(vec3 c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

// Border chosen by a stage's `border` parameter: 0 = clamp, 1 = mirror.
vec4 fetch_b(sampler2D s, ivec2 p, int border) { return border == 1 ? fetch_mirror(s, p) : fetch_clamp(s, p); }

// Bilinear taps on a GL_LINEAR + clamp-to-edge sampler at `pos` in texel units (texel centres at
// +0.5): the texture unit's texture(), or, when AQ_EXACT_BILINEAR is 1 (environment variable
// AQ_REFERENCE_EXACT_BILINEAR=1, a diagnostic), four exact taps weighted in float arithmetic.
// GPUs quantise texture()'s weights (NVIDIA: 8 bits, 1/256 steps); llvmpipe does not
// (docs/reference.md, "On a real GPU").
#ifndef AQ_EXACT_BILINEAR
#define AQ_EXACT_BILINEAR 0
#endif
vec4 bilinear_clamp(sampler2D s, vec2 pos) {
#if AQ_EXACT_BILINEAR
    vec2 f = pos - 0.5;
    vec2 f0 = floor(f);
    vec2 t = f - f0;
    ivec2 p0 = ivec2(f0);
    vec4 a = fetch_clamp(s, p0), b = fetch_clamp(s, p0 + ivec2(1, 0));
    vec4 c = fetch_clamp(s, p0 + ivec2(0, 1)), d = fetch_clamp(s, p0 + ivec2(1, 1));
    return mix(mix(a, b, t.x), mix(c, d, t.x), t.y);
#else
    return texture(s, pos / vec2(textureSize(s, 0)));
#endif
}

// GL's own resampling between resolutions: a full-screen pass reading `s` (any size) with
// texture() at uv = gl_FragCoord.xy / output size, on a GL_LINEAR + clamp-to-edge sampler.
vec4 resample(sampler2D s) {
#if AQ_EXACT_BILINEAR
    return bilinear_clamp(s, gl_FragCoord.xy / vec2(u_out_size) * vec2(textureSize(s, 0)));
#else
    return texture(s, gl_FragCoord.xy / vec2(u_out_size));
#endif
}
// Same size: the exact texel; otherwise the bilinear resample above.
vec4 same_or_resample(sampler2D s) {
    return textureSize(s, 0) == u_out_size ? texelFetch(s, pixel(), 0) : resample(s);
}

// Unnormalised Gaussian weight exp(-o^2 / (2 sigma^2)).
float gauss(float o, float sigma) { return exp(-(o * o) / (2.0 * sigma * sigma)); }

// Colour transmittance C^d for colours (MNPR pow(abs(c), d)).
vec3 cpow(vec3 c, float d) { return pow(abs(c), vec3(d)); }
