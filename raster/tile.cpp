// raster/tile.cpp — the two traversals: the plain reference rasterizer (forward, per triangle) and the tiled one (one task per tile: visibility resolved first, depth test "less", then each pixel's winner shaded once, the same fragment the reference writes last).
#include "raster/raster_internal.h"

#include <immintrin.h>

namespace aq::raster::detail {

// Interpolates the vertex data of the fragment with setup weights b into `in`, every field
// written (shared by both traversals).
void interpolate(const Frame& fr, const Chunk& ch, const TriSetup& t, const Bary& b, FragmentInput& in) {
    float o[3];
    original_weights(ch, t, b, o);
    const DrawVertices& dv = fr.draws[t.draw];
    const scene::Primitive& p = *dv.prim;
    const std::uint32_t i0 = t.v[0], i1 = t.v[1], i2 = t.v[2];
    auto lerp3 = [&](const auto& a0, const auto& a1, const auto& a2) {
        return a0 + (a1 - a0) * o[1] + (a2 - a0) * o[2];
    };
    const DrawVertices::Shading& v0 = dv.view[i0];
    const DrawVertices::Shading& v1 = dv.view[i1];
    const DrawVertices::Shading& v2 = dv.view[i2];
    in.view_pos = lerp3(v0.pos, v1.pos, v2.pos);
    in.normal = lerp3(v0.normal, v1.normal, v2.normal);
    in.has_tangent = !dv.view_tangent.empty();
    in.tangent = in.has_tangent ? lerp3(dv.view_tangent[i0], dv.view_tangent[i1], dv.view_tangent[i2]) : glm::vec4(0.0f);
    in.has_uv = p.uv0.size() == p.positions.size();
    in.uv = in.has_uv ? lerp3(p.uv0[i0], p.uv0[i1], p.uv0[i2]) : glm::vec2(0.0f);
    in.uv_grad = {};
    if (in.has_uv) {  // d uv / d x, d uv / d y for the textures' level of detail
        Bary bx, by;
        bary_derivatives(t, b, bx, by);
        float ox[3], oy[3];
        original_weights(ch, t, bx, ox);
        original_weights(ch, t, by, oy);
        const glm::vec2 e1 = p.uv0[i1] - p.uv0[i0], e2 = p.uv0[i2] - p.uv0[i0];
        in.uv_grad.dx = e1 * ox[1] + e2 * ox[2];
        in.uv_grad.dy = e1 * oy[1] + e2 * oy[2];
    }
    in.color = p.colors.size() == p.positions.size() ? lerp3(p.colors[i0], p.colors[i1], p.colors[i2]) : glm::vec4(1.0f);
    for (int k = 0; k < scene::kNumControlTargets; ++k) {
        const auto& c = p.control[k];
        in.ctrl[k] = c.size() == p.positions.size() ? lerp3(glm::vec3(c[i0]), glm::vec3(c[i1]), glm::vec3(c[i2]))
                                                    : glm::vec3(0.0f);
    }
    in.back = t.back();
    in.base = dv.const_base ? &dv.base : nullptr;
}

FragmentInput interpolate(const Frame& fr, const Chunk& ch, const TriSetup& t, const Bary& b) {
    FragmentInput in;
    interpolate(fr, ch, t, b, in);
    return in;
}

bool alpha_pass(const Frame& fr, const Chunk& ch, const TriSetup& t, const Bary& b) {
    const scene::Material& m = *fr.draws[t.draw].mat;
    return material_alpha(fr.ctx, m, interpolate(fr, ch, t, b)) >= m.alpha_cutoff;
}

// Writes lane i of shaded fragments (depth, object id) at pixel (x, y) of every target.
void write_lane(const FragmentLanes& o, int i, float depth, float object_id, const TargetPtrs& tp, int x, int y) {
    const std::size_t p = std::size_t(y) * tp.width + x;
    float* c = tp.color() + 4 * p;
    c[0] = o.color[0][i]; c[1] = o.color[1][i]; c[2] = o.color[2][i]; c[3] = 1.0f;
    for (int k = 0; k < scene::kNumControlTargets; ++k) {
        float* q = tp.ctrl(k) + 4 * p;
        q[0] = o.ctrl[k][0][i]; q[1] = o.ctrl[k][1][i]; q[2] = o.ctrl[k][2][i]; q[3] = 1.0f;
    }
    tp.depth()[p] = depth;
    float* n = tp.normal() + 3 * p;
    n[0] = o.normal[0][i]; n[1] = o.normal[1][i]; n[2] = o.normal[2][i];
    tp.id()[p] = object_id;
    tp.diffuse()[p] = o.diffuse[i];
    tp.specular()[p] = o.specular[i];
}

void shade_and_write(const Frame& fr, const Chunk& ch, const TriSetup& t, const Bary& b,
                     const TargetPtrs& tp, int x, int y) {
    const DrawVertices& dv = fr.draws[t.draw];
    FragmentLanes o;
    o.set(0, shade_fragment(fr.ctx, *dv.mat, interpolate(fr, ch, t, b)));
    write_lane(o, 0, b.depth, float(dv.object_id), tp, x, y);
}

// ---- Reference traversal: per triangle in submission order, bounding box, whole image --------

void raster_reference(const Frame& fr, const TargetPtrs& tp, int W, int H, float* count) {
    std::vector<float> zbuf(count ? 0 : std::size_t(W) * H, std::numeric_limits<float>::infinity());
    for_each_reference_fragment(fr, [&](const Chunk& ch, const TriSetup& t, int x, int y, const std::int64_t* e) {
        if (count) {
            count[std::size_t(y) * W + x] += 1.0f;
            return;
        }
        const Bary b = perspective_bary(t, e);
        float& z = zbuf[std::size_t(y) * W + x];
        if (!(b.depth < z)) return;
        if (needs_alpha_test(fr, t) && !alpha_pass(fr, ch, t, b)) return;
        z = b.depth;
        shade_and_write(fr, ch, t, b, tp, x, y);
    });
}

// ---- Tiled traversal: one task per tile, visibility then deferred shading ---------------------

// Prefetch hints for the shading gathers of a triangle (no effect on results).
inline void prefetch_vertices(const Frame& fr, const TriSetup& t) {
    const DrawVertices& dv = fr.draws[t.draw];
    for (int j = 0; j < 3; ++j) __builtin_prefetch(&dv.view[t.v[j]]);  // indices checked in setup
}


// Up to eight fragments of one material waiting to be shaded together, then written to a row.
struct Batch {
    const scene::Material* mat = nullptr;
    FragmentInput in[FragmentLanes::kLanes];
    int x[FragmentLanes::kLanes];
    float depth[FragmentLanes::kLanes], id[FragmentLanes::kLanes];
    int n = 0;
    void flush(const Frame& fr, const TargetPtrs& row) {
        if (n == 0) return;
        FragmentLanes o;
        shade_fragments(fr.ctx, *mat, in, n, o);
        for (int i = 0; i < n; ++i) write_lane(o, i, depth[i], id[i], row, x[i], 0);
        n = 0;
    }
};

// One tile row of every G-buffer target (kTile pixels, the layout's order), written by write_lane
// at (x, 0).
struct RowBuffer {
    //! Where target i's row starts in `values`.
    static constexpr std::array<std::size_t, gbuffer_slot::kCount + 1> kOffsets = [] {
        std::array<std::size_t, gbuffer_slot::kCount + 1> o{};
        for (std::size_t i = 0; i < gbuffer_slot::kCount; ++i)
            o[i + 1] = o[i] + std::size_t(target::kGBufferLayout[i].channels) * kTile;
        return o;
    }();
    float values[kOffsets.back()];
    TargetPtrs pointers() {
        TargetPtrs p;
        for (std::size_t t = 0; t < gbuffer_slot::kCount; ++t) p.at[t] = values + kOffsets[t];
        p.width = kTile;
        return p;
    }
    void background(int n, float bg_depth) {  // the values write_background stores
        for (std::size_t t = 0; t < gbuffer_slot::kCount; ++t) {
            const target::GBufferTarget& g = target::kGBufferLayout[t];
            std::fill_n(values + kOffsets[t], std::size_t(g.channels) * std::size_t(n), g.far_background ? bg_depth : 0.0f);
        }
    }
    void stream_row(const TargetPtrs& tp, int x0, int y, int n) const {
        const std::size_t i = std::size_t(y) * tp.width + x0;
        // Targets the caller did not ask for are null (RenderSettings::targets): not written.
        for (std::size_t t = 0; t < gbuffer_slot::kCount; ++t) {
            const std::size_t m = std::size_t(target::kGBufferLayout[t].channels);
            if (tp.at[t]) stream_copy(tp.at[t] + m * i, values + kOffsets[t], m * std::size_t(n));
        }
    }
};

void write_background(const TargetPtrs& tp, std::size_t i, float bg_depth) {
    for (std::size_t t = 0; t < gbuffer_slot::kCount; ++t) {
        const target::GBufferTarget& g = target::kGBufferLayout[t];
        const std::size_t m = std::size_t(g.channels);
        std::fill_n(tp.at[t] + m * i, m, g.far_background ? bg_depth : 0.0f);
    }
}

// Prefetch hints for every cache line of a setup record (no effect on results): 104 bytes at a
// 104-byte stride span three lines in half the records, and then the bounds and flags that the
// tile pass reads first are in the third.
inline void prefetch_setup(const TriSetup& t) {
    const char* a = reinterpret_cast<const char*>(&t);
    __builtin_prefetch(a);
    __builtin_prefetch(a + 64);
    __builtin_prefetch(a + sizeof(TriSetup) - 1);
}

void resolve_tile(const Frame& fr, int tile, int X0, int Y0, int X1, int Y1, float* zbuf, TileRef* ids) {
    for (std::uint32_t ci = 0; ci < fr.chunks.size(); ++ci) {
        const Chunk& ch = fr.chunks[ci];
        for (std::uint32_t k = ch.bin_offsets[tile]; k < ch.bin_offsets[tile + 1]; ++k) {
            const std::uint32_t ti = ch.bin_items[k];
            // The setups of one tile are scattered over the chunk: fetch ahead (latency-bound).
            if (k + 6 < ch.bin_offsets[tile + 1]) {
                prefetch_setup(ch.tris[ch.bin_items[k + 6]]);
            }
            const TriSetup& t = ch.tris[ti];
            const int x0 = std::max<int>(t.x0, X0), x1 = std::min<int>(t.x1, X1);
            const int y0 = std::max<int>(t.y0, Y0), y1 = std::min<int>(t.y1, Y1);
            if (!needs_alpha_test(fr, t)) {
                depth_test_triangle(t, X0, Y0, kTile, x0, x1, y0, y1, zbuf, ids, {ci, ti});
                continue;
            }
            // Alpha-masked: the material's alpha per pixel, after the depth test (as the reference).
            for_each_inside(t, x0, x1, y0, y1, [&](int x, int y, const std::int64_t* e) {
                const int li = (y - Y0) * kTile + (x - X0);
                const Bary b = perspective_bary(t, e);
                if (b.depth < zbuf[li] && alpha_pass(fr, ch, t, b)) {
                    zbuf[li] = b.depth;
                    ids[li] = {ci, ti};
                }
            });
        }
    }
}

// clear: background pixels are written too (fresh or reused targets); otherwise the targets
// already hold the background there (raster.cpp: a tile that showed only background in the
// previous frame written into the same stamped targets).
void raster_tile(const Frame& fr, const TargetPtrs& tp, int tile, TileRect tr, float* count, bool clear,
                 CoverageBits* cov) {
    const int W = fr.grid.width;
    const int X0 = tr.x0, Y0 = tr.y0, X1 = tr.x1, Y1 = tr.y1;
    const int tw = X1 - X0 + 1;
    if (count) {  // overdraw: every covered sample of every triangle, no depth test
        for (const Chunk& ch : fr.chunks)
            for (std::uint32_t k = ch.bin_offsets[tile]; k < ch.bin_offsets[tile + 1]; ++k) {
                const TriSetup& t = ch.tris[ch.bin_items[k]];
                for_each_inside(t, std::max<int>(t.x0, X0), std::min<int>(t.x1, X1), std::max<int>(t.y0, Y0), std::min<int>(t.y1, Y1),
                                [&](int x, int y, const std::int64_t*) { count[std::size_t(y) * W + x] += 1.0f; });
            }
        return;
    }
    // Visibility, then the covered pixels in row-major order. A tile no triangle was binned to
    // shows only background: no depth buffer, no visibility, no coverage scan (most tiles of a
    // model that does not fill the frame).
    float zbuf[kTile * kTile];
    TileRef ids[kTile * kTile];
    std::uint16_t covered[kTile * kTile];
    int nc = 0;
    if (tile_binned(fr, tile)) {
        for (int i = 0; i < kTile * kTile; ++i) {
            zbuf[i] = std::numeric_limits<float>::infinity();
            ids[i].chunk = kNoChunk;
        }
        resolve_tile(fr, tile, X0, Y0, X1, Y1, zbuf, ids);
        // Branch-free append (the coverage edges made the branch mispredict: a third of this
        // function's time); the same list in the same order.
        for (int li = 0; li < kTile * kTile; ++li) {
            covered[nc] = std::uint16_t(li);
            nc += ids[li].chunk != kNoChunk;
        }
        if (cov)
            for (int k = 0; k < nc; ++k)
                cov->word(X0 / kTile, Y0 + covered[k] / kTile) |= std::uint64_t(1) << (covered[k] % kTile);
    }
    // Deferred shading of the covered pixels. Each pixel gathers its setup, then the vertices its
    // setup names (dependent cache misses: one small triangle per pixel on dense meshes), so those
    // are prefetched 12 and 6 pixels ahead (schedule only).
    auto setup_at = [&](int k) -> const TriSetup& {
        const TileRef r = ids[covered[k]];
        return fr.chunks[r.chunk].tris[r.tri];
    };
    // Each row is composed in a small buffer (background, then its shaded pixels) and streamed
    // to the targets: every byte of the 108 B/px G-buffer is written once, with non-temporal
    // stores (no read-for-ownership of lines that are overwritten whole). Without `clear` the
    // targets already hold the background and rows with no covered pixel are skipped.
    // A row without covered pixels is streamed from a background row filled once per tile.
    RowBuffer rb, bg;
    const TargetPtrs rp = rb.pointers();
    bool bg_filled = false;
    int k = 0;
    for (int y = Y0; y <= Y1; ++y) {
        const int ly = y - Y0;
        const bool any = k < nc && covered[k] / kTile == ly;
        if (!any) {
            if (!clear) continue;
            if (!bg_filled) bg.background(tw, fr.background_depth), bg_filled = true;
            bg.stream_row(tp, X0, y, tw);
            continue;
        }
        rb.background(tw, fr.background_depth);
        // The row's fragments are shaded eight at a time (shade_fragments: the bits of
        // shade_fragment), a batch holding consecutive pixels of one material.
        Batch bt;
        for (; k < nc && covered[k] / kTile == ly; ++k) {
            if (k + 12 < nc) prefetch_setup(setup_at(k + 12));
            if (k + 6 < nc) prefetch_vertices(fr, setup_at(k + 6));
            const int lx = covered[k] % kTile;
            const TileRef r = ids[covered[k]];
            const Chunk& ch = fr.chunks[r.chunk];
            const TriSetup& t = ch.tris[r.tri];
            std::int64_t e[3];
            edge_values(t, X0 + lx, y, e);
            const Bary b = perspective_bary(t, e);
            const DrawVertices& dv = fr.draws[t.draw];
            if (bt.n == FragmentLanes::kLanes || (bt.n > 0 && dv.mat != bt.mat)) bt.flush(fr, rp);
            bt.mat = dv.mat;
            interpolate(fr, ch, t, b, bt.in[bt.n]);
            bt.x[bt.n] = lx;
            bt.depth[bt.n] = b.depth;
            bt.id[bt.n] = float(dv.object_id);
            ++bt.n;
        }
        bt.flush(fr, rp);
        rb.stream_row(tp, X0, y, tw);
    }
    stream_fence();  // order the non-temporal stores before the task completes
}

}  // namespace aq::raster::detail
