// stylize/ryb.cpp — Gossett & Chen 2004 RYB cube, its numerical inverse, and the
// brightness-preserving RYB mix of Chen et al. 2015 (see ryb.h).
#include "stylize/ryb.h"

#include <algorithm>
#include <cmath>
#include <vector>

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

namespace {

//! Damped Gauss-Newton on |f(p) - t|^2, projected onto the cube, from p; accepts only improving
//! steps, stops when the residual is below 1e-14 (squared), the step vanishes, or after 24 steps.
V3 refine(V3 p, const V3& t, int max_steps = 24) {
    double best_d = dist2(eval(p), t);
    double lambda = 1e-6;
    for (int it = 0; it < max_steps && best_d > 1e-14; ++it) {
        V3 a, b, c;
        const V3 f = eval(p, &a, &b, &c);
        const V3 e{t.x - f.x, t.y - f.y, t.z - f.z};
        // Normal equations (J^T J + lambda I) d = J^T e, J = [a b c] as columns; Cramer's rule.
        const double m[3][3] = {{dot(a, a) + lambda, dot(a, b), dot(a, c)},
                                {dot(b, a), dot(b, b) + lambda, dot(b, c)},
                                {dot(c, a), dot(c, b), dot(c, c) + lambda}};
        const double g[3] = {dot(a, e), dot(b, e), dot(c, e)};
        auto det3 = [](const double q[3][3]) {
            return q[0][0] * (q[1][1] * q[2][2] - q[1][2] * q[2][1]) - q[0][1] * (q[1][0] * q[2][2] - q[1][2] * q[2][0]) +
                   q[0][2] * (q[1][0] * q[2][1] - q[1][1] * q[2][0]);
        };
        const double det = det3(m);
        if (!(std::fabs(det) > 1e-300)) break;
        double step[3];
        for (int col = 0; col < 3; ++col) {
            double mm[3][3];
            for (int r = 0; r < 3; ++r)
                for (int q = 0; q < 3; ++q) mm[r][q] = (q == col) ? g[r] : m[r][q];
            step[col] = det3(mm) / det;
        }
        const V3 q{clamp01(p.x + step[0]), clamp01(p.y + step[1]), clamp01(p.z + step[2])};
        if (dist2(q, p) < 1e-16) break;  // converged (a minimum on the cube or outside the image)
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
    return p;
}

//! Full solve: best point of a 5^3 lattice of the cube, then refine.
V3 solve_from_lattice(const V3& t) {
    V3 best{0, 0, 0};
    double best_d = 1e300;
    for (int i = 0; i <= 4; ++i)
        for (int j = 0; j <= 4; ++j)
            for (int k = 0; k <= 4; ++k) {
                const V3 p{i * 0.25, j * 0.25, k * 0.25};
                const double d = dist2(eval(p), t);
                if (d < best_d) best_d = d, best = p;
            }
    return refine(best, t);
}

//! Seeds: the full solve at every node of a 17^3 RGB lattice, computed once (thread-safe static
//! initialisation, ~5k solves); a query refines the seed of its nearest node.
constexpr int kSeedN = 17;
const std::vector<V3>& seed_table() {
    static const std::vector<V3> table = [] {
        std::vector<V3> t(std::size_t(kSeedN) * kSeedN * kSeedN);
        for (int b = 0; b < kSeedN; ++b)
            for (int g = 0; g < kSeedN; ++g)
                for (int r = 0; r < kSeedN; ++r)
                    t[(std::size_t(b) * kSeedN + g) * kSeedN + r] =
                        solve_from_lattice({r / double(kSeedN - 1), g / double(kSeedN - 1), b / double(kSeedN - 1)});
        return t;
    }();
    return table;
}

int seed_index(double v) {
    const double s = clamp01(v) * (kSeedN - 1) + 0.5;
    return int(s);  // s in [0.5, kSeedN - 0.5]: a valid node index
}

}  // namespace

glm::vec3 rgb_to_ryb(glm::vec3 rgb) {
    const V3 t{std::isfinite(rgb.x) ? rgb.x : 0.0, std::isfinite(rgb.y) ? rgb.y : 0.0,
               std::isfinite(rgb.z) ? rgb.z : 0.0};
    const V3 seed = seed_table()[(std::size_t(seed_index(t.z)) * kSeedN + seed_index(t.y)) * kSeedN + seed_index(t.x)];
    const V3 p = refine(seed, t, 12);
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
