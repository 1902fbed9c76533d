// raster/particles.cpp — see particles.h. Sprites are binned into 64 x 64 tiles in particle order;
// each tile is written by one task, visiting its particles in order, so the order-dependent
// additive clamp gives the same bytes for any thread count. The reference traversal loops over the
// particles and their blocks on the whole image and calls the same per-fragment function.
#include "raster/particles.h"

#include "raster/tiles.h"

#include <algorithm>
#include <cmath>
#include <limits>

#ifdef __AVX2__
#include <immintrin.h>
#endif

#include "core/hash.h"
#include "raster/vertex.h"
#include "core/maths.h"

namespace aq::raster {

namespace {


// Seeded choices are keyed by particle index through core/hash.h's hash32, never by thread.
inline float unit01(std::uint32_t h) { return float(h >> 8) * (1.0f / 16777216.0f); }

// A uniformly distributed unit vector from two hashes (z uniform in [-1, 1], angle uniform).
glm::vec3 random_unit(std::uint32_t h1, std::uint32_t h2) {
    const float z = 2.0f * unit01(h1) - 1.0f;
    const float a = 6.28318530718f * unit01(h2);
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    return {r * std::cos(a), r * std::sin(a), z};
}

struct Sprite {
    float cx, cy;  // centre, pixels
    float size;    // pixels
    float depth;   // normalised depth of the particle
    int x0, y0, x1, y1;  // covered pixel range (inclusive), clamped to the raster
    int cls;
};

#ifdef __AVX2__
// All bits where x is finite.
inline __m256 finite8(__m256 x) {
    const __m256 abs = _mm256_and_ps(x, _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff)));
    return _mm256_cmp_ps(abs, _mm256_set1_ps(std::numeric_limits<float>::infinity()), _CMP_LT_OQ);
}

// The fragments of sprite s at pixels [xa, xb] of row y, eight per step: render_particles'
// per-fragment function lane by lane (the same operations in the same order; a lane the scalar
// code returns early from keeps its value). b: the row of the class map, D: the row of dpix.
void fragment_row_avx2(const Sprite& s, bool round, float delta, float beta, int y, int xa, int xb, float* b, const float* D) {
    const __m256 lane = _mm256_setr_ps(0, 1, 2, 3, 4, 5, 6, 7);
    const __m256i ilane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const __m256 half = _mm256_set1_ps(0.5f), one = _mm256_set1_ps(1.0f);
    const __m256 left = _mm256_set1_ps(s.cx - 0.5f * s.size), size = _mm256_set1_ps(s.size);
    const float v = ((float(y) + 0.5f) - (s.cy - 0.5f * s.size)) / s.size;
    const __m256 dv2 = _mm256_set1_ps((v - 0.5f) * (v - 0.5f));
    const __m256 depth = _mm256_set1_ps(s.depth), vbeta = _mm256_set1_ps(beta);
    const bool depth_finite = std::isfinite(s.depth);
    const bool step = !(delta > -delta);  // ld06_step's binary limit (delta = 0)
    for (int x = xa; x <= xb; x += 8) {
        const __m256i in = _mm256_cmpgt_epi32(_mm256_set1_epi32(xb - x + 1), ilane);  // lanes <= xb
        const __m256 bv = _mm256_maskload_ps(b + x, in);
        // if (b >= 1) return;
        __m256 keep = _mm256_or_ps(_mm256_cmp_ps(bv, one, _CMP_GE_OQ), _mm256_castsi256_ps(_mm256_xor_si256(in, _mm256_set1_epi32(-1))));
        if (_mm256_movemask_ps(keep) == 0xff) continue;  // all saturated (dense crowns): nothing to compute
        const __m256 Dv = _mm256_maskload_ps(D + x, in);
        __m256 shape = one;
        if (round) {
            const __m256 fx = _mm256_add_ps(_mm256_set1_ps(float(x)), lane);  // float(x) exactly
            const __m256 u = _mm256_div_ps(_mm256_sub_ps(_mm256_add_ps(fx, half), left), size);
            const __m256 du = _mm256_sub_ps(u, half);
            const __m256 r = _mm256_sqrt_ps(_mm256_add_ps(_mm256_mul_ps(du, du), dv2));
            shape = _mm256_sub_ps(one, maths::smoothstep8(0.4f, 0.5f, r));  // particle_shape
            if (depth_finite)
                keep = _mm256_or_ps(keep, _mm256_and_ps(_mm256_cmp_ps(shape, _mm256_setzero_ps(), _CMP_EQ_OQ), finite8(Dv)));
        }
        if (_mm256_movemask_ps(keep) == 0xff) continue;
        const __m256 arg = _mm256_add_ps(_mm256_sub_ps(Dv, depth), vbeta);  // blurred_visibility
        const __m256 fv = step ? _mm256_and_ps(_mm256_cmp_ps(arg, _mm256_set1_ps(-delta), _CMP_GE_OQ), one)
                               : maths::smoothstep8(-delta, delta, arg);
        const __m256 nb = maths::sat8(_mm256_add_ps(_mm256_mul_ps(fv, shape), bv));
        _mm256_maskstore_ps(b + x, _mm256_castps_si256(_mm256_andnot_ps(keep, _mm256_castsi256_ps(in))), nb);
    }
}
#endif

}  // namespace

void check_particle_params(const ParticleParams& p) {
    if (!(std::isfinite(p.quantity) && p.quantity >= 0.0f) || !(std::isfinite(p.height) && p.height > 0.0f) ||
        !(std::isfinite(p.spread) && p.spread >= 0.0f))
        throw Error("particles: quantity, spread and height must be finite (height > 0)");
    if (!(p.t0 <= p.t1)) throw Error("particles: t0 must not exceed t1");
    const double n = double(p.quantity) * double(p.height) * double(p.height);  // eq. 8
    if (!(n <= double(kMaxParticles)))
        throw Error("particles: quantity x height² = " + std::to_string(std::llround(std::min(n, 1e18))) +
                    " particles exceeds the limit of " + std::to_string(kMaxParticles));
}

std::vector<Particle> place_particles(const ImplicitSurface& s, float plant_height, glm::vec3 light_dir,
                                      const ParticleParams& p) {
    check_particle_params(p);
    const double n = double(p.quantity) * double(p.height) * double(p.height);  // eq. 8
    std::vector<Particle> out;
    if (s.positions.empty()) return out;
    const std::size_t N = std::size_t(std::llround(n));
    // Eq. 9 in world units: the offset ω_spread·√h is in units of the height h, scaled to the plant.
    const float offset = p.spread * std::sqrt(p.height) * (plant_height / p.height);
    const glm::vec3 l = glm::normalize(light_dir);
    out.reserve(N);
    const std::uint32_t V = std::uint32_t(s.positions.size());
    for (std::size_t i = 0; i < N; ++i) {
        const std::uint32_t k = std::uint32_t(i) * 3u + p.seed * 0x9E3779B9u;
        const std::uint32_t v = hash32(k) % V;
        Particle q;
        q.position = s.positions[v] + random_unit(hash32(k + 1u), hash32(k + 2u)) * offset;
        q.normal = s.normals[v];
        const float d = glm::dot(q.normal, l);  // eq. 11
        q.cls = d <= p.t0 ? 0 : (d <= p.t1 ? 1 : 2);
        out.push_back(q);
    }
    return out;
}

float particle_size_px(float d, float size_scale, float size_bias, int raster_w) {
    return ((1.0f - d) * size_scale + size_bias) * (float(raster_w) / float(kLd06SizeReference));
}

float particle_shape(float u, float v) {
    const float du = u - 0.5f, dv = v - 0.5f;
    const float r = std::sqrt(du * du + dv * dv);
    return 1.0f - maths::smoothstep(0.4f, 0.5f, r);
}

void render_particles(ImageF& dark, ImageF& medium, ImageF& bright, const PassScene& ps,
                      const std::vector<Particle>& particles, const ParticleParams& p, const Exec& ex) {
    auto finite_in = [](float v, float lo, float hi) { return std::isfinite(v) && v >= lo && v <= hi; };
    if (!finite_in(p.delta, 0, 1) || !finite_in(p.beta, -1, 1)) throw Error("particles: delta in [0, 1], beta in [-1, 1]");
    if (!finite_in(p.size_scale, 0, 1000) || !finite_in(p.size_bias, 0, 200))
        throw Error("particles: size scale must be in [0, 1000] and bias in [0, 200] pixels");
    if (p.shape != 0 && p.shape != 1) throw Error("particles: shape must be 0 (round) or 1 (square)");
    if (!p.depth_map || p.depth_map->empty() || p.depth_map->channels() != 1)
        throw Error("particles: the depth test needs a 1-channel depth map");
    const PassViewSetup view = pass_view(ps, PassView::Camera, p.scale);
    const int W = view.width, H = view.height;
    const float smax = particle_size_px(0.0f, p.size_scale, p.size_bias, W);
    if (double(particles.size()) * double(smax) * double(smax) > kMaxParticleFragments)
        throw Error("particles: " + std::to_string(particles.size()) + " sprites of up to " + std::to_string(int(smax)) +
                    " px would exceed the work bound of the pass (docs/ld06.md \"Limits\")");
    for (ImageF* m : {&dark, &medium, &bright}) {
        if (m->width() != W || m->height() != H || m->channels() != 1) *m = ImageF(W, H, 1, 0.0f);
        else std::fill(m->data(), m->data() + std::size_t(W) * H, 0.0f);
    }
    float* maps[3] = {dark.data(), medium.data(), bright.data()};
    // Project every particle (pure per particle).
    const glm::mat4 proj = projection_matrix(view.camera, float(ps.width) / float(ps.height));
    const glm::mat4 pv = proj * view.camera.view;
    std::vector<Sprite> sprites;
    sprites.reserve(particles.size());
    for (const Particle& q : particles) {
        const glm::vec4 c = pv * glm::vec4(q.position, 1.0f);
        const float eye = -(view.camera.view * glm::vec4(q.position, 1.0f)).z;
        if (!(c.w > 0.0f) || !std::isfinite(c.x + c.y + c.w) || eye < view.camera.znear || eye > view.camera.zfar) continue;
        Sprite s;
        // Centre and size snapped to the rasterizer's 1/256 px, so a size of s pixels covers exactly
        // s x s pixels whatever float rounding eq. 10 met.
        auto snap = [](double v) { return float(std::nearbyint(v * kSubpixelOne) / kSubpixelOne); };
        s.cx = snap((double(c.x) / c.w + 1.0) * 0.5 * W);
        s.cy = snap((1.0 - double(c.y) / c.w) * 0.5 * H);
        s.depth = view.normalized(eye);
        s.size = snap(particle_size_px(maths::sat(s.depth), p.size_scale, p.size_bias, W));
        // Pixels with centre x + 0.5 in [cx - s/2, cx + s/2): x in [ceil(cx - s/2 - 0.5), ceil(cx + s/2 - 0.5) - 1].
        const double x0 = std::ceil(double(s.cx) - 0.5 * s.size - 0.5), x1 = std::ceil(double(s.cx) + 0.5 * s.size - 0.5) - 1;
        const double y0 = std::ceil(double(s.cy) - 0.5 * s.size - 0.5), y1 = std::ceil(double(s.cy) + 0.5 * s.size - 0.5) - 1;
        if (x1 < 0 || y1 < 0 || x0 > W - 1 || y0 > H - 1 || x1 < x0 || y1 < y0) continue;
        s.x0 = int(std::max(0.0, x0));
        s.y0 = int(std::max(0.0, y0));
        s.x1 = int(std::min(double(W - 1), x1));
        s.y1 = int(std::min(double(H - 1), y1));
        s.cls = q.cls;
        sprites.push_back(s);
    }
    // D at every pixel of the pass, once (a pure function of the pixel; every fragment of the
    // pixel used to sample it again): the map resampled to the pass size (the stages' rule: the
    // texel itself at equal sizes, as LD06's 520 px depth map and particle pass are), then
    // quantised (eq. 3-4).
    const View<const float> D = p.depth_map->view<float>();
    std::vector<float> dpix(std::size_t(W) * H);
    auto sample_row = [&](int y) {
        for (int x = 0; x < W; ++x) {
            float Dv = maths::sample_resampled(D, x, y, W, H);
            if (p.test == DepthTest::BlurredRgba8) Dv = quantize_depth_rgba8(Dv);
            dpix[std::size_t(y) * W + x] = Dv;
        }
    };
    for_each_block(ex, std::size_t(H), 1, [&](std::size_t y0, std::size_t y1) {
        for (std::size_t y = y0; y < y1; ++y) sample_row(int(y));
    });
    const float delta = p.test == DepthTest::Binary ? 0.0f : p.delta;
    // The one per-fragment function: blurred test of the sprite's depth (eq. 2), shape, eq. 12.
    // A saturated pixel stays 1 (every contribution is >= 0), so it is skipped: exact.
    // Outside the round blotch (r >= 0.5) the shape is 0 and b = sat(f_v · 0 + b) = b for a finite
    // f_v (a finite D): skipped, exact (the corners of every sprite, ~21 % of its pixels).
    const bool round = p.shape != 1;
    auto fragment = [&](const Sprite& s, int x, int y) {
        const std::size_t i = std::size_t(y) * W + x;
        float& b = maps[s.cls][i];
        if (b >= 1.0f) return;
        const float u = ((float(x) + 0.5f) - (s.cx - 0.5f * s.size)) / s.size;
        const float v = ((float(y) + 0.5f) - (s.cy - 0.5f * s.size)) / s.size;
        float shape = 1.0f;
        if (round) {
            shape = particle_shape(u, v);
            if (shape == 0.0f && std::isfinite(dpix[i]) && std::isfinite(s.depth)) return;
        }
        const float fv = blurred_visibility(dpix[i], s.depth, delta, p.beta);
        b = maths::sat(fv * shape + b);
    };
    // The reference: every sprite in particle order over its box. The tiles: sprites binned in
    // particle order (raster/tiles.h), each tile drawn by one task.
    const TileGrid grid(W, H);
    const TileBins bins = ex.traversal == Traversal::Fast ? bin_boxes(grid, sprites.size(), [&](std::size_t k) {
        return TileRect{sprites[k].x0, sprites[k].y0, sprites[k].x1, sprites[k].y1};
    }) : TileBins{};
    auto reference = [&] {
        for (const Sprite& s : sprites)
            for (int y = s.y0; y <= s.y1; ++y)
                for (int x = s.x0; x <= s.x1; ++x) fragment(s, x, y);
    };
    traverse_tiles(ex, grid, reference, [&](int t, TileRect tr) {
        for (const std::uint32_t k : bins.of(t)) {
            const Sprite& s = sprites[k];
            const int xa = std::max(s.x0, tr.x0), xb = std::min(s.x1, tr.x1);
            for (int y = std::max(s.y0, tr.y0); y <= std::min(s.y1, tr.y1); ++y) {
#ifdef __AVX2__
                const std::size_t row = std::size_t(y) * W;
                fragment_row_avx2(s, round, delta, p.beta, y, xa, xb, maps[s.cls] + row, dpix.data() + row);
#else
                for (int x = xa; x <= xb; ++x) fragment(s, x, y);
#endif
            }
        }
    });
}

}  // namespace aq::raster
