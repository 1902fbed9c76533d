// gaussian_blur/separable — LD06 §2 / §3.3: separable Gaussian low-pass of a one-channel map
// (depth, shadow or intensity), H then V, weights normalised over -radius..radius.
//@pass h out=1 in=image
//@pass v out=1 in=h
//@output blurred=v

#ifdef PASS_h
#define SRC s_image
const ivec2 kDir = ivec2(1, 0);
#else
#define SRC s_h
const ivec2 kDir = ivec2(0, 1);
#endif
void main() {
    float norm = 0.0;
    for (int o = -u_radius; o <= u_radius; ++o) norm += gauss(float(o), u_sigma);
    float sum = 0.0;
    for (int o = -u_radius; o <= u_radius; ++o)
        sum += (gauss(float(o), u_sigma) / norm) * fetch_b(SRC, pixel() + o * kDir, u_border).r;
    o_color = vec4(sum);
}
