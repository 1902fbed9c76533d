// edge_blur/wc18 — WC18 §3.1 / MNPR edgeBlur: Gaussian blur of the Sobel edges with a per-pixel
// kernel size from the painted edge width ctrl.edge.g: K = max(1, int(W + lerp(0, 3W, ctrl))),
// sigma = K / 2, taps |o| < K, weights normalised; K taken at the output pixel in both passes.
//@pass h out=1 in=edges,ctrl_edge
//@pass v out=1 in=h,ctrl_edge
//@output blurred=v

#ifdef PASS_h
#define SRC s_edges
const ivec2 kDir = ivec2(1, 0);
#else
#define SRC s_h
const ivec2 kDir = ivec2(0, 1);
#endif

int kernel_size(float ctrl) {
    float w = float(u_width);
    float k = w + mix(0.0, 3.0 * w, ctrl);
    if (isnan(k)) return 1;                   // unpainted garbage: the narrowest kernel
    return clamp(int(k), 1, 4 * u_width);     // int() truncates towards zero, as MNPR's cast
}

void main() {
    int k = kernel_size(fetch(s_ctrl_edge, pixel()).g);
    float sigma = float(k) / 2.0;
    float sum = 0.0, norm = 0.0;
    for (int o = -k + 1; o < k; ++o) {
        float w = gauss(float(o), sigma);
        sum += w * fetch_b(SRC, pixel() + o * kDir, u_border).r;
        norm += w;
    }
    o_color = vec4(sum / norm);
}
