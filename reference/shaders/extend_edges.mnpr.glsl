// extend_edges/mnpr — WC18 §3.2 extended edges for gaps & overlaps (MNPR edgeBlur "gaps and
// overlaps gradient"): linear kernel taps |l| < W with weights 1 - |l|/W, normalised, H then V;
// then b = b^(1/b) (drops weak gradients) and b = b^(2/W) (MNPR gamma by kernel size); b <= 0 -> 0.
//@pass h out=1 in=edges
//@pass v out=1 in=h
//@output extended=v

#ifdef PASS_h
#define SRC s_edges
const ivec2 kDir = ivec2(1, 0);
#else
#define SRC s_h
const ivec2 kDir = ivec2(0, 1);
#endif

void main() {
    float w = float(u_width);
    float sum = 0.0, norm = 0.0;
    for (int l = -u_width + 1; l < u_width; ++l) {
        float k = 1.0 - float(abs(l)) / w;
        sum += k * fetch_b(SRC, pixel() + l * kDir, u_border).r;
        norm += k;
    }
    float b = sum / norm;
#ifdef PASS_v
    if (!(b > 0.0)) b = 0.0;
    else {
        b = pow(b, 1.0 / b);
        b = pow(b, 2.0 / w);
    }
#endif
    o_color = vec4(b);
}
