// raster/strokes.cpp — see strokes.h. Each stroke covers the union of its segments' capsules
// (pixel centre within width/2 of a projected segment); the nearest segment (first in order on a
// tie) gives the depth and normal at the pixel. Strokes are binned into 64 x 64 tiles in creation
// order and each tile is written by one task, so the "over" compositing gives the same bytes for
// any thread count; the reference traversal visits each stroke's whole bounding box on the whole
// image with the same distance and shading functions. In a tile, a short stroke is scanned in one
// pass over its bounds (every segment per 8-pixel group, in registers), a longer one segment by
// segment over each capsule_box; drawn pixels are shaded eight at a time across strokes.
#pragma GCC optimize("no-trapping-math")  // lets the capsule row loop if-convert and vectorise; values unchanged
#include "raster/strokes.h"

#include "raster/tiles.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <tuple>

#include "raster/vertex.h"
#include "core/maths.h"
#include "core/simd.h"

namespace aq::raster {

namespace {

constexpr int kGroup = 8;                   // pixels per vector step of the capsule scan (AVX2 lanes)
constexpr std::size_t kProjectBlock = 512;  // strokes per projection task
constexpr std::uint32_t kPrefetchAhead = 4;  // strokes of a tile fetched ahead of the scan
constexpr int kShadeBatch = 256;             // drawn pixels gathered across strokes before shading
constexpr std::uint32_t kDirectSegments = 4;  // strokes of at most this many segments and
constexpr int kDirectSpan = 24;               // bounds (in the tile) within this many pixels: one pass
constexpr int kPending = kShadeBatch + kTile * kTile + 8;  // + one stroke's tile + a vector's overrun

// For each 8-bit mask, the indices of its set bits in increasing order, one per byte (the lanes
// the drawn-pixel list keeps, for _mm256_permutevar8x32).
struct CompressTable {
    std::uint64_t lanes[256];
    constexpr CompressTable() : lanes{} {
        for (int m = 0; m < 256; ++m) {
            std::uint64_t v = 0;
            for (int b = 0, k = 0; b < 8; ++b)
                if (m & (1 << b)) v |= std::uint64_t(b) << (8 * k++);
            lanes[m] = v;
        }
    }
};
constexpr CompressTable kCompress;
static_assert(kTile % kGroup == 0);

// One projected segment: screen end points (pixels), view-space end points and normals.
struct Seg {
    float x0, y0, x1, y1;
    glm::vec3 pa, pb;   // view space
    glm::vec3 na, nb;   // view space, unit (zero: no normal)
    bool has_normal;
    bool valid = false;  // false: a dropped or clipped-away segment's slot (skipped)
};

#ifdef __AVX2__
// One segment's seg_dist2 for eight pixel centres, operation for operation (bit for bit).
struct SegLanes {
    __m256 x0, y0, dx, dy, len2;
    bool has_len;
    __m256i k;
    SegLanes() = default;
    SegLanes(const Seg& s, std::uint32_t index) {
        const float ddx = s.x1 - s.x0, ddy = s.y1 - s.y0, l2 = ddx * ddx + ddy * ddy;
        x0 = _mm256_set1_ps(s.x0), y0 = _mm256_set1_ps(s.y0), dx = _mm256_set1_ps(ddx), dy = _mm256_set1_ps(ddy);
        len2 = _mm256_set1_ps(l2), has_len = l2 > 0.0f, k = _mm256_set1_epi32(int(index));
    }
    __m256 dist2(__m256 px, __m256 py, __m256* t) const {
        const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
        __m256 u = zero;
        if (has_len)
            u = _mm256_div_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_sub_ps(px, x0), dx), _mm256_mul_ps(_mm256_sub_ps(py, y0), dy)), len2);
        u = _mm256_blendv_ps(u, zero, _mm256_cmp_ps(u, zero, _CMP_LT_OQ));
        u = _mm256_blendv_ps(u, one, _mm256_cmp_ps(u, one, _CMP_GT_OQ));
        const __m256 ex = _mm256_sub_ps(_mm256_add_ps(x0, _mm256_mul_ps(dx, u)), px);
        const __m256 ey = _mm256_sub_ps(_mm256_add_ps(y0, _mm256_mul_ps(dy, u)), py);
        *t = u;
        return _mm256_add_ps(_mm256_mul_ps(ex, ex), _mm256_mul_ps(ey, ey));
    }
};
#endif

// alpha8 reads pa, pb, na.xy as eight floats from pa and na.z, nb as four from na.z.
static_assert(offsetof(Seg, pb) == offsetof(Seg, pa) + 12 && offsetof(Seg, na) == offsetof(Seg, pa) + 24 &&
              offsetof(Seg, nb) == offsetof(Seg, pa) + 36 && offsetof(Seg, has_normal) >= offsetof(Seg, pa) + 48);

struct PStroke {
    std::uint32_t first, count;  // slots in segs (one per segment; invalid ones skipped)
    int bx0, by0, bx1, by1;      // covered pixel bounds (inclusive)
    bool light_dependent;
};

// Squared distance from pixel centre (px, py) to the segment and the screen parameter of the
// nearest point (the one distance function of both traversals).
inline float seg_dist2(const Seg& s, float px, float py, float* t) {
    const float dx = s.x1 - s.x0, dy = s.y1 - s.y0;
    const float len2 = dx * dx + dy * dy;
    float u = len2 > 0.0f ? ((px - s.x0) * dx + (py - s.y0) * dy) / len2 : 0.0f;
    u = u < 0.0f ? 0.0f : (u > 1.0f ? 1.0f : u);
    const float ex = s.x0 + dx * u - px, ey = s.y0 + dy * u - py;
    *t = u;
    return ex * ex + ey * ey;
}

// The pixels whose centre seg_dist2 can put within `half` of the segment: a centre farther than
// half + margin from the segment's box in x or in y has a computed distance above half, because
// the computed nearest point lies in that box up to the rounding of its three operations (a few
// ulps of the largest coordinate: kCapsuleMarginRel) and the squares' rounding is covered by
// kCapsuleMarginAbs (2·half·1e-3 > half²·2^-22 for half < 8000 px). Both traversals' bounds.
constexpr float kCapsuleMarginAbs = 1e-3f;
constexpr float kCapsuleMarginRel = 1e-6f;  // > 6·2^-24 with room for the bounds' own rounding
struct PxBox {
    int x0, y0, x1, y1;  // inclusive; empty when x0 > x1 or y0 > y1
};
inline PxBox capsule_box(const Seg& s, float half) {
    const float big = std::max({std::abs(s.x0), std::abs(s.y0), std::abs(s.x1), std::abs(s.y1), half});
    const float reach = half + kCapsuleMarginAbs + kCapsuleMarginRel * big + 0.5f;  // + 0.5: centre -> index
    return {int(std::ceil(std::min(s.x0, s.x1) - reach)), int(std::ceil(std::min(s.y0, s.y1) - reach)),
            int(std::floor(std::max(s.x0, s.x1) + reach - 1.0f)), int(std::floor(std::max(s.y0, s.y1) + reach - 1.0f))};
}

}  // namespace

ContourCache build_contour_cache(const scene::Scene& sc) {
    ContourCache cache;
    auto bits = [](glm::vec3 v) {
        std::uint32_t b[3];
        std::memcpy(b, &v, sizeof b);
        return std::make_tuple(b[0], b[1], b[2]);
    };
    for (const scene::Instance& inst : sc.instances) {
        if (inst.mesh < 0 || inst.mesh >= int(sc.meshes.size())) continue;
        for (const scene::Primitive& prim : sc.meshes[std::size_t(inst.mesh)].primitives) {
            if (scene::is_foliage(sc, inst, prim)) continue;
            ContourCache::Mesh m;
            m.prim = &prim;
            const std::uint32_t nv = std::uint32_t(prim.positions.size());
            // Weld by exact position (bit pattern: a total order, NaN included): every vertex maps
            // to the lowest index with the same position.
            std::vector<std::uint32_t> byp(nv);
            m.weld.resize(nv);
            for (std::uint32_t i = 0; i < nv; ++i) byp[i] = i;
            std::sort(byp.begin(), byp.end(), [&](std::uint32_t a, std::uint32_t b) {
                const auto ka = bits(prim.positions[a]), kb = bits(prim.positions[b]);
                return ka != kb ? ka < kb : a < b;
            });
            for (std::uint32_t k = 0; k < nv; ++k)
                m.weld[byp[k]] = (k > 0 && bits(prim.positions[byp[k]]) == bits(prim.positions[byp[k - 1]])) ? m.weld[byp[k - 1]] : byp[k];
            m.world.resize(nv);
            for (std::uint32_t i = 0; i < nv; ++i) m.world[i] = glm::vec3(inst.world * glm::vec4(prim.positions[i], 1.0f));
            // Edges (welded pair) with their uses (3 x triangle + edge slot, increasing), sorted by pair.
            struct Use {
                std::uint32_t a, b, use;
            };
            std::vector<Use> us;
            us.reserve(prim.indices.size());
            for (std::size_t t = 0; t + 2 < prim.indices.size(); t += 3) {
                const std::uint32_t i[3] = {prim.indices[t], prim.indices[t + 1], prim.indices[t + 2]};
                if (i[0] >= nv || i[1] >= nv || i[2] >= nv) continue;
                for (int e = 0; e < 3; ++e) {
                    std::uint32_t a = m.weld[i[e]], b = m.weld[i[(e + 1) % 3]];
                    if (a == b) continue;
                    if (a > b) std::swap(a, b);
                    us.push_back({a, b, std::uint32_t(t + std::size_t(e))});
                }
            }
            std::sort(us.begin(), us.end(), [](const Use& x, const Use& y) {
                return x.a != y.a ? x.a < y.a : (x.b != y.b ? x.b < y.b : x.use < y.use);
            });
            for (std::size_t k = 0; k < us.size();) {
                ContourCache::Edge e{us[k].a, us[k].b, std::uint32_t(m.uses.size()), 0};
                for (; k < us.size() && us[k].a == e.a && us[k].b == e.b; ++k) m.uses.push_back(us[k].use);
                e.uses_end = std::uint32_t(m.uses.size());
                m.edges.push_back(e);
            }
            cache.meshes.push_back(std::move(m));
        }
    }
    return cache;
}

std::vector<Stroke> contour_strokes(const PassScene& ps, const Exec& ex) {
    if (ps.contours) return contour_strokes(ps, *ps.contours, ex);
    return contour_strokes(ps, build_contour_cache(*ps.scene), ex);
}

std::vector<Stroke> contour_strokes(const PassScene& ps, const ContourCache& cache, const Exec& ex) {
    std::vector<Stroke> out;
    const glm::mat4 inv_view = glm::inverse(ps.camera.view);
    const glm::vec3 eye(inv_view[3]);
    const glm::vec3 fwd = -glm::vec3(inv_view[2]);
    for (const ContourCache::Mesh& m : cache.meshes) {
        const scene::Primitive& prim = *m.prim;
        const std::vector<glm::vec3>& world = m.world;
        const std::uint32_t nv = std::uint32_t(world.size());
        // Facing of every triangle from this view: +1 front, -1 back, 0 edge-on or not finite (unused).
        const std::size_t nt = prim.indices.size() / 3;
        std::vector<std::int8_t> facing(nt, 0);
        for_each_block(ex, nt, kContourBlock, [&](std::size_t t0, std::size_t t1) {
            for (std::size_t t = t0; t < t1; ++t) {
                const std::uint32_t i[3] = {prim.indices[3 * t], prim.indices[3 * t + 1], prim.indices[3 * t + 2]};
                if (i[0] >= nv || i[1] >= nv || i[2] >= nv) continue;
                const glm::vec3 n = glm::cross(world[i[1]] - world[i[0]], world[i[2]] - world[i[0]]);
                const glm::vec3 to_eye = ps.camera.orthographic ? -fwd : eye - world[i[0]];
                const float f = glm::dot(n, to_eye);
                if (!std::isfinite(f) || f == 0.0f) continue;
                facing[t] = f > 0.0f ? 1 : -1;
            }
        });
        // Silhouette edges (a front and a back triangle share them), in order of first use. A use
        // (3 x triangle + edge slot) belongs to one edge only, so the first uses are distinct and
        // the order is that of a table indexed by first use (no sort).
        std::vector<std::uint32_t> by_first(prim.indices.size(), ~0u);
        for_each_block(ex, m.edges.size(), kContourBlock, [&](std::size_t e0, std::size_t e1) {
            for (std::size_t ei = e0; ei < e1; ++ei) {
                const ContourCache::Edge& e = m.edges[ei];
                bool front = false, back = false;
                std::uint32_t first = ~0u;
                for (std::uint32_t k = e.uses_begin; k < e.uses_end; ++k) {
                    const std::int8_t f = facing[m.uses[k] / 3];
                    if (f == 0) continue;
                    first = std::min(first, m.uses[k]);
                    (f > 0 ? front : back) = true;
                }
                if (front && back) by_first[first] = std::uint32_t(ei);  // distinct first uses: one writer
            }
        });
        std::vector<std::pair<std::uint32_t, std::uint32_t>> sil;
        for (const std::uint32_t ei : by_first)
            if (ei != ~0u) sil.push_back({m.edges[ei].a, m.edges[ei].b});
        // Vertex -> incident silhouette edges in increasing edge order (a CSR table by counting
        // sort: edge k is appended to its two vertices' lists in order of k).
        std::vector<std::uint32_t> inc_begin(std::size_t(nv) + 1, 0), inc(2 * sil.size());
        for (const auto& e : sil) ++inc_begin[e.first + 1], ++inc_begin[e.second + 1];
        for (std::uint32_t v = 0; v < nv; ++v) inc_begin[v + 1] += inc_begin[v];
        {
            std::vector<std::uint32_t> fill(inc_begin.begin(), inc_begin.end() - 1);
            for (std::uint32_t k = 0; k < sil.size(); ++k) {  // (silhouette edges join vertices < nv:
                inc[fill[sil[k].first]++] = k;                 // their triangles passed the index check)
                inc[fill[sil[k].second]++] = k;
            }
        }
        struct Range {
            const std::uint32_t *lo, *hi;
        };
        auto incident = [&](std::uint32_t v) { return Range{inc.data() + inc_begin[v], inc.data() + inc_begin[v + 1]}; };
        std::vector<char> used(sil.size(), 0);
        auto extend = [&](std::vector<std::uint32_t>& chain) {
            for (;;) {
                const std::uint32_t v = chain.back();
                const auto [lo, hi] = incident(v);
                if (hi - lo != 2) return;  // an end, or a junction of 3+ contour edges
                std::size_t next = sil.size();
                for (auto it = lo; it != hi; ++it)
                    if (!used[*it]) next = std::min<std::size_t>(next, *it);
                if (next == sil.size()) return;
                used[next] = 1;
                chain.push_back(sil[next].first == v ? sil[next].second : sil[next].first);
            }
        };
        for (std::size_t k = 0; k < sil.size(); ++k) {
            if (used[k]) continue;
            used[k] = 1;
            std::vector<std::uint32_t> fwd_chain = {sil[k].first, sil[k].second};
            extend(fwd_chain);
            std::vector<std::uint32_t> back_chain = {sil[k].first};
            extend(back_chain);
            Stroke s;
            for (std::size_t m = back_chain.size(); m-- > 1;) s.points.push_back(world[back_chain[m]]);
            for (std::uint32_t v : fwd_chain) s.points.push_back(world[v]);
            out.push_back(std::move(s));
        }
    }
    return out;
}

void render_strokes(ImageF& out, const PassScene& ps, const std::vector<Stroke>& strokes, const StrokeParams& p,
                    const Exec& ex, std::size_t* dropped) {
    const std::vector<Stroke>* one[1] = {&strokes};
    render_strokes(out, ps, one, p, ex, dropped);
}

namespace {

//! Throws aq::Error for a parameter out of range or more strokes / vertices than the limits;
//! returns the number of strokes.
std::size_t check_strokes(std::span<const std::vector<Stroke>* const> lists, const StrokeParams& p) {
    auto finite_in = [](float v, float lo, float hi) { return std::isfinite(v) && v >= lo && v <= hi; };
    if (!(std::isfinite(p.width_px) && p.width_px > 0.0f && p.width_px <= kMaxStrokeWidthPx))
        throw Error("strokes: width must be in (0, 64] pixels");
    if (!finite_in(p.delta, 0, 1) || !finite_in(p.beta, -1, 1) || !finite_in(p.alpha, 0, 1))
        throw Error("strokes: delta in [0, 1], beta in [-1, 1], alpha in [0, 1]");
    for (float v : {p.fade_near, p.fade_far, p.nv_lo, p.nv_hi})
        if (!finite_in(v, 0, 1)) throw Error("strokes: fades must be in [0, 1]");
    if (!finite_in(p.nl_lo, -1, 1) || !finite_in(p.nl_hi, -1, 1)) throw Error("strokes: n.l fades must be in [-1, 1]");
    std::size_t count = 0, total = 0;
    for (const std::vector<Stroke>* l : lists) {
        count += l->size();
        for (const Stroke& s : *l) total += s.points.size();
    }
    if (count > kMaxStrokes) throw Error("strokes: " + std::to_string(count) + " strokes exceed the limit");
    if (total > kMaxStrokeVertices)
        throw Error("strokes: " + std::to_string(total) + " stroke vertices exceed the limit of " + std::to_string(kMaxStrokeVertices));
    if (p.test != DepthTest::Binary && (!p.depth_map || p.depth_map->empty() || p.depth_map->channels() != 1))
        throw Error("strokes: the blurred depth test needs a 1-channel depth map");
    return count;
}

//! The strokes projected to the pass's pixels: one slot per stroke segment (a dropped or
//! clipped-away one stays invalid and is skipped) and the strokes with pixels to draw, in
//! submission order.
struct ProjectedStrokes {
    std::vector<Seg> segs;
    std::vector<PStroke> strokes;
    std::size_t dropped = 0;  //!< segments with non-finite or far-off coordinates
};

//! Project (clip at the near plane in view space). Strokes in parallel: each fills its own slots
//! of `segs` and its bounds.
ProjectedStrokes project_strokes(std::span<const std::vector<Stroke>* const> lists, std::size_t count,
                                 const PassScene& ps, const PassViewSetup& view, float half, const Exec& ex) {
    const int W = view.width, H = view.height;
    const glm::mat4 proj = projection_matrix(view.camera, float(ps.width) / float(ps.height));
    const glm::mat3 vrot(view.camera.view);
    const float znear = view.camera.znear;
    std::vector<const Stroke*> all;
    all.reserve(count);
    for (const std::vector<Stroke>* l : lists)
        for (const Stroke& s : *l) all.push_back(&s);
    std::vector<std::uint32_t> slot(all.size() + 1, 0);
    for (std::size_t i = 0; i < all.size(); ++i)
        slot[i + 1] = slot[i] + std::uint32_t(all[i]->points.size() > 1 ? all[i]->points.size() - 1 : 0);
    ProjectedStrokes r;
    std::vector<Seg>& segs = r.segs;
    segs.resize(slot.back());
    std::vector<PStroke> projected(all.size());
    std::vector<std::uint32_t> valid_count(all.size(), 0), drops(all.size(), 0);
    auto to_px = [&](glm::vec3 v, float* x, float* y) {
        const glm::vec4 c = proj * glm::vec4(v, 1.0f);
        *x = (c.x / c.w + 1.0f) * 0.5f * float(W);
        *y = (1.0f - c.y / c.w) * 0.5f * float(H);
    };
    auto project = [&](std::size_t si) {
        const Stroke& s = *all[si];
        PStroke q{slot[si], slot[si + 1] - slot[si], 1 << 30, 1 << 30, -1, -1, s.light_dependent};
        const bool normals = s.normals.size() == s.points.size();
        // Each point is transformed once (a segment's end is the next one's start); a segment end
        // moved by near-plane clipping is projected anew.
        struct End {
            glm::vec3 v, n;  // view space
            float x, y;      // pixels
            float ln;        // |n|
        };
        auto end_of = [&](std::size_t i) {
            End e;
            e.v = glm::vec3(view.camera.view * glm::vec4(s.points[i], 1.0f));
            e.n = normals ? vrot * s.normals[i] : glm::vec3(0);
            to_px(e.v, &e.x, &e.y);
            e.ln = glm::length(e.n);
            return e;
        };
        End eb = s.points.size() > 1 ? end_of(0) : End{};
        for (std::size_t i = 0; i + 1 < s.points.size(); ++i) {
            const End ea = eb;
            eb = end_of(i + 1);
            glm::vec3 a = ea.v, b = eb.v, na = ea.n, nb = eb.n;
            bool a_moved = false, b_moved = false;
            if (!std::isfinite(a.x + a.y + a.z + b.x + b.y + b.z + na.x + na.y + na.z + nb.x + nb.y + nb.z)) {
                ++drops[si];
                continue;
            }
            if (!view.camera.orthographic) {
                const float da = -a.z, db = -b.z;
                if (da < znear && db < znear) continue;
                if (da < znear || db < znear) {  // clip to the near plane
                    const float t = (znear - da) / (db - da);
                    const glm::vec3 c = a + (b - a) * t;
                    const glm::vec3 nc = na + (nb - na) * t;
                    if (da < znear) a = c, na = nc, a_moved = true;
                    else b = c, nb = nc, b_moved = true;
                }
            }
            Seg g;
            if (a_moved) to_px(a, &g.x0, &g.y0);
            else g.x0 = ea.x, g.y0 = ea.y;
            if (b_moved) to_px(b, &g.x1, &g.y1);
            else g.x1 = eb.x, g.y1 = eb.y;
            if (!std::isfinite(g.x0 + g.y0 + g.x1 + g.y1) || std::abs(g.x0) > 1e7f || std::abs(g.y0) > 1e7f ||
                std::abs(g.x1) > 1e7f || std::abs(g.y1) > 1e7f) {
                ++drops[si];
                continue;
            }
            g.pa = a;
            g.pb = b;
            const float la = a_moved ? glm::length(na) : ea.ln, lb = b_moved ? glm::length(nb) : eb.ln;
            g.has_normal = normals && la > 0.0f && lb > 0.0f;
            g.na = g.has_normal ? na / la : glm::vec3(0);
            g.nb = g.has_normal ? nb / lb : glm::vec3(0);
            g.valid = true;
            const PxBox box = capsule_box(g, half);
            q.bx0 = std::min(q.bx0, box.x0);
            q.by0 = std::min(q.by0, box.y0);
            q.bx1 = std::max(q.bx1, box.x1);
            q.by1 = std::max(q.by1, box.y1);
            segs[slot[si] + i] = g;
            ++valid_count[si];
        }
        q.bx0 = std::max(q.bx0, 0);
        q.by0 = std::max(q.by0, 0);
        q.bx1 = std::min(q.bx1, W - 1);
        q.by1 = std::min(q.by1, H - 1);
        projected[si] = q;
    };
    for_each_block(ex, all.size(), kProjectBlock, [&](std::size_t s0, std::size_t s1) {
        for (std::size_t si = s0; si < s1; ++si) project(si);
    });
    for (std::size_t si = 0; si < all.size(); ++si) {
        const PStroke& q = projected[si];
        r.dropped += drops[si];
        if (valid_count[si] > 0 && q.bx0 <= q.bx1 && q.by0 <= q.by1) r.strokes.push_back(q);
    }
    return r;
}

//! The drawing's work, bounded before any pixel is touched (docs/limits.md "Work budgets"): in
//! pixel-segment distance tests as the chosen traversal makes them. The reference tries every
//! segment of a stroke at every pixel of the stroke's bounds; the tiled traversal tries each
//! segment over its capsule bounds within the image, and looks at every segment of a stroke once
//! per tile the stroke's bounds touch. Throws aq::Error over kMaxStrokeWork.
void check_stroke_work(const ProjectedStrokes& pr, float half, int W, int H, const Exec& ex) {
    const std::vector<PStroke>& ps_strokes = pr.strokes;
    const std::vector<Seg>& segs = pr.segs;
    double work = 0;
    for (const PStroke& st : ps_strokes) {
        const double bw = st.bx1 - st.bx0 + 1, bh = st.by1 - st.by0 + 1;
        if (ex.traversal == Traversal::Reference) {
            work += bw * bh * double(st.count);
            continue;
        }
        const double tiles = double(st.bx1 / kTile - st.bx0 / kTile + 1) * double(st.by1 / kTile - st.by0 / kTile + 1);
        work += tiles * double(st.count);
        for (std::uint32_t k = st.first; k < st.first + st.count; ++k) {
            if (!segs[k].valid) continue;
            const PxBox b = capsule_box(segs[k], half);
            const double w = std::min(b.x1, W - 1) - std::max(b.x0, 0) + 1 + 2 * (kGroup - 1);  // widened to 8-pixel groups
            const double h = std::min(b.y1, H - 1) - std::max(b.y0, 0) + 1;
            if (w > 0 && h > 0) work += w * h;
        }
    }
    if (work > double(kMaxStrokeWork))
        throw Error("strokes: drawing these strokes at " + std::to_string(W) + "x" + std::to_string(H) + " would take " +
                    std::to_string(static_cast<long long>(work / 1e6)) + " million pixel-segment tests, over the budget of " +
                    std::to_string(kMaxStrokeWork / 1'000'000) + " million (docs/limits.md \"Work budgets\"); use fewer or "
                    "shorter segments, a narrower stroke or a smaller image");
}

//! The value of a drawn pixel once its nearest segment is known (composite): eq. 2 visibility and
//! the §4.4 fades, alpha_of(...) composited "over" the stroke map (over). depth_at: the depth map
//! at a pixel (the texel itself when the map has the pass's size, as the toolkit resamples).
struct StrokeShader {
    const StrokeParams& p;
    const PassViewSetup& view;
    const std::vector<Seg>& segs;
    glm::vec3 light_view;
    View<const float> D;
    int W, H;
    bool tested;
    float delta;

    StrokeShader(const StrokeParams& params, const PassViewSetup& v, const std::vector<Seg>& s, glm::vec3 light)
        : p(params), view(v), segs(s), light_view(light), W(v.width), H(v.height) {
        if (p.depth_map && !p.depth_map->empty() && p.depth_map->channels() == 1) D = p.depth_map->view<float>();
        tested = D.data != nullptr;
        delta = p.test == DepthTest::Binary ? 0.0f : p.delta;
    }
    float depth_at(int x, int y) const {
        const float Dv = maths::sample_resampled(D, x, y, W, H);
        return p.test == DepthTest::BlurredRgba8 ? quantize_depth_rgba8(Dv) : Dv;
    }
    float alpha_of(bool light_dependent, const Seg& g, float ts, int x, int y) const {
        // Screen parameter -> view-space parameter (perspective-correct through the depths).
        float t = ts;
        if (!view.camera.orthographic) {
            const float za = -g.pa.z, zb = -g.pb.z;
            t = (ts / zb) / ((1.0f - ts) / za + ts / zb);
        }
        const glm::vec3 pv = g.pa + (g.pb - g.pa) * t;
        const float fd = view.normalized(-pv.z);
        const float fv = tested ? blurred_visibility(depth_at(x, y), fd, delta, p.beta) : 1.0f;
        float a = p.alpha * fv * (1.0f - maths::smoothstep(p.fade_near, p.fade_far, fd));
        if (g.has_normal) {
            glm::vec3 n = g.na + (g.nb - g.na) * t;
            const float ln = glm::length(n);
            n = ln > 0.0f ? n / ln : n;
            const glm::vec3 v = view.camera.orthographic ? glm::vec3(0, 0, 1) : glm::normalize(-pv);
            a *= maths::smoothstep(p.nv_lo, p.nv_hi, std::abs(glm::dot(n, v)));
            if (light_dependent) a *= 1.0f - maths::smoothstep(p.nl_lo, p.nl_hi, glm::dot(n, light_view));
        }
        return a;
    }
#ifdef __AVX2__
    // alpha_of for eight drawn pixels (lane l: pixel (xs[l], ys[l]), segment ks[l], screen parameter
    // ts[l], a hatching stroke's when lights[l]; n <= 8 lanes used, the others copy lane 0): its
    // operations lane by lane, bit for bit (glm's dot is (x·x + y·y) + z·z, normalize multiplies by
    // 1 / sqrt).
    void alpha8(const int* xs, const int* ys, const std::uint32_t* ks, const float* ts, const std::uint8_t* lights,
                int n, float* out_a) const {
        // Fields, one register each: ts, pa.xyz, pb.xyz, na.xyz, nb.xyz (transposed from the
        // lanes' segments: 8 x 8 and 8 x 4 floats), D, has_normal, light.
        alignas(32) float f0[8], f13[8], f14[8], f15[8];
        const Seg* g8[8];
        bool any_normal = false, any_light = false;
        for (int l = 0; l < 8; ++l) {
            const int src = l < n ? l : 0;  // unused lanes copy lane 0
            const Seg& g = segs[ks[src]];
            g8[l] = &g;
            f0[l] = ts[src];
            f13[l] = !tested ? 0.0f : (l < n ? depth_at(xs[l], ys[l]) : f13[0]);
            f14[l] = g.has_normal ? 1.0f : 0.0f;
            f15[l] = lights[src] ? 1.0f : 0.0f;
            any_normal = any_normal || g.has_normal;
            any_light = any_light || lights[src];
        }
        __m256 F[16];
        F[0] = _mm256_load_ps(f0), F[13] = _mm256_load_ps(f13), F[14] = _mm256_load_ps(f14), F[15] = _mm256_load_ps(f15);
        {
            __m256 r[8], t[8];
            for (int l = 0; l < 8; ++l) r[l] = _mm256_loadu_ps(&g8[l]->pa.x);  // pa, pb, na.xy
            for (int l = 0; l < 8; l += 2) t[l] = _mm256_unpacklo_ps(r[l], r[l + 1]), t[l + 1] = _mm256_unpackhi_ps(r[l], r[l + 1]);
            for (int l = 0; l < 8; l += 4) {
                r[l] = _mm256_shuffle_ps(t[l], t[l + 2], 0x44), r[l + 1] = _mm256_shuffle_ps(t[l], t[l + 2], 0xEE);
                r[l + 2] = _mm256_shuffle_ps(t[l + 1], t[l + 3], 0x44), r[l + 3] = _mm256_shuffle_ps(t[l + 1], t[l + 3], 0xEE);
            }
            for (int c = 0; c < 4; ++c)
                F[1 + c] = _mm256_permute2f128_ps(r[c], r[c + 4], 0x20), F[5 + c] = _mm256_permute2f128_ps(r[c], r[c + 4], 0x31);
            __m256 q[4];
            for (int l = 0; l < 4; ++l)  // na.z, nb: lane l in the low half, lane l + 4 in the high half
                q[l] = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(&g8[l]->na.z)), _mm_loadu_ps(&g8[l + 4]->na.z), 1);
            const __m256 u0 = _mm256_unpacklo_ps(q[0], q[1]), u1 = _mm256_unpackhi_ps(q[0], q[1]);
            const __m256 u2 = _mm256_unpacklo_ps(q[2], q[3]), u3 = _mm256_unpackhi_ps(q[2], q[3]);
            F[9] = _mm256_shuffle_ps(u0, u2, 0x44), F[10] = _mm256_shuffle_ps(u0, u2, 0xEE);
            F[11] = _mm256_shuffle_ps(u1, u3, 0x44), F[12] = _mm256_shuffle_ps(u1, u3, 0xEE);
        }
        auto ld = [&](int k) { return F[k]; };
        auto set = [](float v) { return _mm256_set1_ps(v); };
        const __m256 one = set(1.0f), zero = _mm256_setzero_ps(), sign = set(-0.0f);
        const __m256 s = ld(0);
        __m256 t = s;
        if (!view.camera.orthographic) {
            const __m256 za = _mm256_xor_ps(ld(3), sign), zb = _mm256_xor_ps(ld(6), sign);
            const __m256 q = _mm256_div_ps(s, zb);
            t = _mm256_div_ps(q, _mm256_add_ps(_mm256_div_ps(_mm256_sub_ps(one, s), za), q));
        }
        auto lerp = [&](int a, int b) { return _mm256_add_ps(ld(a), _mm256_mul_ps(_mm256_sub_ps(ld(b), ld(a)), t)); };
        const __m256 pvx = lerp(1, 4), pvy = lerp(2, 5), pvz = lerp(3, 6);
        const __m256 fd = _mm256_div_ps(_mm256_sub_ps(_mm256_xor_ps(pvz, sign), set(view.depth_near)),
                                        set(view.depth_far - view.depth_near));
        __m256 fv = one;
        if (tested) {
            const __m256 x = _mm256_add_ps(_mm256_sub_ps(ld(13), fd), set(p.beta));
            fv = delta > -delta ? maths::smoothstep8(-delta, delta, x)
                                : _mm256_and_ps(_mm256_cmp_ps(x, set(-delta), _CMP_GE_OQ), one);
        }
        __m256 a = _mm256_mul_ps(_mm256_mul_ps(set(p.alpha), fv), _mm256_sub_ps(one, maths::smoothstep8(p.fade_near, p.fade_far, fd)));
        if (any_normal) {
            auto dot = [](__m256 ax, __m256 ay, __m256 az, __m256 bx, __m256 by, __m256 bz) {
                return _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(ax, bx), _mm256_mul_ps(ay, by)), _mm256_mul_ps(az, bz));
            };
            __m256 nx = lerp(7, 10), ny = lerp(8, 11), nz = lerp(9, 12);
            const __m256 ln = _mm256_sqrt_ps(dot(nx, ny, nz, nx, ny, nz));
            const __m256 pos = _mm256_cmp_ps(ln, zero, _CMP_GT_OQ);
            nx = _mm256_blendv_ps(nx, _mm256_div_ps(nx, ln), pos);
            ny = _mm256_blendv_ps(ny, _mm256_div_ps(ny, ln), pos);
            nz = _mm256_blendv_ps(nz, _mm256_div_ps(nz, ln), pos);
            __m256 vx = zero, vy = zero, vz = one;
            if (!view.camera.orthographic) {
                const __m256 wx = _mm256_xor_ps(pvx, sign), wy = _mm256_xor_ps(pvy, sign), wz = _mm256_xor_ps(pvz, sign);
                const __m256 inv = _mm256_div_ps(one, _mm256_sqrt_ps(dot(wx, wy, wz, wx, wy, wz)));
                vx = _mm256_mul_ps(wx, inv), vy = _mm256_mul_ps(wy, inv), vz = _mm256_mul_ps(wz, inv);
            }
            const __m256 nv = _mm256_andnot_ps(sign, dot(nx, ny, nz, vx, vy, vz));
            __m256 an = _mm256_mul_ps(a, maths::smoothstep8(p.nv_lo, p.nv_hi, nv));
            if (any_light) {
                const __m256 nl = dot(nx, ny, nz, set(light_view.x), set(light_view.y), set(light_view.z));
                const __m256 lit = _mm256_mul_ps(an, _mm256_sub_ps(one, maths::smoothstep8(p.nl_lo, p.nl_hi, nl)));
                an = _mm256_blendv_ps(an, lit, _mm256_cmp_ps(ld(15), zero, _CMP_GT_OQ));
            }
            a = _mm256_blendv_ps(a, an, _mm256_cmp_ps(ld(14), zero, _CMP_GT_OQ));
        }
        alignas(32) float r[8];
        _mm256_store_ps(r, a);
        for (int l = 0; l < n; ++l) out_a[l] = r[l];
    }
#endif
};

inline void over(float* dst, float a) { *dst = a + *dst * (1.0f - a); }

//! The reference traversal: per stroke, every pixel of its bounds tries every segment.
void draw_strokes_reference(float* img, const ProjectedStrokes& pr, float r2, const StrokeShader& sh) {
    const std::vector<PStroke>& ps_strokes = pr.strokes;
    const std::vector<Seg>& segs = pr.segs;
    const int W = sh.W;
    for (const PStroke& st : ps_strokes)
        for (int y = st.by0; y <= st.by1; ++y)
            for (int x = st.bx0; x <= st.bx1; ++x) {
                const float px = float(x) + 0.5f, py = float(y) + 0.5f;
                float best = std::numeric_limits<float>::infinity(), bt = 0;
                std::uint32_t bs = 0;
                for (std::uint32_t k = st.first; k < st.first + st.count; ++k) {
                    if (!segs[k].valid) continue;
                    float t;
                    const float d2 = seg_dist2(segs[k], px, py, &t);
                    if (d2 < best) best = d2, bt = t, bs = k;
                }
                if (best <= r2) over(img + std::size_t(y) * W + x, sh.alpha_of(st.light_dependent, segs[bs], bt, x, y));
            }
}

//! One tile's drawing (draw_strokes_tiled), strokes in order: per pixel the nearest segment of the
//! stroke being drawn (best, bt, bs), and the drawn pixels waiting to be shaded, in drawing order
//! (strokes in order, each row by row): their alphas do not depend on the order, so they are
//! computed eight at a time across strokes, then composited "over" in this order. Flushed at
//! kShadeBatch and at the end.
class StrokeTile {
public:
    StrokeTile(float* img, const StrokeShader& sh, const std::vector<Seg>& segs, TileRect tr, float half, float r2)
        : img(img), sh(sh), segs(segs), W(sh.W), X0(tr.x0), Y0(tr.y0), X1(tr.x1), Y1(tr.y1), half(half), r2(r2) {}

    //! Lists the pixels of the stroke in this tile (x0..x1, y0..y1: its bounds clipped to the tile).
    void draw(const PStroke& st) {
        const int x0 = std::max(st.bx0, X0), x1 = std::min(st.bx1, X1);
        const int y0 = std::max(st.by0, Y0), y1 = std::min(st.by1, Y1);
        const std::uint8_t light = st.light_dependent ? 1 : 0;
#ifdef __AVX2__
        if (st.count <= kDirectSegments && x1 - x0 < kDirectSpan && y1 - y0 < kDirectSpan) scan_short(st, x0, x1, y0, y1, light);
        else
#endif
            scan_long(st, x0, x1, y0, y1, light);
        if (np >= kShadeBatch) flush();
    }

    //! Shades the listed pixels and composites them in order.
    void flush() {
#ifdef __AVX2__
    for (int i0 = 0; i0 < np; i0 += 8) {
        const int m = std::min(8, np - i0);
        float av[8];
        sh.alpha8(qx + i0, qy + i0, pk + i0, pt + i0, plight + i0, m, av);
        for (int l = 0; l < m; ++l) over(img + std::size_t(qy[i0 + l]) * W + qx[i0 + l], av[l]);
    }
#else
    for (int i = 0; i < np; ++i)
        over(img + std::size_t(qy[i]) * W + qx[i], sh.alpha_of(plight[i] != 0, segs[pk[i]], pt[i], qx[i], qy[i]));
#endif
    np = 0;
    }

private:
#ifdef __AVX2__
    // Appends the lanes of `mask` (pixels xs on row y, screen parameters u, segments k) to the
    // drawn-pixel list, in lane order: a table gives the kept lanes' indices.
    void list8(int mask, __m256i xs, int y, __m256 u, __m256i k, std::uint8_t light) {
    const __m256i idx = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(std::int64_t(kCompress.lanes[mask])));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(qx + np), _mm256_permutevar8x32_epi32(xs, idx));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(qy + np), _mm256_set1_epi32(y));
    _mm256_storeu_ps(pt + np, _mm256_permutevar8x32_ps(u, idx));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(pk + np), _mm256_permutevar8x32_epi32(k, idx));
    std::memset(plight + np, light, kGroup);
    np += __builtin_popcount(unsigned(mask));
    }

    // A short stroke (hatching: a few segments over a few pixels) in one pass over its bounds: per
    // group of eight pixels, every segment in order (the strict < of nearest(), first on a tie) in
    // registers, the drawn lanes listed at once. Pixels of the bounds outside every capsule_box
    // are not drawn, as in the reference.
    void scan_short(const PStroke& st, int x0, int x1, int y0, int y1, std::uint8_t light) {
    int nseg = 0;
    SegLanes sl[kDirectSegments];
    for (std::uint32_t k = st.first; k < st.first + st.count; ++k)
        if (segs[k].valid) sl[nseg++] = SegLanes(segs[k], k);
    const int gx0 = X0 + ((x0 - X0) & ~(kGroup - 1));
    const __m256 r2v = _mm256_set1_ps(r2), inf = _mm256_set1_ps(std::numeric_limits<float>::infinity());
    for (int y = y0; y <= y1; ++y) {
        const __m256 vpy = _mm256_set1_ps(float(y) + 0.5f);
        for (int gx = gx0; gx <= x1; gx += kGroup) {
            const __m256i xs = _mm256_add_epi32(_mm256_set1_epi32(gx), __m256i(simd::kLaneIndex8));
            const __m256 vpx = _mm256_add_ps(_mm256_cvtepi32_ps(xs), _mm256_set1_ps(0.5f));
            __m256 best8 = inf, bu = _mm256_setzero_ps();
            __m256i bk = _mm256_setzero_si256();
            for (int i = 0; i < nseg; ++i) {
                __m256 u;
                const __m256 d2 = sl[i].dist2(vpx, vpy, &u);
                const __m256 win = _mm256_cmp_ps(d2, best8, _CMP_LT_OQ);
                best8 = _mm256_blendv_ps(best8, d2, win);
                bu = _mm256_blendv_ps(bu, u, win);
                bk = _mm256_blendv_epi8(bk, sl[i].k, _mm256_castps_si256(win));
            }
            const __m256 in_tile = _mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_set1_epi32(X1 + 1), xs));
            const int mask = _mm256_movemask_ps(_mm256_and_ps(_mm256_cmp_ps(best8, r2v, _CMP_LE_OQ), in_tile));
            if (mask != 0) list8(mask, xs, y, bu, bk, light);
        }
    }
    }
#endif

    // A longer stroke, segment by segment.
    void scan_long(const PStroke& st, int x0, int x1, int y0, int y1, std::uint8_t light) {
    // Per row of the tile, the span [lo, hi] the stroke's segment bounds have touched:
    // only it is initialised and scanned (outside it no segment is near, best stays
    // +inf and nothing is drawn, as over the whole stroke bounds).
    int lo[kTile], hi[kTile];
    for (int y = y0; y <= y1; ++y) lo[y - Y0] = x1 + 1, hi[y - Y0] = x1;
    auto touch = [&](int y, int a, int b) {
        float* brow = best + (y - Y0) * kTile - X0;
        int& l = lo[y - Y0];
        int& h = hi[y - Y0];
        if (l > h) {
            std::fill(brow + a, brow + b + 1, std::numeric_limits<float>::infinity());
            l = a, h = b;
            return;
        }
        if (a < l) std::fill(brow + a, brow + l, std::numeric_limits<float>::infinity()), l = a;
        if (b > h) std::fill(brow + h + 1, brow + b + 1, std::numeric_limits<float>::infinity()), h = b;
    };
    // Segments in order, each over its own capsule bounds: the same minimum (first on
    // a tie) as the reference's loop over all segments per pixel.
    // A segment's span is widened to whole 8-pixel groups of the tile row (within the
    // tile): its distances there are exact too, and a pixel outside its capsule_box is
    // either not drawn or nearer to another segment, so the minimum is the reference's
    // (which tries every segment at every pixel of the stroke's bounds). The groups run
    // as one 8-lane step each, without the short rows' scalar remainders.
    for (std::uint32_t k = st.first; k < st.first + st.count; ++k) {
        const Seg& g = segs[k];
        if (!g.valid) continue;
        const PxBox b = capsule_box(g, half);
        const int sy0 = std::max(y0, b.y0), sy1 = std::min(y1, b.y1);
        const int cx0 = std::max(x0, b.x0), cx1 = std::min(x1, b.x1);
        if (cx0 > cx1 || sy0 > sy1) continue;
        const int sx0 = X0 + ((cx0 - X0) & ~(kGroup - 1));
        const int sx1 = std::min(X1, X0 + ((cx1 - X0) | (kGroup - 1)));
        const int groups_end = sx0 + ((sx1 - sx0 + 1) & ~(kGroup - 1));
        for (int y = sy0; y <= sy1; ++y) {
            touch(y, sx0, sx1);
            // Selects, not a branch: the groups vectorise (no-trapping-math above); the
            // same strict < (first segment on a tie; NaN never wins).
            float* __restrict brow = best + (y - Y0) * kTile - X0;
            float* __restrict trow = bt + (y - Y0) * kTile - X0;
            std::uint32_t* __restrict srow = bs + (y - Y0) * kTile - X0;
            const float py = float(y) + 0.5f;
            auto nearer = [&](int x) {
                float t;
                const float d2 = seg_dist2(g, float(x) + 0.5f, py, &t);
                const bool win = d2 < brow[x];
                brow[x] = win ? d2 : brow[x];
                trow[x] = win ? t : trow[x];
                srow[x] = win ? k : srow[x];
            };
            int x = sx0;
            for (; x < groups_end; x += kGroup)
                for (int l = 0; l < kGroup; ++l) nearer(x + l);
            for (; x <= sx1; ++x) nearer(x);  // the tile's last pixels when W % 8 != 0
        }
    }
    // The drawn pixels are listed: with AVX2 eight at a time, compressed by a table, without
    // a branch per pixel (which ones are drawn is irregular along a thin stroke).
    for (int y = y0; y <= y1; ++y) {
        const float* brow = best + (y - Y0) * kTile - X0;
        const float* trow = bt + (y - Y0) * kTile - X0;
        const std::uint32_t* srow = bs + (y - Y0) * kTile - X0;
        int x = lo[y - Y0];
        const int h = hi[y - Y0];
#ifdef __AVX2__
        const __m256 r2v = _mm256_set1_ps(r2);
        for (; x + kGroup - 1 <= h; x += kGroup) {  // spans are whole groups but at the image's edge
            const int mask =
                _mm256_movemask_ps(_mm256_cmp_ps(_mm256_loadu_ps(brow + x), r2v, _CMP_LE_OQ));
            if (mask != 0)
                list8(mask, _mm256_add_epi32(_mm256_set1_epi32(x), __m256i(simd::kLaneIndex8)), y,
                      _mm256_loadu_ps(trow + x),
                      _mm256_loadu_si256(reinterpret_cast<const __m256i*>(srow + x)), light);
        }
#endif
        for (; x <= h; ++x)
            if (brow[x] <= r2)
                qx[np] = x, qy[np] = y, pk[np] = srow[x], pt[np] = trow[x], plight[np++] = light;
    }
    }

    float* const img;
    const StrokeShader& sh;
    const std::vector<Seg>& segs;
    const int W, X0, Y0, X1, Y1;
    const float half, r2;
    float best[kTile * kTile], bt[kTile * kTile];
    std::uint32_t bs[kTile * kTile];
    alignas(32) int qx[kPending], qy[kPending];
    alignas(32) std::uint32_t pk[kPending];
    alignas(32) float pt[kPending];
    std::uint8_t plight[kPending];
    int np = 0;
};

//! One tile of the tiled traversal (strokes binned into tiles in submission order, raster/tiles.h):
//! each binned stroke's segments over their capsule bounds, the drawn pixels listed and shaded
//! eight at a time, composited in drawing order (StrokeTile).
void draw_stroke_tile(float* img, const ProjectedStrokes& pr, std::span<const std::uint32_t> items, TileRect tr,
                      float half, float r2, const StrokeShader& sh) {
    const std::vector<PStroke>& ps_strokes = pr.strokes;
    const std::vector<Seg>& segs = pr.segs;
    StrokeTile t(img, sh, segs, tr, half, r2);
    for (std::size_t it = 0; it < items.size(); ++it) {
        if (it + kPrefetchAhead < items.size()) {  // the strokes of a tile lie apart in memory
            const PStroke& ahead = ps_strokes[items[it + kPrefetchAhead]];
            __builtin_prefetch(&segs[ahead.first]);
            __builtin_prefetch(reinterpret_cast<const char*>(&segs[ahead.first]) + 64);
            __builtin_prefetch(reinterpret_cast<const char*>(&segs[ahead.first]) + 128);
        }
        if (it + 2 * kPrefetchAhead < items.size()) __builtin_prefetch(&ps_strokes[items[it + 2 * kPrefetchAhead]]);
        t.draw(ps_strokes[items[it]]);
    }
    t.flush();
}

}  // namespace

void render_strokes(ImageF& out, const PassScene& ps, std::span<const std::vector<Stroke>* const> lists,
                    const StrokeParams& p, const Exec& ex, std::size_t* dropped) {
    const std::size_t count = check_strokes(lists, p);
    const PassViewSetup view = pass_view(ps, PassView::Camera, p.scale);
    const int W = view.width, H = view.height;
    if (out.width() != W || out.height() != H || out.channels() != 1) out = ImageF(W, H, 1, 0.0f);
    else std::fill(out.data(), out.data() + std::size_t(W) * H, 0.0f);
    const float half = 0.5f * p.width_px * float(W) / float(kLd06SizeReferenceStrokes);
    const float r2 = half * half;
    const ProjectedStrokes pr = project_strokes(lists, count, ps, view, half, ex);
    if (dropped) *dropped = pr.dropped;
    const glm::mat3 vrot(view.camera.view);
    const StrokeShader sh(p, view, pr.segs, glm::normalize(vrot * ps.light_dir));
    check_stroke_work(pr, half, W, H, ex);
    const TileGrid grid(W, H);
    const TileBins bins = ex.traversal == Traversal::Fast ? bin_boxes(grid, pr.strokes.size(), [&](std::size_t k) {
        const PStroke& st = pr.strokes[k];
        return TileRect{st.bx0, st.by0, st.bx1, st.by1};
    }) : TileBins{};
    traverse_tiles(ex, grid, [&] { draw_strokes_reference(out.data(), pr, r2, sh); },
                   [&](int tile, TileRect tr) { draw_stroke_tile(out.data(), pr, bins.of(tile), tr, half, r2, sh); });
}

}  // namespace aq::raster
