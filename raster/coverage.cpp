// raster/coverage.cpp — coverage antialiasing of the silhouettes (docs/raster.md "Coverage
// antialiasing"): after the single-sample traversal, the pixels whose 3x3 neighbourhood holds both
// covered and uncovered pixels get the coverage of the 4x4 samples of `--ssaa 4` by every triangle
// there (alpha-masked ones through their alpha test at each sample) as their alpha; an uncovered
// pixel there takes its covered neighbours' values. The samples' union is independent of the order
// in which triangles are met, so the plain loop over all triangles and the per-tile schedule over
// the bins give the same masks bit for bit.
#include <bit>
#include <cstdlib>

#include <immintrin.h>

#include "raster/raster_internal.h"

namespace aq::raster::detail {

namespace {

//! The 4x4 sample grid of ssaa 4 in a pixel: offsets ((2i + 1) / 8 − 1/2) px from the centre, in
//! the setup's fixed-point units (kSubpixelOne per pixel; exact).
constexpr std::int64_t kSampleOffset[kCoverageGrid] = {-kCoverageReach, -kSubpixelOne / 8, kSubpixelOne / 8,
                                                       kCoverageReach};
static_assert(kCoverageGrid * kCoverageGrid == 16, "the masks are 16 bits");
static_assert(kSubpixelOne == 256, "the AVX2 sample offsets below are these values");

//! Samples of pixel (x, y) that t covers: bit 4 sy + sx. With `alpha` (needs_alpha_test: t's draw
//! is alpha-masked) a sample is kept only where the alpha test passes there (the traversal's test,
//! at the sample's weights). `plain`: the scalar loop only (the reference traversal's; the tiled
//! one tests 16 samples per AVX2 step).
std::uint16_t sample_mask(const Frame& fr, const Chunk& ch, const TriSetup& t, int x, int y, bool plain, bool alpha) {
    std::int64_t c[3];
    edge_values(t, x, y, c);
    // Each edge's least and greatest value over the 16 samples (at the grid's corners): all
    // samples outside one edge -> none covered; inside all three (and no alpha test) -> all.
    bool all = !alpha;
    for (int i = 0; i < 3; ++i) {
        const std::int64_t reach = (std::abs(std::int64_t(t.A[i])) + std::abs(std::int64_t(t.B[i]))) * kSampleOffset[3];
        if (c[i] + reach < t.bias(i)) return 0;
        all = all && c[i] - reach >= t.bias(i);
    }
    if (all) return std::uint16_t(0xffff);
#ifdef __AVX2__
    // Schedule only: the 16 samples in two registers when every value fits in int32 (|c| < 2^30,
    // |A|, |B| < 2^20: each sample's value is within 2^28 of c), the same integers as below.
    bool fits = !plain;
    for (int i = 0; i < 3; ++i)
        fits = fits && std::abs(c[i]) < (std::int64_t(1) << 30) && std::abs(t.A[i]) < (1 << 20) && std::abs(t.B[i]) < (1 << 20);
    if (fits) {
        const __m256i ox = _mm256_setr_epi32(-96, -32, 32, 96, -96, -32, 32, 96);
        const __m256i oy_lo = _mm256_setr_epi32(-96, -96, -96, -96, -32, -32, -32, -32);
        const __m256i oy_hi = _mm256_setr_epi32(32, 32, 32, 32, 96, 96, 96, 96);
        __m256i lo = _mm256_set1_epi32(-1), hi = lo;
        for (int i = 0; i < 3; ++i) {
            const __m256i a = _mm256_mullo_epi32(_mm256_set1_epi32(t.A[i]), ox);
            const __m256i ci = _mm256_set1_epi32(std::int32_t(c[i]));
            const __m256i b = _mm256_set1_epi32(t.B[i]);
            const __m256i bias_m1 = _mm256_set1_epi32(t.bias(i) - 1);  // inside: E > bias - 1
            const __m256i e_lo = _mm256_add_epi32(ci, _mm256_add_epi32(a, _mm256_mullo_epi32(b, oy_lo)));
            const __m256i e_hi = _mm256_add_epi32(ci, _mm256_add_epi32(a, _mm256_mullo_epi32(b, oy_hi)));
            lo = _mm256_and_si256(lo, _mm256_cmpgt_epi32(e_lo, bias_m1));
            hi = _mm256_and_si256(hi, _mm256_cmpgt_epi32(e_hi, bias_m1));
        }
        std::uint16_t m = std::uint16_t(unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(lo))) |
                                        unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(hi))) << 8);
        if (!alpha) return m;
        for (std::uint16_t b = m; b; b = std::uint16_t(b & (b - 1))) {
            const int k = std::countr_zero(b);
            std::int64_t e[3];
            for (int i = 0; i < 3; ++i)
                e[i] = c[i] + std::int64_t(t.A[i]) * kSampleOffset[k % kCoverageGrid] +
                       std::int64_t(t.B[i]) * kSampleOffset[k / kCoverageGrid];
            if (!alpha_pass(fr, ch, t, perspective_bary(t, e))) m = std::uint16_t(m & ~(1u << k));
        }
        return m;
    }
#endif
    std::uint16_t m = 0;
    for (int sy = 0; sy < kCoverageGrid; ++sy)
        for (int sx = 0; sx < kCoverageGrid; ++sx) {
            std::int64_t e[3];
            for (int i = 0; i < 3; ++i)
                e[i] = c[i] + std::int64_t(t.A[i]) * kSampleOffset[sx] + std::int64_t(t.B[i]) * kSampleOffset[sy];
            if (!inside(t, e)) continue;
            if (alpha && !alpha_pass(fr, ch, t, perspective_bary(t, e))) continue;
            m = std::uint16_t(m | (1u << (kCoverageGrid * sy + sx)));
        }
    return m;
}

//! The edges of a compact sub-pixel record (its draw is opaque: no alpha test reads the rest).
TriSetup edges_of(const SubpixelTri& m) {
    TriSetup t(TriSetup::NoInit{});
    const std::int64_t X[3] = {m.X[0], m.X[1], m.X[2]}, Y[3] = {m.Y[0], m.Y[1], m.Y[2]};
    set_edges(X, Y, t);
    return t;
}

//! The n lowest bits set (n in [0, 64]): a row span of a 64-pixel tile row.
std::uint64_t low_bits(int n) { return n >= 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << n) - 1; }

//! Writes pixel (x, y)'s coverage from its sample mask m (a flagged pixel). Returns whether it
//! wrote anything.
bool write_coverage(const TargetPtrs& tp, const CoverageBits& cov, int x, int y, std::uint16_t mask) {
    const int n = std::popcount(mask);
    const std::size_t i = std::size_t(y) * tp.width + x;
    if (cov.at(x, y)) {
        // Covered centre: its own values, alpha = its samples' share (at least one: the centre
        // itself is covered even where a sliver holds none of the 16 samples).
        if (n == kCoverageSamples) return false;
        const float a = float(std::max(n, 1)) / float(kCoverageSamples);
        tp.color()[4 * i + 3] = a;
        for (int t = 0; t < scene::kNumControlTargets; ++t)
            if (float* c = tp.ctrl(t)) c[4 * i + 3] = a;
        return true;
    }
    if (n == 0) return false;
    // Uncovered centre with covered samples: the covered 8-neighbours' values (sums in row-major
    // order, as the SSAA resolve averages the covered samples), alpha = the samples' share.
    float rgb[3] = {0, 0, 0}, ctrl[scene::kNumControlTargets][3] = {}, nn[3] = {0, 0, 0};
    float depth = std::numeric_limits<float>::infinity(), diffuse = 0, specular = 0, id = 0;
    int k = 0;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const int u = x + dx, v = y + dy;
            if ((dx == 0 && dy == 0) || u < 0 || v < 0 || u >= cov.W || v >= cov.H || !cov.at(u, v)) continue;
            const std::size_t j = std::size_t(v) * tp.width + u;
            for (int c = 0; c < 3; ++c) rgb[c] += tp.color()[4 * j + c];
            for (int t = 0; t < scene::kNumControlTargets; ++t)
                if (tp.ctrl(t))
                    for (int c = 0; c < 3; ++c) ctrl[t][c] += tp.ctrl(t)[4 * j + c];
            depth = std::min(depth, tp.depth()[j]);
            if (tp.normal())
                for (int c = 0; c < 3; ++c) nn[c] += tp.normal()[3 * j + c];
            if (tp.diffuse()) diffuse += tp.diffuse()[j];
            if (tp.specular()) specular += tp.specular()[j];
            if (k == 0 && tp.id()) id = tp.id()[j];
            ++k;
        }
    if (k == 0) return false;  // samples of a sliver between pixel centres: left as background
    const float a = float(n) / float(kCoverageSamples), inv = 1.0f / float(k);
    for (int c = 0; c < 3; ++c) tp.color()[4 * i + c] = rgb[c] * inv;
    tp.color()[4 * i + 3] = a;
    for (int t = 0; t < scene::kNumControlTargets; ++t)
        if (tp.ctrl(t)) {
            for (int c = 0; c < 3; ++c) tp.ctrl(t)[4 * i + c] = ctrl[t][c] * inv;
            tp.ctrl(t)[4 * i + 3] = a;
        }
    tp.depth()[i] = depth;
    if (tp.normal()) {
        const glm::vec3 v = normalize3(glm::vec3(nn[0], nn[1], nn[2]) * inv);
        tp.normal()[3 * i] = v.x, tp.normal()[3 * i + 1] = v.y, tp.normal()[3 * i + 2] = v.z;
    }
    if (tp.diffuse()) tp.diffuse()[i] = diffuse * inv;
    if (tp.specular()) tp.specular()[i] = specular * inv;
    // object_id: the majority of the samples (as the SSAA resolve): the object's where it covers
    // more than half of them.
    if (tp.id()) tp.id()[i] = 2 * n > kCoverageSamples ? id : 0.0f;
    return true;
}

}  // namespace

void CoverageBits::reset(int w, int h) {
    W = w, H = h;
    words = (w + kTile - 1) / kTile;
    bits.assign(std::size_t(words) * std::size_t(h), 0);
}

void CoverageBits::from_alpha(const TargetPtrs& tp) {
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            if (tp.color()[4 * (std::size_t(y) * tp.width + x) + 3] > 0.0f) word(x / kTile, y) |= std::uint64_t(1) << (x % kTile);
}

// Plain reference: flags from each pixel's 3x3 neighbourhood, then every triangle over every
// flagged pixel of its sample bounds, then the writes.
void coverage_reference(const Frame& fr, const TargetPtrs& tp, const CoverageBits& cov) {
    const int W = cov.W, H = cov.H;
    std::vector<std::uint8_t> flag(std::size_t(W) * H, 0);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            bool any = false, all = true;
            for (int v = std::max(y - 1, 0); v <= std::min(y + 1, H - 1); ++v)
                for (int u = std::max(x - 1, 0); u <= std::min(x + 1, W - 1); ++u) {
                    any = any || cov.at(u, v);
                    all = all && cov.at(u, v);
                }
            flag[std::size_t(y) * W + x] = any && !all;
        }
    std::vector<std::uint16_t> mask(std::size_t(W) * H, 0);
    auto add = [&](const Chunk& ch, const TriSetup& t, const PixelRect& r, bool alpha) {
        for (int y = r.y0; y <= r.y1; ++y)
            for (int x = r.x0; x <= r.x1; ++x)
                if (flag[std::size_t(y) * W + x]) mask[std::size_t(y) * W + x] |= sample_mask(fr, ch, t, x, y, true, alpha);
    };
    for (const Chunk& ch : fr.chunks) {
        // Every triangle over its pixel-centre bounds widened by one pixel (the samples' reach,
        // without the cover bits that narrow it for the tiled schedule).
        for (const TriSetup& t : ch.tris) add(ch, t, coverage_bounds(t.x0, t.y0, t.x1, t.y1, 0, W, H), needs_alpha_test(fr, t));
        for (const SubpixelTri& m : ch.micro) add(ch, edges_of(m), {m.x0, m.y0, m.x1, m.y1}, false);
    }
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            if (flag[std::size_t(y) * W + x]) write_coverage(tp, cov, x, y, mask[std::size_t(y) * W + x]);
}

// One tile of the tiled schedule: the flags as 64-bit rows (3x3 OR and AND of the coverage
// bits), then the triangles binned to this tile over the flagged pixels, then the writes. Writes only this tile's
// pixels and reads only covered neighbours' values, which no tile writes (only their alpha).
bool coverage_tile(const Frame& fr, const TargetPtrs& tp, const CoverageBits& cov, int tile, TileRect tr) {
    // No triangle binned here (binned by coverage_bounds too): no sample of the tile is covered.
    bool binned = tile_binned(fr, tile);
    for (const Chunk& ch : fr.chunks)
        binned = binned || (!ch.fine_offsets.empty() && ch.fine_offsets[tile] != ch.fine_offsets[tile + 1]);
    if (!binned) return false;
    const int W = cov.W, H = cov.H;
    const int X0 = tr.x0, Y0 = tr.y0, X1 = tr.x1, Y1 = tr.y1, tx = X0 / kTile;
    const int tw = X1 - X0 + 1;
    const std::uint64_t valid = low_bits(tw);
    // Per row: OR and AND of the pixel and its left and right neighbours (outside the image: 0 for
    // OR, 1 for AND, i.e. not part of the neighbourhood).
    auto horizontal = [&](int y, std::uint64_t& o, std::uint64_t& a) {
        const std::uint64_t c = cov.word(tx, y) & valid;
        const bool has_l = tx > 0, has_r = X1 + 1 < W;
        const std::uint64_t l = has_l ? cov.word(tx - 1, y) >> 63 : 0;  // pixel X0 - 1
        const std::uint64_t r = has_r ? cov.word(tx + 1, y) & 1 : 0;    // pixel X1 + 1
        const std::uint64_t top = std::uint64_t(1) << (tw - 1);
        const std::uint64_t left_n = (c << 1) | l;                      // bit j: pixel j - 1
        const std::uint64_t right_n = (c >> 1) | (r ? top : 0);         // bit j: pixel j + 1
        o = (c | left_n | right_n) & valid;
        a = c & (left_n | (has_l ? 0 : 1)) & (right_n | (has_r ? 0 : top));
    };
    std::uint64_t hor[kTile + 2], hand[kTile + 2];
    for (int y = Y0 - 1; y <= Y1 + 1; ++y) {
        const int j = y - (Y0 - 1);
        if (y < 0 || y >= H) {
            hor[j] = 0, hand[j] = valid;
        } else {
            horizontal(y, hor[j], hand[j]);
        }
    }
    std::uint64_t flag[kTile];
    std::uint64_t flag_rows = 0;  // bit r: row r of the tile has a flagged pixel
    for (int y = Y0; y <= Y1; ++y) {
        const int j = y - (Y0 - 1);
        flag[y - Y0] = (hor[j - 1] | hor[j] | hor[j + 1]) & ~(hand[j - 1] & hand[j] & hand[j + 1]) & valid;
        flag_rows |= std::uint64_t(flag[y - Y0] != 0) << (y - Y0);
    }
    if (!flag_rows) return false;
    std::uint16_t mask[kTile * kTile];
    std::fill_n(mask, kTile * kTile, std::uint16_t(0));
    // The triangles binned here (by their coverage_bounds too: every triangle that may cover a
    // sample in the tile). Their coverage_bounds first (most reach no flagged pixel); the
    // ones that do are listed with their records prefetched, then tested a batch at a time (the
    // records are scattered over the chunk: a miss each, overlapped this way; schedule only).
    struct Hit {
        std::uint32_t tri;
        std::int16_t x0, x1, y0, y1;
    };
    constexpr int kBatch = 32;
    Hit hits[kBatch];
    int nh = 0;
    auto run = [&](const Chunk& ch) {
        for (int h = 0; h < nh; ++h) {
            const Hit& e = hits[h];
            const bool micro = e.tri & Chunk::kMicroItem;
            const TriSetup t = micro ? edges_of(ch.micro[e.tri & ~Chunk::kMicroItem]) : ch.tris[e.tri];
            const bool alpha = !micro && needs_alpha_test(fr, t);
            const int n = e.x1 - e.x0 + 1;
            const std::uint64_t range = low_bits(n) << (e.x0 - X0);
            for (int y = e.y0; y <= e.y1; ++y)
                for (std::uint64_t b = flag[y - Y0] & range; b; b &= b - 1) {
                    const int lx = std::countr_zero(b);
                    std::uint16_t& m = mask[(y - Y0) * kTile + lx];
                    if (m != 0xffff) m = std::uint16_t(m | sample_mask(fr, ch, t, X0 + lx, y, false, alpha));
                }
        }
        nh = 0;
    };
    for (const Chunk& ch : fr.chunks) {
        for (int list = 0; list < 2; ++list) {  // the traversal's bin, then the sub-pixel one
            const std::vector<std::uint32_t>& offsets = list == 0 ? ch.bin_offsets : ch.fine_offsets;
            const std::vector<std::uint32_t>& items = list == 0 ? ch.bin_items : ch.fine_items;
            const std::vector<Chunk::Bounds>& bounds = list == 0 ? ch.bin_bounds : ch.fine_bounds;
            if (offsets.empty()) continue;
            const std::uint32_t end = offsets[tile + 1];
            for (std::uint32_t k = offsets[tile]; k < end; ++k) {
                const Chunk::Bounds& b = bounds[k];
                const int x0 = std::max<int>(b.x0, X0), x1 = std::min<int>(b.x1, X1);
                const int y0 = std::max<int>(b.y0, Y0), y1 = std::min<int>(b.y1, Y1);
                if (x0 > x1 || y0 > y1 || !(flag_rows >> (y0 - Y0) & low_bits(y1 - y0 + 1))) continue;
                const int n = x1 - x0 + 1;
                const std::uint64_t range = low_bits(n) << (x0 - X0);
                std::uint64_t hit = 0;
                for (int y = y0; y <= y1; ++y) hit |= flag[y - Y0] & range;
                if (!hit) continue;
                if (items[k] & Chunk::kMicroItem) {
                    __builtin_prefetch(&ch.micro[items[k] & ~Chunk::kMicroItem]);
                } else {
                    const char* rec = reinterpret_cast<const char*>(&ch.tris[items[k]]);
                    __builtin_prefetch(rec);
                    __builtin_prefetch(rec + 64);
                }
                hits[nh++] = {items[k], std::int16_t(x0), std::int16_t(x1), std::int16_t(y0), std::int16_t(y1)};
                if (nh == kBatch) run(ch);
            }
        }
        run(ch);  // a chunk's records before the next chunk's
    }
    for (int y = Y0; y <= Y1; ++y)
        for (std::uint64_t b = flag[y - Y0]; b; b &= b - 1) {
            const int lx = std::countr_zero(b);
            write_coverage(tp, cov, X0 + lx, y, mask[(y - Y0) * kTile + lx]);
        }
    return true;
}

}  // namespace aq::raster::detail
