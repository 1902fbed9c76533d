// raster/setup.h — clipping and fixed-point triangle setup, shared by the tiled and reference
// rasterizers (docs/raster.md "Setup", "Fill rule", "Clipping").
//
// Screen space is y-down with pixel centres at integer + 0.5; positions are snapped to 1/256 px.
// Edge function of edge a->b at sample p: E = (b.x-a.x)(p.y-a.y) - (b.y-a.y)(p.x-a.x), evaluated
// exactly in int64 as A*p.x + B*p.y + C. Triangles are re-ordered so that the area is positive;
// a sample is inside when every E_i >= bias_i, bias 0 for top/left edges and 1 otherwise
// (top-left rule: a top edge is horizontal with the interior below, a left edge goes up).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "raster/vertex.h"

namespace aq::raster {

//! One rasterizable triangle after clipping, culling and snapping: 104 bytes (the tile pass reads
//! one per binned triangle and per shaded pixel; a dense mesh sets up hundreds of thousands).
struct TriSetup {
    std::int64_t C[3];         //!< E_i at fixed-point sample (0, 0)
    std::int32_t A[3], B[3];   //!< edge steps: E_i(x+1) = E_i + A_i*256 (fixed-point sample)
    float inv_w[3];            //!< 1/w of setup vertex j (edge i is opposite vertex i)
    float depth[3];            //!< linear eye depth of setup vertex j
    std::uint32_t draw;        //!< index into the frame's draws
    //! The vertex indices of the primitive's triangle, in its index buffer's order (the shading's
    //! gathers start here instead of at the index buffer: one dependent load less per pixel).
    std::uint32_t v[3];
    std::int32_t clip;         //!< -1: setup vertex j is original vertex perm(j); else index into the clip table
    std::int16_t x0, y0, x1, y1;  //!< inclusive pixel bounds, clamped to the raster (< kMaxImageSide)
    //! Bits 0-2: the bias of edge i (0 top-left edge, 1 otherwise); kPermBit: vertices 1 and 2
    //! swapped; kBackBit: the triangle faces away (CW in NDC); kSubpixelBit: it holds no pixel
    //! centre (kept for the coverage pass only, SetupOptions::keep_subpixel; its bounds may be
    //! empty by one pixel).
    std::uint8_t flags;
    //! Which sides of the pixels whose coverage samples (±3/8 px from a centre) the triangle may
    //! reach lie one pixel inside the bounds widened by one, before clamping (bit 0: x0, 1: x1,
    //! 2: y0, 3: y1): coverage_bounds() (the coverage pass's binning and scan).
    std::uint8_t cover;
    static constexpr std::uint8_t kPermBit = 1u << 3, kBackBit = 1u << 4, kSubpixelBit = 1u << 5;
    bool subpixel() const { return (flags & kSubpixelBit) != 0; }
    int bias(int i) const { return (flags >> i) & 1; }
    bool perm() const { return (flags & kPermBit) != 0; }
    bool back() const { return (flags & kBackBit) != 0; }
    // No default member initializers: trivially constructible, setup writes every field.
    struct NoInit {};
    TriSetup() = default;
    explicit TriSetup(NoInit) {}  //!< for emplace_back without the zeroing of value-initialisation
};
static_assert(sizeof(TriSetup) == 104);

//! How far the coverage pass's outermost samples lie from a pixel centre per axis: 3/8 px (the 4x4
//! grid of ssaa 4, offsets (2i + 1) / 8 - 1/2 px), in fixed-point units.
inline constexpr int kCoverageReach = 3 * kSubpixelOne / 8;
//! TriSetup::cover of a triangle whose snapped vertices span [xmin, xmax] x [ymin, ymax]: a side's
//! bit is set where the samples' pixel bound (ceil / floor of the extent less the reach) equals the
//! pixel-centre bound (that of extent less half a pixel), i.e. one pixel inside the widened bound.
template <class I>
inline I cover_bits(I xmin, I xmax, I ymin, I ymax) {
    constexpr int h = kSubpixelOne / 2, lo = h + kCoverageReach - (kSubpixelOne - 1), hi = h - kCoverageReach;
    auto low = [](I v) { return I(((v - lo) >> kSubpixelBits) == ((v + h - 1) >> kSubpixelBits)); };
    auto high = [](I v) { return I(((v - hi) >> kSubpixelBits) == ((v - h) >> kSubpixelBits)); };
    return I(low(xmin) | high(xmax) << 1 | low(ymin) << 2 | high(ymax) << 3);
}

//! The pixels in which t may cover one of the coverage pass's samples (±kCoverageReach from a pixel
//! centre; the triangle's fixed-point extent meets that span), clamped to W x H: t's pixel-centre
//! bounds widened by one pixel, less TriSetup::cover's sides. Empty when x0 > x1 or y0 > y1.
struct PixelRect {
    int x0, y0, x1, y1;
};
inline PixelRect coverage_bounds(int x0, int y0, int x1, int y1, unsigned cover, int W, int H) {
    return {std::max(x0 - 1 + int(cover & 1), 0), std::max(y0 - 1 + int((cover >> 2) & 1), 0),
            std::min(x1 + 1 - int((cover >> 1) & 1), W - 1), std::min(y1 + 1 - int((cover >> 3) & 1), H - 1)};
}
inline PixelRect coverage_bounds(const TriSetup& t, int W, int H) {
    return coverage_bounds(t.x0, t.y0, t.x1, t.y1, t.cover, W, H);
}

//! A sub-pixel triangle of an opaque material, as the coverage pass needs it (the batch setup's
//! record for it with SetupOptions::keep_subpixel, instead of a 104-byte TriSetup that no traversal
//! reads): its snapped vertices in setup order (positive area) and its coverage_bounds.
struct SubpixelTri {
    std::int32_t X[3], Y[3];
    std::int16_t x0, y0, x1, y1;
};
static_assert(sizeof(SubpixelTri) == 32);

//! The edge functions and top-left biases of a triangle whose setup vertices (positive area) are
//! X, Y: edge i runs from vertex (i + 1) % 3 to vertex (i + 2) % 3, opposite vertex i.
//! Writes t.flags: the three biases, no other bit.
[[gnu::always_inline]] inline void set_edges(const std::int64_t (&X)[3], const std::int64_t (&Y)[3], TriSetup& t) {
    std::uint8_t flags = 0;
    for (int i = 0; i < 3; ++i) {
        const int a = (i + 1) % 3, b = (i + 2) % 3;
        const std::int64_t dx = X[b] - X[a], dy = Y[b] - Y[a];
        t.A[i] = std::int32_t(-dy);
        t.B[i] = std::int32_t(dx);
        t.C[i] = dy * X[a] - dx * Y[a];
        const bool top_left = (dy == 0 && dx > 0) || dy < 0;
        flags |= std::uint8_t((top_left ? 0u : 1u) << i);
    }
    t.flags = flags;
}

//! For clipped triangles: the original-triangle barycentric weights of each setup vertex.
struct ClipVerts {
    glm::vec3 beta[3];
};

//! Edge function values at pixel (px, py), exact.
inline void edge_values(const TriSetup& t, int px, int py, std::int64_t e[3]) {
    const std::int64_t sx = std::int64_t(px) * kSubpixelOne + kSubpixelOne / 2;
    const std::int64_t sy = std::int64_t(py) * kSubpixelOne + kSubpixelOne / 2;
    for (int i = 0; i < 3; ++i) e[i] = std::int64_t(t.A[i]) * sx + std::int64_t(t.B[i]) * sy + t.C[i];
}

inline bool inside(const TriSetup& t, const std::int64_t e[3]) {
    return e[0] >= t.bias(0) && e[1] >= t.bias(1) && e[2] >= t.bias(2);
}

//! Calls f(x, y, e) for every pixel of [x0, x1] x [y0, y1] whose centre is inside t, row by row,
//! with its exact edge values (stepped in integers from edge_values at (x0, y0): the same values).
template <class F>
inline void for_each_inside(const TriSetup& t, int x0, int x1, int y0, int y1, F&& f) {
    if (x0 > x1 || y0 > y1) return;
    std::int64_t row[3];
    edge_values(t, x0, y0, row);
    const std::int64_t sx[3] = {std::int64_t(t.A[0]) * kSubpixelOne, std::int64_t(t.A[1]) * kSubpixelOne,
                                std::int64_t(t.A[2]) * kSubpixelOne};
    const std::int64_t sy[3] = {std::int64_t(t.B[0]) * kSubpixelOne, std::int64_t(t.B[1]) * kSubpixelOne,
                                std::int64_t(t.B[2]) * kSubpixelOne};
    for (int y = y0; y <= y1; ++y) {
        std::int64_t e[3] = {row[0], row[1], row[2]};
        for (int x = x0; x <= x1; ++x) {
            if (inside(t, e)) f(x, y, static_cast<const std::int64_t*>(e));
            e[0] += sx[0], e[1] += sx[1], e[2] += sx[2];
        }
        row[0] += sy[0], row[1] += sy[1], row[2] += sy[2];
    }
}

//! Perspective-correct weights of the setup vertices and the interpolated linear depth.
//! The one floating-point path from exact edge values to a fragment; both traversals call it.
struct Bary {
    float b[3];
    float depth;
    float r;  //!< 1 / sum of e_i / w_i (the weights' normaliser; derivatives: bary_derivatives)
};
inline Bary perspective_bary(const TriSetup& t, const std::int64_t e[3]) {
    const float q0 = float(e[0]) * t.inv_w[0];
    const float q1 = float(e[1]) * t.inv_w[1];
    const float q2 = float(e[2]) * t.inv_w[2];
    const float r = 1.0f / ((q0 + q1) + q2);
    Bary b;
    b.b[0] = q0 * r;
    b.b[1] = q1 * r;
    b.b[2] = q2 * r;
    b.depth = t.depth[0] + b.b[1] * (t.depth[1] - t.depth[0]) + b.b[2] * (t.depth[2] - t.depth[0]);
    b.r = r;
    return b;
}

//! The derivatives of perspective_bary's weights per pixel step in x and y, analytic: with
//! q_i = e_i / w_i (affine in the pixel position, steps a_i = A_i * kSubpixelOne / w_i) and
//! b_i = q_i / S, d b_i = (a_i - b_i * sum a) / S. Only the depth-free weights are set.
inline void bary_derivatives(const TriSetup& t, const Bary& b, Bary& dx, Bary& dy) {
    constexpr float k = float(kSubpixelOne);
    float ax[3], ay[3];
    for (int i = 0; i < 3; ++i) {
        ax[i] = float(t.A[i]) * k * t.inv_w[i];
        ay[i] = float(t.B[i]) * k * t.inv_w[i];
    }
    const float sx = (ax[0] + ax[1]) + ax[2], sy = (ay[0] + ay[1]) + ay[2];
    for (int i = 0; i < 3; ++i) {
        dx.b[i] = (ax[i] - b.b[i] * sx) * b.r;
        dy.b[i] = (ay[i] - b.b[i] * sy) * b.r;
    }
    dx.depth = dy.depth = 0.0f;
    dx.r = dy.r = 0.0f;
}

struct SetupCounters {
    std::uint64_t non_finite = 0;    //!< dropped: a vertex position was NaN/Inf after transform
    std::uint64_t bad_index = 0;     //!< dropped: index out of range
    std::uint64_t clip_unstable = 0; //!< dropped: clipping produced a non-finite vertex
    std::uint64_t clipped = 0;       //!< triangles that went through the clipper
    void add(const SetupCounters& o) {
        non_finite += o.non_finite; bad_index += o.bad_index;
        clip_unstable += o.clip_unstable; clipped += o.clipped;
    }
};

struct SetupOptions {
    bool cull_backfaces = false;
    //! Keep the triangles that hold no pixel centre but whose bounds reach within a pixel of one
    //! (marked TriSetup::kSubpixelBit): the coverage pass needs their samples (docs/raster.md
    //! "Coverage antialiasing"); the traversals skip them. Else they are dropped.
    bool keep_subpixel = false;
};

//! Sets up triangle `tri` of draw `draw_index`, appending 0..n TriSetups (a clipped polygon is a
//! fan, in order) to `out` and their clip tables to `clip_out` (TriSetup::clip indexes it).
void setup_triangle(const DrawVertices& dv, std::uint32_t draw_index, std::uint32_t tri,
                    const Viewport& vp, const SetupOptions& opt, std::vector<TriSetup>& out,
                    std::vector<ClipVerts>& clip_out, SetupCounters& counters);

//! Triangles [begin, end) of the batch pre-pass (schedule only): appends exactly what
//! setup_triangle for tri = begin, ..., end - 1 in order appends, and counts the same.
inline constexpr std::uint32_t kSetupBatch = 256;
//! `subpixel_out`, when given (with keep_subpixel, for a draw whose material is not alpha-masked),
//! receives the sub-pixel triangles the batch path sets up as SubpixelTri instead of TriSetup
//! (those of setup_triangle's path, clipped or large, stay TriSetups with kSubpixelBit).
void setup_triangles(const DrawVertices& dv, std::uint32_t draw_index, std::uint32_t begin, std::uint32_t end,
                     const Viewport& vp, const SetupOptions& opt, std::vector<TriSetup>& out,
                     std::vector<ClipVerts>& clip_out, SetupCounters& counters,
                     std::vector<SubpixelTri>* subpixel_out = nullptr);

}  // namespace aq::raster
