// stylize/ryb.cpp — Gossett & Chen 2004 RYB cube, its numerical inverse, and the
// brightness-preserving RYB mix of Chen et al. 2015 (see ryb.h).
#include "stylize/ryb.h"

#include <algorithm>
#include <cmath>

namespace aq::stylize {

namespace {

struct V3 {
    double x, y, z;
};

double clamp01(double v) { return v > 0.0 ? (v < 1.0 ? v : 1.0) : 0.0; }  // NaN -> 0

V3 corner(int i) { return {kRybCorners[i].x, kRybCorners[i].y, kRybCorners[i].z}; }

//! Trilinear map and, optionally, its Jacobian columns (d/dr, d/dy, d/db).
V3 eval(const V3& p, V3* jr = nullptr, V3* jy = nullptr, V3* jb = nullptr) {
    const double r = p.x, y = p.y, b = p.z;
    V3 out{0, 0, 0}, dr{0, 0, 0}, dy{0, 0, 0}, db{0, 0, 0};
    for (int i = 0; i < 8; ++i) {
        const int ir = i & 1, iy = (i >> 1) & 1, ib = (i >> 2) & 1;
        const double wr = ir ? r : 1.0 - r, wy = iy ? y : 1.0 - y, wb = ib ? b : 1.0 - b;
        const double sr = ir ? 1.0 : -1.0, sy = iy ? 1.0 : -1.0, sb = ib ? 1.0 : -1.0;
        const V3 c = corner(i);
        const double w = wr * wy * wb, gr = sr * wy * wb, gy = wr * sy * wb, gb = wr * wy * sb;
        out = {out.x + w * c.x, out.y + w * c.y, out.z + w * c.z};
        dr = {dr.x + gr * c.x, dr.y + gr * c.y, dr.z + gr * c.z};
        dy = {dy.x + gy * c.x, dy.y + gy * c.y, dy.z + gy * c.z};
        db = {db.x + gb * c.x, db.y + gb * c.y, db.z + gb * c.z};
    }
    if (jr) *jr = dr;
    if (jy) *jy = dy;
    if (jb) *jb = db;
    return out;
}

double dist2(const V3& a, const V3& b) {
    const double dx = a.x - b.x, dy = a.y - b.y, dz = a.z - b.z;
    return dx * dx + dy * dy + dz * dz;
}

double dot(const V3& a, const V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

}  // namespace

glm::vec3 ryb_to_rgb(glm::vec3 ryb) {
    const V3 o = eval({clamp01(ryb.x), clamp01(ryb.y), clamp01(ryb.z)});
    return {float(o.x), float(o.y), float(o.z)};
}

glm::vec3 rgb_to_ryb(glm::vec3 rgb) {
    const V3 t{std::isfinite(rgb.x) ? rgb.x : 0.0, std::isfinite(rgb.y) ? rgb.y : 0.0,
               std::isfinite(rgb.z) ? rgb.z : 0.0};
    // Start from the closest point of a 5^3 lattice of the cube (deterministic, robust start).
    V3 best{0, 0, 0};
    double best_d = 1e300;
    for (int i = 0; i <= 4; ++i)
        for (int j = 0; j <= 4; ++j)
            for (int k = 0; k <= 4; ++k) {
                const V3 p{i * 0.25, j * 0.25, k * 0.25};
                const double d = dist2(eval(p), t);
                if (d < best_d) best_d = d, best = p;
            }
    // Damped Gauss-Newton, projected onto the cube; accepts only improving steps.
    V3 p = best;
    double lambda = 1e-6;
    for (int it = 0; it < 24 && best_d > 1e-14; ++it) {
        V3 a, b, c;
        const V3 f = eval(p, &a, &b, &c);
        const V3 e{t.x - f.x, t.y - f.y, t.z - f.z};
        // Normal equations (J^T J + lambda I) d = J^T e, J = [a b c] as columns.
        double m[3][3] = {{dot(a, a) + lambda, dot(a, b), dot(a, c)},
                          {dot(b, a), dot(b, b) + lambda, dot(b, c)},
                          {dot(c, a), dot(c, b), dot(c, c) + lambda}};
        double g[3] = {dot(a, e), dot(b, e), dot(c, e)};
        // Cramer's rule (3x3, well conditioned thanks to lambda).
        const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        if (!(std::fabs(det) > 1e-300)) break;
        auto solve_col = [&](int col) {
            double mm[3][3];
            for (int r = 0; r < 3; ++r)
                for (int q = 0; q < 3; ++q) mm[r][q] = (q == col) ? g[r] : m[r][q];
            return (mm[0][0] * (mm[1][1] * mm[2][2] - mm[1][2] * mm[2][1]) -
                    mm[0][1] * (mm[1][0] * mm[2][2] - mm[1][2] * mm[2][0]) +
                    mm[0][2] * (mm[1][0] * mm[2][1] - mm[1][1] * mm[2][0])) /
                   det;
        };
        const V3 q{clamp01(p.x + solve_col(0)), clamp01(p.y + solve_col(1)), clamp01(p.z + solve_col(2))};
        const double dq = dist2(eval(q), t);
        if (dq < best_d) {
            best_d = dq;
            p = q;
            lambda = std::max(lambda * 0.1, 1e-9);
        } else {
            lambda *= 100.0;  // step too long (or blocked by the cube): damp harder
            if (lambda > 1e6) break;
        }
    }
    return {float(p.x), float(p.y), float(p.z)};
}

float ryb_brightness(glm::vec3 c) {
    return std::sqrt(kBrightnessWeights.x * c.x * c.x + kBrightnessWeights.y * c.y * c.y +
                     kBrightnessWeights.z * c.z * c.z);
}

glm::vec3 mix_ryb(glm::vec3 a, glm::vec3 b, float t, float brightness_scale) {
    const glm::vec3 ra = rgb_to_ryb(a), rb = rgb_to_ryb(b);
    const glm::vec3 ryb = ra * (1.0f - t) + rb * t;
    glm::vec3 rgb = ryb_to_rgb(ryb);
    // Chen et al. 2015: restore the (mixed) brightness of the inputs. Scaling RGB by s scales
    // b() by exactly s, so the target is met unless clamping at 1 intervenes.
    const float target = (ryb_brightness(a) * (1.0f - t) + ryb_brightness(b) * t) * brightness_scale;
    const float have = ryb_brightness(rgb);
    if (have > 1e-6f && std::isfinite(target)) rgb *= target / have;
    auto c01 = [](float v) { return v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; };
    return {c01(rgb.x), c01(rgb.y), c01(rgb.z)};
}

}  // namespace aq::stylize
