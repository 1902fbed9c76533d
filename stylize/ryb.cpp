// stylize/ryb.cpp — Gossett & Chen 2004 RYB cube, its numerical inverse, and the
// brightness-preserving RYB mix of Chen et al. 2015 (see ryb.h).
#include "stylize/ryb.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace aq::stylize {

namespace {

//! A point of the cube or of RGB in one number type: double (one conversion) or d4 (four lanes).
template <class D>
struct V3T {
    D x, y, z;
};
using V3 = V3T<double>;

double clamp01(double v) { return v > 0.0 ? (v < 1.0 ? v : 1.0) : 0.0; }  // NaN -> 0

//! Trilinear map and, optionally, its Jacobian columns (d/dr, d/dy, d/db); the same operations
//! for a double and for each lane of a d4.
template <class D>
V3T<D> eval(const V3T<D>& p, V3T<D>* jr = nullptr, V3T<D>* jy = nullptr, V3T<D>* jb = nullptr) {
    const D r = p.x, y = p.y, b = p.z;
    const D zero{};
    V3T<D> out{zero, zero, zero}, dr{zero, zero, zero}, dy{zero, zero, zero}, db{zero, zero, zero};
    for (int i = 0; i < 8; ++i) {
        const int ir = i & 1, iy = (i >> 1) & 1, ib = (i >> 2) & 1;
        const D wr = ir ? r : 1.0 - r, wy = iy ? y : 1.0 - y, wb = ib ? b : 1.0 - b;
        const double sr = ir ? 1.0 : -1.0, sy = iy ? 1.0 : -1.0, sb = ib ? 1.0 : -1.0;
        const double cx = kRybCorners[i].x, cy = kRybCorners[i].y, cz = kRybCorners[i].z;
        const D w = wr * wy * wb, gr = sr * wy * wb, gy = wr * sy * wb, gb = wr * wy * sb;
        out = {out.x + w * cx, out.y + w * cy, out.z + w * cz};
        dr = {dr.x + gr * cx, dr.y + gr * cy, dr.z + gr * cz};
        dy = {dy.x + gy * cx, dy.y + gy * cy, dy.z + gy * cz};
        db = {db.x + gb * cx, db.y + gb * cy, db.z + gb * cz};
    }
    if (jr) *jr = dr;
    if (jy) *jy = dy;
    if (jb) *jb = db;
    return out;
}

template <class D>
D dist2(const V3T<D>& a, const V3T<D>& b) {
    const D dx = a.x - b.x, dy = a.y - b.y, dz = a.z - b.z;
    return dx * dx + dy * dy + dz * dz;
}

template <class D>
D dot(const V3T<D>& a, const V3T<D>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

template <class D>
D det3(const D (&q)[3][3]) {
    return q[0][0] * (q[1][1] * q[2][2] - q[1][2] * q[2][1]) - q[0][1] * (q[1][0] * q[2][2] - q[1][2] * q[2][0]) +
           q[0][2] * (q[1][0] * q[2][1] - q[1][1] * q[2][0]);
}

//! One Gauss-Newton step's proposal from p (the normal equations (J^T J + lambda I) d = J^T e,
//! J = [a b c] as columns, by Cramer's rule), before the projection: step and the determinant.
template <class D>
void gauss_newton_step(const V3T<D>& p, const V3T<D>& t, D lambda, D (&step)[3], D& det) {
    V3T<D> a, b, c;
    const V3T<D> f = eval(p, &a, &b, &c);
    const V3T<D> e{t.x - f.x, t.y - f.y, t.z - f.z};
    const D m[3][3] = {{dot(a, a) + lambda, dot(a, b), dot(a, c)},
                       {dot(b, a), dot(b, b) + lambda, dot(b, c)},
                       {dot(c, a), dot(c, b), dot(c, c) + lambda}};
    const D g[3] = {dot(a, e), dot(b, e), dot(c, e)};
    det = det3(m);
    for (int col = 0; col < 3; ++col) {
        D mm[3][3];
        for (int r = 0; r < 3; ++r)
            for (int q = 0; q < 3; ++q) mm[r][q] = (q == col) ? g[r] : m[r][q];
        step[col] = det3(mm) / det;
    }
}

}  // namespace

glm::vec3 ryb_to_rgb(glm::vec3 ryb) {
    const V3 o = eval(V3{clamp01(ryb.x), clamp01(ryb.y), clamp01(ryb.z)});
    return {float(o.x), float(o.y), float(o.z)};
}

namespace {

//! Damped Gauss-Newton on |f(p) - t|^2, projected onto the cube, from p; accepts only improving
//! steps, stops when the residual is below 1e-14 (squared), the step vanishes, or after
//! max_steps steps. The reference schedule of the inverse (Refine4 runs it in four lanes).
V3 refine(V3 p, const V3& t, int max_steps = 24) {
    double best_d = dist2(eval(p), t);
    double lambda = 1e-6;
    for (int it = 0; it < max_steps && best_d > 1e-14; ++it) {
        double step[3], det;
        gauss_newton_step(p, t, lambda, step, det);
        if (!(std::fabs(det) > 1e-300)) break;
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

// The refinement in the four lanes of one vector (GCC/clang vector extensions: one AVX register
// with -mavx2), each lane refining its own colour: the lane runs refine's operations in refine's
// order on its own state, so its result has refine's bits. A lane that refine would have left (a
// break, the residual test, max_steps) is masked out of every later update and, at the end of the
// step, hands its result back and takes the next colour, so the four lanes stay busy although the
// colours need 2 to 12 steps.
typedef double d4 __attribute__((vector_size(32)));
typedef std::int64_t m4 __attribute__((vector_size(32)));

inline d4 bc(double v) { return d4{v, v, v, v}; }
inline d4 sel(m4 m, d4 a, d4 b) { return m ? a : b; }
inline bool any(m4 m) { return (m[0] | m[1] | m[2] | m[3]) != 0; }
inline d4 clamp01(d4 v) { return sel(v > bc(0.0), sel(v < bc(1.0), v, bc(1.0)), bc(0.0)); }  // NaN -> 0

//! The states of four refinements (refine's locals, lane by lane).
struct Refine4 {
    V3T<d4> p, t;
    d4 best_d, lambda;
    m4 active, steps;
    //! One step of refine's loop body in every active lane; a lane stays active when refine
    //! would run another step.
    void step(int max_steps) {
        d4 s[3], det;
        gauss_newton_step(p, t, lambda, s, det);
        active &= sel(det < bc(0.0), -det, det) > bc(1e-300);  // |det| > 1e-300 (NaN: false)
        const V3T<d4> q{clamp01(p.x + s[0]), clamp01(p.y + s[1]), clamp01(p.z + s[2])};
        active &= ~(dist2(q, p) < bc(1e-16));
        const d4 dq = dist2(eval(q), t);
        const m4 improves = dq < best_d;
        const m4 better = active & improves, worse = active & ~improves;
        best_d = sel(better, dq, best_d);
        p = {sel(better, q.x, p.x), sel(better, q.y, p.y), sel(better, q.z, p.z)};
        const d4 down = lambda * 0.1;
        lambda = sel(better, sel(down < bc(1e-9), bc(1e-9), down), sel(worse, lambda * 100.0, lambda));
        active &= ~(worse & (lambda > bc(1e6)));
        steps -= active;  // active lanes are -1
        active &= (steps < m4{} + std::int64_t(max_steps)) & (best_d > bc(1e-14));
    }
    //! Starts lane l on target tl from seed s (refine's state before its loop).
    void start(int l, const V3& tl, const V3& s, int max_steps) {
        t.x[l] = tl.x, t.y[l] = tl.y, t.z[l] = tl.z;
        p.x[l] = s.x, p.y[l] = s.y, p.z[l] = s.z;
        best_d[l] = dist2(eval(s), tl);
        lambda[l] = 1e-6;
        steps[l] = 0;
        active[l] = (max_steps > 0 && best_d[l] > 1e-14) ? -1 : 0;
    }
};

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

//! The inverse's target and seed for one colour (non-finite components read as 0).
V3 target_of(glm::vec3 rgb) {
    return {std::isfinite(rgb.x) ? rgb.x : 0.0, std::isfinite(rgb.y) ? rgb.y : 0.0, std::isfinite(rgb.z) ? rgb.z : 0.0};
}
const V3& seed_of(const V3& t) {
    return seed_table()[(std::size_t(seed_index(t.z)) * kSeedN + seed_index(t.y)) * kSeedN + seed_index(t.x)];
}
constexpr int kInverseSteps = 12;

}  // namespace

glm::vec3 rgb_to_ryb(glm::vec3 rgb) {
    const V3 t = target_of(rgb);
    const V3 p = refine(seed_of(t), t, kInverseSteps);
    return {float(p.x), float(p.y), float(p.z)};
}

void rgb_to_ryb_many(const glm::vec3* rgb, glm::vec3* ryb, std::size_t n) {
    Refine4 r{};
    std::size_t lane_colour[4] = {};
    bool held[4] = {};
    std::size_t next = 0;
    for (;;) {
        for (int l = 0; l < 4; ++l)
            while (!r.active[l]) {  // lane l is done (or empty): its result out, the next colour in
                if (held[l]) ryb[lane_colour[l]] = {float(r.p.x[l]), float(r.p.y[l]), float(r.p.z[l])};
                held[l] = next < n;
                if (!held[l]) break;
                const V3 tl = target_of(rgb[next]);
                r.start(l, tl, seed_of(tl), kInverseSteps);
                lane_colour[l] = next++;
            }
        if (!any(r.active)) break;
        r.step(kInverseSteps);
    }
}

float ryb_brightness(glm::vec3 c) {
    return std::sqrt(kBrightnessWeights.x * c.x * c.x + kBrightnessWeights.y * c.y * c.y +
                     kBrightnessWeights.z * c.z * c.z);
}

glm::vec3 mix_ryb(glm::vec3 a, glm::vec3 b, float t, float brightness_scale) {
    return mix_ryb_converted(a, b, rgb_to_ryb(a), rgb_to_ryb(b), t, brightness_scale);
}

glm::vec3 mix_ryb_converted(glm::vec3 a, glm::vec3 b, glm::vec3 ra, glm::vec3 rb, float t, float brightness_scale) {
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
