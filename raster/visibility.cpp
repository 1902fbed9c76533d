// raster/visibility.cpp — the depth test of one triangle over a block of pixels (raster/visibility.h).
#include "raster/visibility.h"

#include <bit>
#include <cstdlib>
#include <limits>

#ifdef __AVX2__
#include <immintrin.h>
#endif

namespace aq::raster {

namespace {

constexpr int kPlainPixels = 4;

// The plain loop: the reference traversal's per-pixel test over for_each_inside's exact edge values.
void depth_test_plain(const TriSetup& t, int X0, int Y0, int stride, int x0, int x1, int y0, int y1, float* zbuf,
                      TileRef* ids, TileRef ref) {
    for_each_inside(t, x0, x1, y0, y1, [&](int x, int y, const std::int64_t* e) {
        const int li = (y - Y0) * stride + (x - X0);
        const Bary b = perspective_bary(t, e);
        if (b.depth < zbuf[li]) {
            zbuf[li] = b.depth;
            ids[li] = ref;
        }
    });
}

#ifdef __AVX2__
// Whether every edge value of t at the pixels [x0, x1] x [y0, y1] fits in int32: an edge function
// is linear, so its extremes over the block are at the corners.
bool edges_fit_int32(const TriSetup& t, int x0, int x1, int y0, int y1) {
    const int xs[2] = {x0, x1}, ys[2] = {y0, y1};
    for (const int x : xs)
        for (const int y : ys) {
            std::int64_t e[3];
            edge_values(t, x, y, e);
            for (const std::int64_t v : e)
                if (v < std::numeric_limits<std::int32_t>::min() || v > std::numeric_limits<std::int32_t>::max())
                    return false;
        }
    return true;
}

// perspective_bary's depth in eight lanes from their exact int32 edge values: the same operations
// in the same order as the scalar function, so each lane has its bits.
[[gnu::always_inline]] inline __m256 lanes_depth(const TriSetup& t, __m256i e0, __m256i e1, __m256i e2) {
    const __m256 q0 = _mm256_mul_ps(_mm256_cvtepi32_ps(e0), _mm256_set1_ps(t.inv_w[0]));
    const __m256 q1 = _mm256_mul_ps(_mm256_cvtepi32_ps(e1), _mm256_set1_ps(t.inv_w[1]));
    const __m256 q2 = _mm256_mul_ps(_mm256_cvtepi32_ps(e2), _mm256_set1_ps(t.inv_w[2]));
    const __m256 r = _mm256_div_ps(_mm256_set1_ps(1.0f), _mm256_add_ps(_mm256_add_ps(q0, q1), q2));
    const __m256 b1 = _mm256_mul_ps(q1, r), b2 = _mm256_mul_ps(q2, r);
    return _mm256_add_ps(_mm256_add_ps(_mm256_set1_ps(t.depth[0]), _mm256_mul_ps(b1, _mm256_set1_ps(t.depth[1] - t.depth[0]))),
                         _mm256_mul_ps(b2, _mm256_set1_ps(t.depth[2] - t.depth[0])));
}

// Blocks of at most eight pixels (most bins of a dense mesh: 1 x 2 to 3 x 2 pixels) in one
// register: lane l is pixel (l % w, l / w) of a block w pixels wide. It needs every |A_i|, |B_i|
// below 2^14 (the triangle's snapped extent below 64 px in x and y): then every pixel centre of the
// block lies within that extent of each vertex (bounds hold centres inside the snapped bounds; a
// block is inside the bounds), so each edge value E = dx (sy - Ya) - dy (sx - Xa) is below 2^29 and
// the lanes' int32 sums are exact.
constexpr int kBlock8Pixels = 8;
constexpr int kBlock8MinPixels = 2;  // a single pixel costs less in the plain loop (measured)
constexpr std::int32_t kBlock8Edge = 1 << 14;

bool block8_edges(const TriSetup& t) {
    std::uint32_t m = 0;
    for (int i = 0; i < 3; ++i) m |= std::uint32_t(std::abs(t.A[i])) | std::uint32_t(std::abs(t.B[i]));
    return m < std::uint32_t(kBlock8Edge);
}

// The lane offsets of a block w pixels wide (w = 1..8): dx = l % w, dy = l / w.
struct Block8Lanes {
    alignas(32) std::int32_t dx[kBlock8Pixels][8], dy[kBlock8Pixels][8];
    constexpr Block8Lanes() : dx{}, dy{} {
        for (int w = 1; w <= kBlock8Pixels; ++w)
            for (int l = 0; l < 8; ++l) dx[w - 1][l] = l % w, dy[w - 1][l] = l / w;
    }
};
constexpr Block8Lanes kBlock8Lanes;

void depth_test_block8(const TriSetup& t, int X0, int Y0, int stride, int x0, int x1, int y0, int y1, float* zbuf,
                       TileRef* ids, TileRef ref) {
    const int w = x1 - x0 + 1, n = w * (y1 - y0 + 1);
    const __m256i dx = _mm256_load_si256(reinterpret_cast<const __m256i*>(kBlock8Lanes.dx[w - 1]));
    const __m256i dy = _mm256_load_si256(reinterpret_cast<const __m256i*>(kBlock8Lanes.dy[w - 1]));
    std::int64_t e0[3];
    edge_values(t, x0, y0, e0);
    __m256i in = _mm256_cmpgt_epi32(_mm256_set1_epi32(n), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    __m256i e[3];
    for (int i = 0; i < 3; ++i) {
        e[i] = _mm256_add_epi32(_mm256_set1_epi32(std::int32_t(e0[i])),
                                _mm256_add_epi32(_mm256_mullo_epi32(dx, _mm256_set1_epi32(t.A[i] * kSubpixelOne)),
                                                 _mm256_mullo_epi32(dy, _mm256_set1_epi32(t.B[i] * kSubpixelOne))));
        in = _mm256_and_si256(in, _mm256_cmpgt_epi32(e[i], _mm256_set1_epi32(t.bias(i) - 1)));  // e >= bias
    }
    unsigned mask = unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(in)));
    if (mask == 0) return;
    alignas(32) float d[8];
    _mm256_store_ps(d, lanes_depth(t, e[0], e[1], e[2]));
    const std::int32_t* ldx = kBlock8Lanes.dx[w - 1];
    const std::int32_t* ldy = kBlock8Lanes.dy[w - 1];
    const std::size_t li0 = std::size_t(y0 - Y0) * stride + (x0 - X0);
    for (; mask; mask &= mask - 1) {
        const int l = std::countr_zero(mask);
        const std::size_t li = li0 + std::size_t(ldy[l]) * stride + ldx[l];
        if (d[l] < zbuf[li]) {
            zbuf[li] = d[l];
            ids[li] = ref;
        }
    }
}

// Eight pixels of a row per step. Lane values are computed modulo 2^32 (vector integer adds and
// multiplies wrap); every lane inside the block holds a value that fits in int32, so it is exact.
// Lanes past x1 are masked out of every load and store.
void depth_test_avx2(const TriSetup& t, int X0, int Y0, int stride, int x0, int x1, int y0, int y1, float* zbuf,
                     TileRef* ids, TileRef ref) {
    std::int64_t row[3];
    edge_values(t, x0, y0, row);
    const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    __m256i off[3], step[3], bias[3];
    for (int i = 0; i < 3; ++i) {
        const std::uint32_t sx = std::uint32_t(std::int64_t(t.A[i]) * kSubpixelOne);  // modulo 2^32
        off[i] = _mm256_mullo_epi32(lane, _mm256_set1_epi32(std::int32_t(sx)));
        step[i] = _mm256_set1_epi32(std::int32_t(sx * 8u));
        bias[i] = _mm256_set1_epi32(t.bias(i) - 1);  // e >= bias  <=>  e > bias - 1
    }
    const __m256i ref64 = _mm256_set1_epi64x(std::int64_t(std::uint64_t(ref.tri) << 32 | ref.chunk));
    const int n = x1 - x0 + 1;
    for (int y = y0; y <= y1; ++y) {
        __m256i e0 = _mm256_add_epi32(_mm256_set1_epi32(std::int32_t(row[0])), off[0]);
        __m256i e1 = _mm256_add_epi32(_mm256_set1_epi32(std::int32_t(row[1])), off[1]);
        __m256i e2 = _mm256_add_epi32(_mm256_set1_epi32(std::int32_t(row[2])), off[2]);
        const std::size_t li = std::size_t(y - Y0) * stride + (x0 - X0);
        float* zr = zbuf + li;
        TileRef* ir = ids + li;
        for (int k = 0; k < n; k += 8) {
            __m256i in = _mm256_and_si256(_mm256_cmpgt_epi32(e0, bias[0]),
                                          _mm256_and_si256(_mm256_cmpgt_epi32(e1, bias[1]), _mm256_cmpgt_epi32(e2, bias[2])));
            if (n - k < 8) in = _mm256_and_si256(in, _mm256_cmpgt_epi32(_mm256_set1_epi32(n - k), lane));
            if (!_mm256_testz_si256(in, in)) {
                const __m256 depth = lanes_depth(t, e0, e1, e2);
                const __m256 z = _mm256_maskload_ps(zr + k, in);
                const __m256i m = _mm256_and_si256(_mm256_castps_si256(_mm256_cmp_ps(depth, z, _CMP_LT_OQ)), in);
                if (!_mm256_testz_si256(m, m)) {
                    _mm256_maskstore_ps(zr + k, m, depth);
                    const __m256i lo = _mm256_cvtepi32_epi64(_mm256_castsi256_si128(m));
                    const __m256i hi = _mm256_cvtepi32_epi64(_mm256_extracti128_si256(m, 1));
                    _mm256_maskstore_epi64(reinterpret_cast<long long*>(ir + k), lo, ref64);
                    _mm256_maskstore_epi64(reinterpret_cast<long long*>(ir + k + 4), hi, ref64);
                }
            }
            e0 = _mm256_add_epi32(e0, step[0]);
            e1 = _mm256_add_epi32(e1, step[1]);
            e2 = _mm256_add_epi32(e2, step[2]);
        }
        for (int i = 0; i < 3; ++i) row[i] += std::int64_t(t.B[i]) * kSubpixelOne;
    }
}
#endif

}  // namespace

void depth_test_triangle(const TriSetup& t, int X0, int Y0, int stride, int x0, int x1, int y0, int y1, float* zbuf,
                         TileRef* ids, TileRef ref, VisibilitySchedule schedule) {
    if (x0 > x1 || y0 > y1) return;
#ifdef __AVX2__
    // Blocks of a few pixels (dense meshes' triangles) cost less in the plain loop than the vector
    // setup (BM_RasterFrame, docs/performance.md).
    const int pixels = (x1 - x0 + 1) * (y1 - y0 + 1);
    if (schedule == VisibilitySchedule::Fast && pixels >= kBlock8MinPixels && pixels <= kBlock8Pixels &&
        block8_edges(t)) {
        depth_test_block8(t, X0, Y0, stride, x0, x1, y0, y1, zbuf, ids, ref);
        return;
    }
    const bool small = pixels <= kPlainPixels;
    if (schedule == VisibilitySchedule::Fast && !small && edges_fit_int32(t, x0, x1, y0, y1)) {
        depth_test_avx2(t, X0, Y0, stride, x0, x1, y0, y1, zbuf, ids, ref);
        return;
    }
#else
    (void)schedule;
#endif
    depth_test_plain(t, X0, Y0, stride, x0, x1, y0, y1, zbuf, ids, ref);
}

}  // namespace aq::raster
