// edge_blur/wc17 — WC17 §3.3: "the equivalent of a 5x5 Gaussian kernel (sigma = 1)" of the colour
// image, at half resolution (bilinear downsample) as published; separable, H then V.
//@pass down out=4 size=half_if_half_res:color in=color:linear
//@pass h out=4 in=down
//@pass v out=4 in=h
//@output blurred=v

#ifdef PASS_down
void main() { o_color = u_half_res ? resample(s_color) : fetch(s_color, pixel()); }
#endif

#if defined(PASS_h) || defined(PASS_v)
#ifdef PASS_h
#define SRC s_down
const ivec2 kDir = ivec2(1, 0);
#else
#define SRC s_h
const ivec2 kDir = ivec2(0, 1);
#endif
void main() {
    float norm = 0.0;
    for (int o = -u_radius; o <= u_radius; ++o) norm += gauss(float(o), u_sigma);
    vec4 sum = vec4(0.0);
    for (int o = -u_radius; o <= u_radius; ++o)
        sum += (gauss(float(o), u_sigma) / norm) * fetch_b(SRC, pixel() + o * kDir, u_border);
    o_color = sum;
}
#endif
