// edge_detect/rgbd_sobel — WC18 §3 (spec §4.2): 3x3 Sobel on the 4-vector (r, g, b, depth * wD);
// edge = min(1, sqrt(|H|^2 + |V|^2)) (MNPR sobelRGBD: length(vec2(length(H), length(V)))).
//@pass sobel out=1 in=color,depth

vec4 rgbd(ivec2 p) {
    return vec4(fetch_b(s_color, p, u_border).rgb, fetch_b(s_depth, p, u_border).r * u_depth_weight);
}

void main() {
    ivec2 p = pixel();
    vec4 tl = rgbd(p + ivec2(-1, -1)), tc = rgbd(p + ivec2(0, -1)), tr = rgbd(p + ivec2(1, -1));
    vec4 ml = rgbd(p + ivec2(-1, 0)),                                 mr = rgbd(p + ivec2(1, 0));
    vec4 bl = rgbd(p + ivec2(-1, 1)), bc = rgbd(p + ivec2(0, 1)),  br = rgbd(p + ivec2(1, 1));
    vec4 h = (tr + 2.0 * mr + br) - (tl + 2.0 * ml + bl);   // Sobel x
    vec4 v = (bl + 2.0 * bc + br) - (tl + 2.0 * tc + tr);   // Sobel y
    o_color = vec4(min(1.0, length(vec2(length(h), length(v)))));
}
