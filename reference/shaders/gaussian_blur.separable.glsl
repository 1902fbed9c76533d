// gaussian_blur/separable — LD06 §2 / §3.3: separable Gaussian low-pass of a one-channel map
// (depth, shadow or intensity), H then V, weights normalised over -radius..radius. First the mean
// of each downsample x downsample block (rows, then pixels in a row; the blocks' part inside the map).
//@pass down out=1 size=div_downsample:image in=image
//@pass h out=1 in=down
//@pass v out=1 in=h
//@output blurred=v

#ifdef PASS_down
void main() {
    ivec2 size = textureSize(s_image, 0);
    ivec2 lo = pixel() * u_downsample, hi = min(lo + u_downsample, size);
    float sum = 0.0;
    for (int y = lo.y; y < hi.y; ++y)
        for (int x = lo.x; x < hi.x; ++x) sum += texelFetch(s_image, ivec2(x, y), 0).r;
    o_color = vec4(sum / float((hi.y - lo.y) * (hi.x - lo.x)));
}
#else
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
    float sum = 0.0;
    for (int o = -u_radius; o <= u_radius; ++o)
        sum += (gauss(float(o), u_sigma) / norm) * fetch_b(SRC, pixel() + o * kDir, u_border).r;
    o_color = vec4(sum);
}
#endif
