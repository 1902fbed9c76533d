// raster/setup.cpp — homogeneous clipping (near, far, guard band) and fixed-point triangle setup.
#include "raster/setup.h"

#include <cmath>

namespace aq::raster {

namespace {

constexpr std::int64_t kSmallTrianglePixels = 4;

template <class T>
inline T min3(T a, T b, T c) { return std::min(a, std::min(b, c)); }
template <class T>
inline T max3(T a, T b, T c) { return std::max(a, std::max(b, c)); }

// The snapped bounds of a triangle hold a pixel centre (c = 256 p + 128, xmin <= c <= xmax): the
// quick reject of setup_one and of the batch pre-pass (build() computes the clamped bounds).
inline bool bounds_hold_centre(const SnapVertex& a, const SnapVertex& b, const SnapVertex& c) {
    const std::int32_t xmin = min3(a.x, b.x, c.x), xmax = max3(a.x, b.x, c.x);
    const std::int32_t ymin = min3(a.y, b.y, c.y), ymax = max3(a.y, b.y, c.y);
    return (((xmin + kSubpixelOne / 2 - 1) >> kSubpixelBits) <= ((xmax - kSubpixelOne / 2) >> kSubpixelBits)) &
           (((ymin + kSubpixelOne / 2 - 1) >> kSubpixelBits) <= ((ymax - kSubpixelOne / 2) >> kSubpixelBits));
}

// Builds the setup of one snapped triangle; returns false when it covers no pixel centre, is
// degenerate after snapping or is culled. beta: original weights of the three vertices (clip
// path) or null (fast path, identity).
[[gnu::always_inline]] inline bool build(const SnapVertex (&sv)[3], const glm::vec3* beta, const Viewport& vp,
           const SetupOptions& opt, bool double_sided, TriSetup& t, ClipVerts& cv) {
    std::int64_t x[3] = {sv[0].x, sv[1].x, sv[2].x};
    std::int64_t y[3] = {sv[0].y, sv[1].y, sv[2].y};
    // Pixel bounds first (cheap, rejects most sub-pixel triangles): centres c = 256 p + 128 with
    // xmin <= c <= xmax.
    const std::int64_t xmin = min3(x[0], x[1], x[2]), xmax = max3(x[0], x[1], x[2]);
    const std::int64_t ymin = min3(y[0], y[1], y[2]), ymax = max3(y[0], y[1], y[2]);
    std::int64_t px0 = (xmin - kSubpixelOne / 2 + kSubpixelOne - 1) >> kSubpixelBits;
    std::int64_t px1 = (xmax - kSubpixelOne / 2) >> kSubpixelBits;
    std::int64_t py0 = (ymin - kSubpixelOne / 2 + kSubpixelOne - 1) >> kSubpixelBits;
    std::int64_t py1 = (ymax - kSubpixelOne / 2) >> kSubpixelBits;
    px0 = std::max<std::int64_t>(px0, 0);
    py0 = std::max<std::int64_t>(py0, 0);
    px1 = std::min<std::int64_t>(px1, vp.width - 1);
    py1 = std::min<std::int64_t>(py1, vp.height - 1);
    if (px0 > px1 || py0 > py1) return false;
    const std::int64_t area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
    if (area == 0) return false;  // degenerate after snapping
    // y-down screen: counter-clockwise in NDC (glTF front face) has negative area here.
    const bool back = area > 0;
    if (back && opt.cull_backfaces && !double_sided) return false;
    int order[3] = {0, 1, 2};
    if (area < 0) {
        order[1] = 2;
        order[2] = 1;
    }
    std::int64_t X[3], Y[3];
    for (int j = 0; j < 3; ++j) {
        X[j] = x[order[j]];
        Y[j] = y[order[j]];
    }
    for (int i = 0; i < 3; ++i) {
        const int a = (i + 1) % 3, b = (i + 2) % 3;  // edge i: vertex a -> vertex b, opposite i
        const std::int64_t dx = X[b] - X[a], dy = Y[b] - Y[a];
        t.A[i] = std::int32_t(-dy);
        t.B[i] = std::int32_t(dx);
        t.C[i] = dy * X[a] - dx * Y[a];
        const bool top_left = (dy == 0 && dx > 0) || dy < 0;
        t.bias[i] = top_left ? 0 : 1;
    }
    t.x0 = std::int32_t(px0);
    t.x1 = std::int32_t(px1);
    t.y0 = std::int32_t(py0);
    t.y1 = std::int32_t(py1);
    // Small-triangle fast path: most triangles of dense meshes cover at most a few pixel centres
    // of their bounds; a triangle that covers none is dropped here instead of being binned.
    if ((px1 - px0 + 1) * (py1 - py0 + 1) <= kSmallTrianglePixels) {
        bool any = false;
        for (int py = t.y0; py <= t.y1 && !any; ++py)
            for (int px = t.x0; px <= t.x1 && !any; ++px) {
                std::int64_t e[3];
                edge_values(t, px, py, e);
                any = inside(t, e);
            }
        if (!any) return false;
    }
    for (int j = 0; j < 3; ++j) {
        t.inv_w[j] = sv[order[j]].inv_w;
        t.depth[j] = sv[order[j]].depth;
        if (beta) cv.beta[j] = beta[order[j]];
    }
    t.perm = order[1] == 2 ? 1 : 0;
    t.back = back ? 1 : 0;
    return true;
}

struct ClipVertex {
    glm::dvec4 c;
    glm::dvec3 beta;
    double depth;
};

double plane_dist(const ClipVertex& v, int plane, const Viewport& vp) {
    const glm::dvec4& c = v.c;
    switch (plane) {
        case 0: return c.z + c.w;             // near
        case 1: return c.w - c.z;             // far
        case 2: return c.x + vp.gb_x * c.w;   // left
        case 3: return vp.gb_x * c.w - c.x;   // right
        case 4: return c.y + vp.gb_y * c.w;   // bottom
        default: return vp.gb_y * c.w - c.y;  // top
    }
}

// Sutherland-Hodgman against one plane. Intersections are always computed from the inside vertex
// towards the outside one, so the two triangles sharing an edge get the identical new vertex.
int clip_plane(const ClipVertex* in, int n, ClipVertex* out, int plane, const Viewport& vp) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
        const ClipVertex& p = in[i];
        const ClipVertex& q = in[(i + 1) % n];
        const double dp = plane_dist(p, plane, vp), dq = plane_dist(q, plane, vp);
        const bool pin = dp >= 0, qin = dq >= 0;
        if (pin) out[m++] = p;
        if (pin != qin) {
            const ClipVertex& a = pin ? p : q;  // inside
            const ClipVertex& b = pin ? q : p;  // outside
            const double da = pin ? dp : dq, db = pin ? dq : dp;
            const double s = da / (da - db);
            ClipVertex r;
            r.c = a.c + (b.c - a.c) * s;
            r.beta = a.beta + (b.beta - a.beta) * s;
            r.depth = a.depth + (b.depth - a.depth) * s;
            out[m++] = r;
        }
    }
    return m;
}

// The clip path (rare), out of line so that the fast path does not pay for its buffers.
[[gnu::noinline]] void setup_clipped(const DrawVertices& dv, std::uint32_t draw_index, std::uint32_t tri,
                                     std::uint32_t i0, std::uint32_t i1, std::uint32_t i2, std::uint32_t planes,
                                     const Viewport& vp, const SetupOptions& opt, std::vector<TriSetup>& out,
                                     std::vector<ClipVerts>& clip_out, SetupCounters& counters) {
    const bool double_sided = dv.mat->double_sided;
    TriSetup t;
    t.draw = draw_index;
    t.tri = tri;
    ClipVerts cv;
    // Clip path (rare): polygon of at most 3 + 6 vertices.
    ++counters.clipped;
    ClipVertex bufA[12], bufB[12];
    const std::uint32_t ids[3] = {i0, i1, i2};
    for (int j = 0; j < 3; ++j) {
        bufA[j].c = glm::dvec4(dv.clip[ids[j]]);
        bufA[j].beta = glm::dvec3(j == 0, j == 1, j == 2);
        bufA[j].depth = -double(dv.view[ids[j]].pos.z);
    }
    int n = 3;
    ClipVertex* cur = bufA;
    ClipVertex* nxt = bufB;
    for (int pl = 0; pl < 6 && n >= 3; ++pl) {
        if (!(planes & (1u << pl))) continue;
        n = clip_plane(cur, n, nxt, pl, vp);
        std::swap(cur, nxt);
    }
    if (n < 3) return;
    SnapVertex sv[12];
    glm::vec3 beta[12];
    for (int j = 0; j < n; ++j) {
        const glm::vec4 c(cur[j].c);
        const float depth = float(cur[j].depth);
        const bool ok = std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z) &&
                        std::isfinite(c.w) && c.w > 0.0f && std::isfinite(depth) &&
                        std::abs(double(c.x) / c.w) <= 2.0 * vp.gb_x &&
                        std::abs(double(c.y) / c.w) <= 2.0 * vp.gb_y;
        if (!ok) {
            ++counters.clip_unstable;
            return;
        }
        sv[j] = snap_vertex(c, depth, vp);
        beta[j] = glm::vec3(cur[j].beta);
    }
    for (int j = 1; j + 1 < n; ++j) {
        const SnapVertex tv[3] = {sv[0], sv[j], sv[j + 1]};
        const glm::vec3 tb[3] = {beta[0], beta[j], beta[j + 1]};
        TriSetup s = t;
        if (build(tv, tb, vp, opt, double_sided, s, cv)) {
            s.clip = std::int32_t(clip_out.size());
            clip_out.push_back(cv);
            out.push_back(s);
        }
    }
}

// The setup of one triangle (setup_triangle's definition; setup_triangles inlines it).
[[gnu::always_inline]] inline void setup_one(const DrawVertices& dv, std::uint32_t draw_index, std::uint32_t tri,
                                             const Viewport& vp, const SetupOptions& opt, std::vector<TriSetup>& out,
                                             std::vector<ClipVerts>& clip_out, SetupCounters& counters) {
    const auto& idx = dv.prim->indices;
    const std::uint32_t i0 = idx[3 * std::size_t(tri)], i1 = idx[3 * std::size_t(tri) + 1],
                        i2 = idx[3 * std::size_t(tri) + 2];
    const std::size_t nv = dv.clip.size();
    if (i0 >= nv || i1 >= nv || i2 >= nv) {
        ++counters.bad_index;
        return;
    }
    const SnapVertex& s0 = dv.snap[i0];
    const SnapVertex& s1 = dv.snap[i1];
    const SnapVertex& s2 = dv.snap[i2];
    const std::uint32_t c0 = s0.code, c1 = s1.code, c2 = s2.code;
    const bool double_sided = dv.mat->double_sided;
    if ((c0 | c1 | c2) & kOutNonFinite) {
        ++counters.non_finite;
        return;
    }
    if (c0 & c1 & c2) return;  // entirely outside one plane
    if ((c0 | c1 | c2) == 0) {
        ClipVerts unused;
        const SnapVertex sv[3] = {s0, s1, s2};
        // Quick reject of triangles whose bounds hold no pixel centre (most of a dense mesh),
        // before anything is written; build() repeats the exact computation.
        if (!bounds_hold_centre(s0, s1, s2)) return;
        // Built in place, uninitialised (build() writes every field it keeps): a stack copy
        // re-read right after its narrow stores stalls on store forwarding. Dropped on reject.
        TriSetup& t = out.emplace_back(TriSetup::NoInit{});
        t.draw = draw_index;
        t.tri = tri;
        t.clip = -1;
        if (!build(sv, nullptr, vp, opt, double_sided, t, unused)) out.pop_back();
        return;
    }
    setup_clipped(dv, draw_index, tri, i0, i1, i2, c0 | c1 | c2, vp, opt, out, clip_out, counters);
}

// A triangle the batch pre-pass must hand to setup_one: any vertex index out of range, any vertex
// outside a clip plane or non-finite (setup_one counts, clips or drops it), or bounds that hold a
// pixel centre. False only for triangles setup_one drops without a trace (the quick reject).
[[gnu::always_inline]] inline bool needs_setup(const SnapVertex* snap, std::size_t nv, const std::uint32_t* ix) {
    const bool bad = (ix[0] >= nv) | (ix[1] >= nv) | (ix[2] >= nv);
    const SnapVertex& s0 = snap[bad ? 0 : ix[0]];
    const SnapVertex& s1 = snap[bad ? 0 : ix[1]];
    const SnapVertex& s2 = snap[bad ? 0 : ix[2]];
    return bad | ((s0.code | s1.code | s2.code) != 0) | bounds_hold_centre(s0, s1, s2);
}

}  // namespace

void setup_triangle(const DrawVertices& dv, std::uint32_t draw_index, std::uint32_t tri,
                    const Viewport& vp, const SetupOptions& opt, std::vector<TriSetup>& out,
                    std::vector<ClipVerts>& clip_out, SetupCounters& counters) {
    setup_one(dv, draw_index, tri, vp, opt, out, clip_out, counters);
}

void setup_triangles(const DrawVertices& dv, std::uint32_t draw_index, std::uint32_t begin, std::uint32_t end,
                     const Viewport& vp, const SetupOptions& opt, std::vector<TriSetup>& out,
                     std::vector<ClipVerts>& clip_out, SetupCounters& counters) {
    // Two passes per batch: a branch-free pre-pass lists the triangles that need setup (on dense
    // meshes most bounds hold no pixel centre, and a per-triangle branch on that mispredicts),
    // then setup_one runs on the listed ones in order.
    const std::uint32_t* idx = dv.prim->indices.data();
    const std::size_t nv = dv.clip.size();
    const SnapVertex* snap = nv ? &dv.snap[0] : nullptr;
    std::uint32_t list[kSetupBatch];
    for (std::uint32_t b = begin; b < end;) {
        const std::uint32_t e = end - b > kSetupBatch ? b + kSetupBatch : end;
        std::uint32_t n = 0;
        if (nv == 0) {
            for (std::uint32_t t = b; t < e; ++t) list[n++] = t;
        } else {
            for (std::uint32_t t = b; t < e; ++t) {
                list[n] = t;
                n += needs_setup(snap, nv, idx + 3 * std::size_t(t)) ? 1u : 0u;
            }
        }
        for (std::uint32_t k = 0; k < n; ++k) setup_one(dv, draw_index, list[k], vp, opt, out, clip_out, counters);
        b = e;
    }
}

}  // namespace aq::raster
