// RYB paint-like colour space for overlaps (spec §4.7): Gossett & Chen 2004 trilinear RYB cube
// (corner colours from their Fig. 2), a numerical RGB -> RYB inverse (the trilinear map has no
// closed form): best point of a 5^3 lattice, then damped Gauss-Newton (Levenberg-Marquardt)
// projected onto the unit cube; and the brightness-preserving mix of Chen et al. 2015,
// b(c) = sqrt(c^T diag(0.241, 0.691, 0.068) c). The inverse runs in double precision (GLSL 4.00
// fp64): in single precision the least-squares solve stalls ~1e-3 away from the optimum near the
// cube's faces, and the overlap colours would then differ from the C++ stage by up to ~0.008.
// For colours outside the cube's image the least-squares problem has several local minima on the
// cube's faces; which one a solver reaches depends on its start (stylize/ryb.cpp seeds from a
// 17^3 RGB table, this twin from the best point of a 5^3 RYB lattice), so out-of-gamut mixes may
// differ by ~1e-2 (docs/reference.md).

const vec3 kRyb[8] = vec3[8](vec3(1.0, 1.0, 1.0),      // white
                             vec3(1.0, 0.0, 0.0),      // red
                             vec3(1.0, 1.0, 0.0),      // yellow
                             vec3(1.0, 0.5, 0.0),      // orange
                             vec3(0.163, 0.373, 0.6),  // blue
                             vec3(0.5, 0.0, 0.5),      // purple
                             vec3(0.0, 0.66, 0.2),     // green
                             vec3(0.2, 0.094, 0.0));   // black
const vec3 kBrightness = vec3(0.241, 0.691, 0.068);

dvec3 ryb2rgb_d(dvec3 p, out dmat3 J) {
    dvec3 o = dvec3(0.0);
    J = dmat3(0.0);
    for (int i = 0; i < 8; ++i) {
        dvec3 s = dvec3(double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1));
        dvec3 w = mix(1.0 - p, p, s);           // per-axis weight
        dvec3 sg = s * 2.0 - 1.0;               // its derivative sign
        dvec3 c = dvec3(kRyb[i]);
        o += w.x * w.y * w.z * c;
        J[0] += sg.x * w.y * w.z * c;
        J[1] += w.x * sg.y * w.z * c;
        J[2] += w.x * w.y * sg.z * c;
    }
    return o;
}
dvec3 ryb2rgb_d(dvec3 p) { dmat3 j; return ryb2rgb_d(p, j); }
vec3 ryb2rgb(vec3 p) { return vec3(ryb2rgb_d(dvec3(clamp(p, 0.0, 1.0)))); }

double dist2(dvec3 a, dvec3 b) { dvec3 d = a - b; return dot(d, d); }

vec3 rgb2ryb(vec3 rgb) {
    dvec3 t = dvec3(rgb);
    dvec3 best = dvec3(0.0);
    double best_d = 1e300lf;  // lf: an unsuffixed literal is a float, and 1e300 overflows it (NVIDIA: error C0153)
    for (int i = 0; i <= 4; ++i)
        for (int j = 0; j <= 4; ++j)
            for (int k = 0; k <= 4; ++k) {
                dvec3 p = dvec3(i, j, k) * 0.25;
                double d = dist2(ryb2rgb_d(p), t);
                if (d < best_d) { best_d = d; best = p; }
            }
    dvec3 p = best;
    double lambda = 1e-6;
    for (int it = 0; it < 24 && best_d > 1e-14; ++it) {
        dmat3 J;
        dvec3 e = t - ryb2rgb_d(p, J);
        dmat3 A = transpose(J) * J + dmat3(lambda);
        dvec3 step = inverse(A) * (transpose(J) * e);
        dvec3 q = clamp(p + step, 0.0, 1.0);
        double dq = dist2(ryb2rgb_d(q), t);
        if (dq < best_d) { best_d = dq; p = q; lambda = max(lambda * 0.1, 1e-9); }
        else { lambda *= 100.0; if (lambda > 1e6) break; }
    }
    return vec3(p);
}

float brightness(vec3 c) { return sqrt(dot(kBrightness * c, c)); }

vec3 mix_ryb(vec3 a, vec3 b, float t, float brightness_scale) {
    vec3 rgb = ryb2rgb(mix(rgb2ryb(a), rgb2ryb(b), t));
    float target = mix(brightness(a), brightness(b), t) * brightness_scale;
    float have = brightness(rgb);
    if (have > 1e-6) rgb *= target / have;
    return clamp(rgb, 0.0, 1.0);
}
