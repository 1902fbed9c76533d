// raster/raster.cpp — render_gbuffer: vertex stage -> setup/binning -> per-tile visibility and
// deferred watercolor shading (fast, oneTBB) or the plain reference rasterizer -> SSAA resolve.
//
// Determinism (docs/raster.md): every per-vertex, per-triangle and per-fragment result is a pure
// function of its inputs; the fast path only changes the schedule. Setups are produced per chunk
// of consecutive triangles and bins list them per chunk, so a tile visits triangles in submission
// order; each tile has exactly one writer. The tiled path resolves visibility first (depth test
// "less": the earliest-submitted nearest fragment wins) and shades each pixel's winner once, which
// is the same fragment the reference's forward loop writes last.
#include "raster/raster.h"

#include <cmath>
#include <limits>
#include <iterator>
#include <numeric>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>

#include <immintrin.h>
#include <mutex>

#include <tbb/parallel_for.h>

#include "raster/material.h"
#include "raster/setup.h"
#include "raster/vertex.h"

namespace aq::raster {

namespace {

constexpr std::uint32_t kChunkTris = 32768;  // triangles per setup chunk (schedule only)
constexpr std::size_t kVertexGrain = 4096;
constexpr int kTile = 64;                   // tile side in pixels (binning and raster)
constexpr std::uint32_t kNoChunk = 0xffffffffu;

// AQ_RASTER_PROFILE=1 prints per-phase wall times to stderr (profiling aid, docs/performance.md).
struct PhaseTimer {
    bool on = std::getenv("AQ_RASTER_PROFILE") != nullptr;
    std::chrono::steady_clock::time_point t = std::chrono::steady_clock::now();
    double cpu = cpu_ms();
    static double cpu_ms() {
        timespec ts;
        clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
        return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
    }
    void lap(const char* what) {
        if (!on) return;
        const auto n = std::chrono::steady_clock::now();
        const double c = cpu_ms();
        std::fprintf(stderr, "  raster %-10s wall %8.2f ms  cpu %8.2f ms\n", what,
                     std::chrono::duration<double, std::milli>(n - t).count(), c - cpu);
        t = n;
        cpu = c;
    }
};

struct Chunk {
    //! Consecutive triangles of the submission sequence, possibly spanning several draws (so the
    //! number of chunks, and of per-chunk bin tables, is bounded by triangles / kChunkTris + 1
    //! however many small draws the scene has).
    struct Segment {
        std::uint32_t draw, begin, end;
    };
    std::vector<Segment> segments;
    std::uint32_t size = 0;
    std::vector<TriSetup> tris;
    std::vector<ClipVerts> clips;
    std::vector<std::uint32_t> bin_offsets;  // per tile, CSR into bin_items (fast path only)
    std::vector<std::uint32_t> bin_items;
    SetupCounters counters;
};

struct TargetPtrs {
    float* color;
    float* ctrl[scene::kNumControlTargets];
    float* depth;
    float* normal;
    float* id;
    float* diffuse;
    float* specular;
    int width;
};

struct Frame {
    FrameParams fp;
    SetupOptions sopt;
    ShadeContext ctx;
    std::vector<DrawVertices> draws;
    std::vector<Chunk> chunks;
    int tiles_x = 0, tiles_y = 0;
    float background_depth = 0;
};

const scene::Material& default_material() {
    static const scene::Material m;
    return m;
}

void validate(const scene::Camera& cam, const RenderSettings& s) {
    if (s.ssaa < 1 || s.ssaa > 4)
        throw Error("render: ssaa " + std::to_string(s.ssaa) + " is not in [1, 4]");
    check_image_size(s.width, s.height, "render");
    check_image_size(s.width * s.ssaa, s.height * s.ssaa, "render (supersampled)");
    if (!(std::isfinite(s.fps) && s.fps > 0.0f)) throw Error("render: fps must be finite and > 0");
    if (!(std::isfinite(cam.znear) && std::isfinite(cam.zfar) && cam.zfar > cam.znear))
        throw Error("camera '" + cam.name + "': needs finite znear < zfar");
    if (cam.orthographic) {
        if (!(std::isfinite(cam.xmag) && std::isfinite(cam.ymag) && cam.xmag != 0.0f && cam.ymag != 0.0f))
            throw Error("camera '" + cam.name + "': orthographic xmag/ymag must be finite and non-zero");
    } else {
        if (!(cam.znear > 0.0f)) throw Error("camera '" + cam.name + "': perspective znear must be > 0");
        if (!(cam.yfov > 0.0f && cam.yfov < 3.14159f))
            throw Error("camera '" + cam.name + "': yfov must be in (0, pi)");
        if (cam.aspect && !(std::isfinite(*cam.aspect) && *cam.aspect > 0.0f))
            throw Error("camera '" + cam.name + "': aspect ratio must be finite and > 0");
    }
    const TremorParams& t = s.tremor;
    if (!(std::isfinite(t.tremor_px) && std::isfinite(t.front) && std::isfinite(t.speed) &&
          std::isfinite(t.frequency)))
        throw Error("render: tremor parameters must be finite");
    if (!(std::isfinite(s.substrate_color.x) && std::isfinite(s.substrate_color.y) &&
          std::isfinite(s.substrate_color.z)))
        throw Error("render: substrate colour must be finite");
}

template <class F>
void run_for(bool parallel, std::size_t n, F&& f) {
    if (!parallel) {
        for (std::size_t i = 0; i < n; ++i) f(i);
        return;
    }
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) { f(i); });
}

// Vertex stage and chunked setup (+ binning on the fast path).
void prepare(Frame& fr, const scene::Scene& sc, const scene::Camera& cam, bool parallel, bool bin,
             std::vector<std::string>* warnings, PhaseTimer& timer) {
    const glm::mat4 view = cam.view;
    std::size_t bad_material = 0, bad_mesh = 0, missing_tangents = 0;
    // fr.draws / fr.chunks may hold the previous frame's scratch (FrameScratch): their buffers
    // are reused (every element is rewritten before it is read), only the objects are reset.
    std::vector<DrawVertices> old_draws = std::move(fr.draws);
    std::vector<Chunk> old_chunks = std::move(fr.chunks);
    fr.draws.clear();
    fr.chunks.clear();
    std::size_t next_draw = 0, next_chunk = 0;
    for (const scene::Instance& inst : sc.instances) {
        if (inst.mesh < 0 || inst.mesh >= int(sc.meshes.size())) {
            ++bad_mesh;
            continue;
        }
        for (const scene::Primitive& p : sc.meshes[inst.mesh].primitives) {
            if (p.positions.empty() || p.indices.size() < 3) continue;
            DrawVertices dv = next_draw < old_draws.size() ? std::move(old_draws[next_draw++]) : DrawVertices{};
            dv.prim = &p;
            if (p.material >= 0 && p.material < int(sc.materials.size())) {
                dv.mat = &sc.materials[p.material];
            } else {
                dv.mat = &default_material();
                ++bad_material;
            }
            dv.object_id = inst.object_id;
            const std::size_t n = p.positions.size();
            dv.clip.resize(n);
            dv.view.resize(n);
            dv.snap.resize(n);
            dv.view_tangent.clear();
            if (p.tangents.size() == n) dv.view_tangent.resize(n);
            else if (dv.mat->normal_texture.texture >= 0) ++missing_tangents;
            fr.draws.push_back(std::move(dv));
        }
    }
    if (bad_mesh) warnings->push_back(std::to_string(bad_mesh) + " instance(s) reference a missing mesh: skipped");
    if (bad_material)
        warnings->push_back(std::to_string(bad_material) + " primitive(s) reference a missing material: default material used");
    if (missing_tangents)
        warnings->push_back(std::to_string(missing_tangents) + " primitive(s) with a normal map have no tangents: normal map ignored");

    // Per-draw matrices (float, computed once; docs/raster.md).
    struct Job { std::uint32_t draw; std::size_t begin, end; };
    std::vector<Job> jobs;
    std::vector<glm::mat4> mv(fr.draws.size());
    std::vector<glm::mat3> nm(fr.draws.size());
    {
        std::size_t d = 0;
        for (const scene::Instance& inst : sc.instances) {
            if (inst.mesh < 0 || inst.mesh >= int(sc.meshes.size())) continue;
            for (const scene::Primitive& p : sc.meshes[inst.mesh].primitives) {
                if (p.positions.empty() || p.indices.size() < 3) continue;
                mv[d] = view * inst.world;
                nm[d] = glm::transpose(glm::inverse(glm::mat3(mv[d])));
                for (std::size_t b = 0; b < p.positions.size(); b += kVertexGrain)
                    jobs.push_back({std::uint32_t(d), b, std::min(p.positions.size(), b + kVertexGrain)});
                ++d;
            }
        }
    }
    run_for(parallel, jobs.size(), [&](std::size_t j) {
        const Job& jb = jobs[j];
        transform_vertices(fr.fp, mv[jb.draw], nm[jb.draw], fr.draws[jb.draw], jb.begin, jb.end);
    });
    timer.lap("vertex");

    for (std::uint32_t d = 0; d < fr.draws.size(); ++d) {
        const std::uint32_t ntri = std::uint32_t(fr.draws[d].prim->indices.size() / 3);
        for (std::uint32_t b = 0; b < ntri;) {
            if (fr.chunks.empty() || fr.chunks.back().size == kChunkTris) {
                if (next_chunk < old_chunks.size()) {
                    Chunk& r = fr.chunks.emplace_back(std::move(old_chunks[next_chunk++]));
                    r.segments.clear();
                    r.size = 0;
                    r.tris.clear();
                    r.clips.clear();
                    r.bin_offsets.clear();
                    r.bin_items.clear();
                    r.counters = SetupCounters{};
                } else {
                    fr.chunks.emplace_back();
                }
            }
            Chunk& c = fr.chunks.back();
            const std::uint32_t e = std::min(ntri, b + (kChunkTris - c.size));
            c.segments.push_back({d, b, e});
            c.size += e - b;
            b = e;
        }
    }
    const int ntiles = fr.tiles_x * fr.tiles_y;
    run_for(parallel, fr.chunks.size(), [&](std::size_t ci) {
        Chunk& c = fr.chunks[ci];
        c.tris.reserve(c.size);
        if (!bin) {
            for (const Chunk::Segment& sg : c.segments)
                for (std::uint32_t t = sg.begin; t < sg.end; ++t)
                    setup_triangle(fr.draws[sg.draw], sg.draw, t, fr.fp.vp, fr.sopt, c.tris, c.clips, c.counters);
            return;
        }
        // Setup and binning in one pass: (tile, setup index) pairs, then a counting sort by tile
        // (stable, so each tile's list stays in submission order). The 120-byte setups are
        // written once and not re-read here.
        std::vector<std::uint64_t> pairs;
        pairs.reserve(c.size);
        c.bin_offsets.assign(std::size_t(ntiles) + 1, 0);
        for (const Chunk::Segment& sg : c.segments) {
            const DrawVertices& dv = fr.draws[sg.draw];
            for (std::uint32_t t = sg.begin; t < sg.end; ++t) {
                std::size_t k = c.tris.size();
                setup_triangle(dv, sg.draw, t, fr.fp.vp, fr.sopt, c.tris, c.clips, c.counters);
                for (; k < c.tris.size(); ++k) {
                    const TriSetup& st = c.tris[k];
                    for (int ty = st.y0 / kTile; ty <= st.y1 / kTile; ++ty)
                        for (int tx = st.x0 / kTile; tx <= st.x1 / kTile; ++tx) {
                            const std::uint32_t tile = std::uint32_t(ty * fr.tiles_x + tx);
                            ++c.bin_offsets[tile + 1];
                            pairs.push_back(std::uint64_t(tile) << 32 | k);
                        }
                }
            }
        }
        for (int i = 0; i < ntiles; ++i) c.bin_offsets[i + 1] += c.bin_offsets[i];
        c.bin_items.resize(pairs.size());
        std::vector<std::uint32_t> fill(c.bin_offsets.begin(), c.bin_offsets.end() - 1);
        for (const std::uint64_t p : pairs) c.bin_items[fill[p >> 32]++] = std::uint32_t(p);
    });
    SetupCounters total;
    std::size_t nsetup = 0, nbinned = 0;
    for (const Chunk& c : fr.chunks) {
        total.add(c.counters);
        nsetup += c.tris.size();
        nbinned += c.bin_items.size();
    }
    if (timer.on) std::fprintf(stderr, "  raster triangles set up %zu, bin entries %zu\n", nsetup, nbinned);
    if (total.non_finite)
        warnings->push_back(std::to_string(total.non_finite) + " triangle(s) with non-finite vertex positions dropped");
    if (total.bad_index)
        warnings->push_back(std::to_string(total.bad_index) + " triangle(s) with out-of-range indices dropped");
    if (total.clip_unstable)
        warnings->push_back(std::to_string(total.clip_unstable) + " triangle(s) dropped: clipping produced non-finite or out-of-range vertices");
}

// Interpolates the vertex data of the fragment with setup weights b (shared by both traversals).
FragmentInput interpolate(const Frame& fr, const Chunk& ch, const TriSetup& t, const Bary& b) {
    float o[3];
    if (t.clip < 0) {
        o[0] = b.b[0];
        o[1] = t.perm ? b.b[2] : b.b[1];
        o[2] = t.perm ? b.b[1] : b.b[2];
    } else {
        const ClipVerts& cv = ch.clips[t.clip];
        for (int k = 0; k < 3; ++k) o[k] = (b.b[0] * cv.beta[0][k] + b.b[1] * cv.beta[1][k]) + b.b[2] * cv.beta[2][k];
    }
    const DrawVertices& dv = fr.draws[t.draw];
    const scene::Primitive& p = *dv.prim;
    const std::size_t base = 3 * std::size_t(t.tri);
    const std::uint32_t i0 = p.indices[base], i1 = p.indices[base + 1], i2 = p.indices[base + 2];
    auto lerp3 = [&](const auto& a0, const auto& a1, const auto& a2) {
        return a0 + (a1 - a0) * o[1] + (a2 - a0) * o[2];
    };
    FragmentInput in;
    const DrawVertices::Shading& v0 = dv.view[i0];
    const DrawVertices::Shading& v1 = dv.view[i1];
    const DrawVertices::Shading& v2 = dv.view[i2];
    in.view_pos = lerp3(v0.pos, v1.pos, v2.pos);
    in.normal = lerp3(v0.normal, v1.normal, v2.normal);
    if (!dv.view_tangent.empty()) {
        in.tangent = lerp3(dv.view_tangent[i0], dv.view_tangent[i1], dv.view_tangent[i2]);
        in.has_tangent = true;
    }
    if (p.uv0.size() == p.positions.size()) {
        in.uv = lerp3(p.uv0[i0], p.uv0[i1], p.uv0[i2]);
        in.has_uv = true;
    }
    if (p.colors.size() == p.positions.size()) in.color = lerp3(p.colors[i0], p.colors[i1], p.colors[i2]);
    for (int k = 0; k < scene::kNumControlTargets; ++k) {
        const auto& c = p.control[k];
        if (c.size() == p.positions.size())
            in.ctrl[k] = lerp3(glm::vec3(c[i0]), glm::vec3(c[i1]), glm::vec3(c[i2]));
    }
    in.back = t.back != 0;
    return in;
}

inline bool needs_alpha_test(const Frame& fr, const TriSetup& t) {
    return fr.draws[t.draw].mat->alpha_mode == scene::AlphaMode::Mask;
}

bool alpha_pass(const Frame& fr, const Chunk& ch, const TriSetup& t, const Bary& b) {
    const scene::Material& m = *fr.draws[t.draw].mat;
    return material_alpha(fr.ctx, m, interpolate(fr, ch, t, b)) >= m.alpha_cutoff;
}

void shade_and_write(const Frame& fr, const Chunk& ch, const TriSetup& t, const Bary& b,
                     const TargetPtrs& tp, int x, int y) {
    const DrawVertices& dv = fr.draws[t.draw];
    const FragmentOutput o = shade_fragment(fr.ctx, *dv.mat, interpolate(fr, ch, t, b));
    const std::size_t i = std::size_t(y) * tp.width + x;
    float* c = tp.color + 4 * i;
    c[0] = o.color.x; c[1] = o.color.y; c[2] = o.color.z; c[3] = o.color.w;
    for (int k = 0; k < scene::kNumControlTargets; ++k) {
        float* q = tp.ctrl[k] + 4 * i;
        q[0] = o.ctrl[k].x; q[1] = o.ctrl[k].y; q[2] = o.ctrl[k].z; q[3] = 1.0f;
    }
    tp.depth[i] = b.depth;
    float* n = tp.normal + 3 * i;
    n[0] = o.normal.x; n[1] = o.normal.y; n[2] = o.normal.z;
    tp.id[i] = float(dv.object_id);
    tp.diffuse[i] = o.diffuse;
    tp.specular[i] = o.specular;
}

// ---- Reference traversal: per triangle in submission order, bounding box, whole image --------

void raster_reference(const Frame& fr, const TargetPtrs& tp, int W, int H, float* count) {
    std::vector<float> zbuf(count ? 0 : std::size_t(W) * H, std::numeric_limits<float>::infinity());
    for (const Chunk& ch : fr.chunks)
        for (const TriSetup& t : ch.tris)
            for (int y = t.y0; y <= t.y1; ++y)
                for (int x = t.x0; x <= t.x1; ++x) {
                    std::int64_t e[3];
                    edge_values(t, x, y, e);
                    if (!inside(t, e)) continue;
                    if (count) {
                        count[std::size_t(y) * W + x] += 1.0f;
                        continue;
                    }
                    const Bary b = perspective_bary(t, e);
                    float& z = zbuf[std::size_t(y) * W + x];
                    if (!(b.depth < z)) continue;
                    if (needs_alpha_test(fr, t) && !alpha_pass(fr, ch, t, b)) continue;
                    z = b.depth;
                    shade_and_write(fr, ch, t, b, tp, x, y);
                }
}

// ---- Tiled traversal: one task per tile, visibility then deferred shading ---------------------

// Prefetch hints for the shading gathers of a triangle (no effect on results).
inline void prefetch_indices(const Frame& fr, const TriSetup& t) {
    __builtin_prefetch(fr.draws[t.draw].prim->indices.data() + 3 * std::size_t(t.tri));
}
inline void prefetch_vertices(const Frame& fr, const TriSetup& t) {
    const DrawVertices& dv = fr.draws[t.draw];
    const std::uint32_t* idx = dv.prim->indices.data() + 3 * std::size_t(t.tri);
    for (int j = 0; j < 3; ++j) __builtin_prefetch(&dv.view[idx[j]]);  // indices checked in setup
}

// Streams n floats to dst: 32-byte aligned runs with non-temporal stores, the ends plain.
inline void stream_floats(float* dst, const float* src, std::size_t n) {
    std::size_t i = 0;
    for (; i < n && (reinterpret_cast<std::uintptr_t>(dst + i) & 31) != 0; ++i) dst[i] = src[i];
    for (; i + 8 <= n; i += 8) _mm256_stream_ps(dst + i, _mm256_loadu_ps(src + i));
    for (; i < n; ++i) dst[i] = src[i];
}

// One tile row of all ten targets (kTile pixels), written by shade_and_write at (x, 0).
struct RowBuffer {
    float color[4 * kTile], ctrl[scene::kNumControlTargets][4 * kTile], depth[kTile],
        normal[3 * kTile], id[kTile], diffuse[kTile], specular[kTile];
    TargetPtrs pointers() {
        TargetPtrs p;
        p.color = color;
        for (int k = 0; k < scene::kNumControlTargets; ++k) p.ctrl[k] = ctrl[k];
        p.depth = depth;
        p.normal = normal;
        p.id = id;
        p.diffuse = diffuse;
        p.specular = specular;
        p.width = kTile;
        return p;
    }
    void background(int n, float bg_depth) {  // the values write_background stores
        std::fill_n(color, 4 * n, 0.0f);
        for (auto& c : ctrl) std::fill_n(c, 4 * n, 0.0f);
        std::fill_n(depth, n, bg_depth);
        std::fill_n(normal, 3 * n, 0.0f);
        std::fill_n(id, n, 0.0f);
        std::fill_n(diffuse, n, 0.0f);
        std::fill_n(specular, n, 0.0f);
    }
    void stream_row(const TargetPtrs& tp, int x0, int y, int n) const {
        const std::size_t i = std::size_t(y) * tp.width + x0;
        stream_floats(tp.color + 4 * i, color, 4 * std::size_t(n));
        for (int k = 0; k < scene::kNumControlTargets; ++k) stream_floats(tp.ctrl[k] + 4 * i, ctrl[k], 4 * std::size_t(n));
        stream_floats(tp.depth + i, depth, std::size_t(n));
        stream_floats(tp.normal + 3 * i, normal, 3 * std::size_t(n));
        stream_floats(tp.id + i, id, std::size_t(n));
        stream_floats(tp.diffuse + i, diffuse, std::size_t(n));
        stream_floats(tp.specular + i, specular, std::size_t(n));
    }
};

struct TileRef {
    std::uint32_t chunk, tri;
};

void write_background(const TargetPtrs& tp, std::size_t i, float bg_depth) {
    for (int c = 0; c < 4; ++c) tp.color[4 * i + c] = 0.0f;
    for (int k = 0; k < scene::kNumControlTargets; ++k)
        for (int c = 0; c < 4; ++c) tp.ctrl[k][4 * i + c] = 0.0f;
    tp.depth[i] = bg_depth;
    for (int c = 0; c < 3; ++c) tp.normal[3 * i + c] = 0.0f;
    tp.id[i] = 0.0f;
    tp.diffuse[i] = 0.0f;
    tp.specular[i] = 0.0f;
}

// clear: the targets hold a previous frame (render_gbuffer_into), so background pixels are
// written too; otherwise they already hold the background from the allocation.
void raster_tile(const Frame& fr, const TargetPtrs& tp, int W, int H, int tile, float* count, bool clear) {
    const int tx = tile % fr.tiles_x, ty = tile / fr.tiles_x;
    const int X0 = tx * kTile, Y0 = ty * kTile;
    const int X1 = std::min(X0 + kTile, W) - 1, Y1 = std::min(Y0 + kTile, H) - 1;
    const int tw = X1 - X0 + 1;
    float zbuf[kTile * kTile];
    TileRef ids[kTile * kTile];
    for (int i = 0; i < kTile * kTile; ++i) {
        zbuf[i] = std::numeric_limits<float>::infinity();
        ids[i].chunk = kNoChunk;
    }
    const std::int64_t step = kSubpixelOne;
    for (std::uint32_t ci = 0; ci < fr.chunks.size(); ++ci) {
        const Chunk& ch = fr.chunks[ci];
        for (std::uint32_t k = ch.bin_offsets[tile]; k < ch.bin_offsets[tile + 1]; ++k) {
            const std::uint32_t ti = ch.bin_items[k];
            // The setups of one tile are scattered over the chunk: fetch ahead (latency-bound).
            if (k + 6 < ch.bin_offsets[tile + 1]) {
                const char* ahead = reinterpret_cast<const char*>(&ch.tris[ch.bin_items[k + 6]]);
                __builtin_prefetch(ahead);
                __builtin_prefetch(ahead + 64);
            }
            const TriSetup& t = ch.tris[ti];
            const int x0 = std::max(t.x0, X0), x1 = std::min(t.x1, X1);
            const int y0 = std::max(t.y0, Y0), y1 = std::min(t.y1, Y1);
            std::int64_t row[3];
            edge_values(t, x0, y0, row);
            const std::int64_t sx[3] = {t.A[0] * step, t.A[1] * step, t.A[2] * step};
            const std::int64_t sy[3] = {t.B[0] * step, t.B[1] * step, t.B[2] * step};
            const bool atest = needs_alpha_test(fr, t);
            for (int y = y0; y <= y1; ++y) {
                std::int64_t e[3] = {row[0], row[1], row[2]};
                for (int x = x0; x <= x1; ++x) {
                    if (inside(t, e)) {
                        const int li = (y - Y0) * kTile + (x - X0);
                        if (count) {
                            count[std::size_t(y) * W + x] += 1.0f;
                        } else {
                            const Bary b = perspective_bary(t, e);
                            if (b.depth < zbuf[li] && (!atest || alpha_pass(fr, ch, t, b))) {
                                zbuf[li] = b.depth;
                                ids[li] = {ci, ti};
                            }
                        }
                    }
                    e[0] += sx[0]; e[1] += sx[1]; e[2] += sx[2];
                }
                row[0] += sy[0]; row[1] += sy[1]; row[2] += sy[2];
            }
        }
    }
    if (count) return;
    // Deferred shading of the covered pixels, row-major. Each pixel gathers its setup, then the
    // triangle's indices, then its vertices (dependent cache misses: one small triangle per pixel
    // on dense meshes), so those are prefetched 12, 8 and 4 pixels ahead (schedule only).
    std::uint16_t covered[kTile * kTile];
    int nc = 0;
    for (int li = 0; li < kTile * kTile; ++li)
        if (ids[li].chunk != kNoChunk) covered[nc++] = std::uint16_t(li);
    auto setup_at = [&](int k) -> const TriSetup& {
        const TileRef r = ids[covered[k]];
        return fr.chunks[r.chunk].tris[r.tri];
    };
    // Each row is composed in a small buffer (background, then its shaded pixels) and streamed
    // to the targets: every byte of the 108 B/px G-buffer is written once, with non-temporal
    // stores (no read-for-ownership of lines that are overwritten whole). Without `clear` the
    // targets already hold the background and rows with no covered pixel are skipped.
    RowBuffer rb;
    const TargetPtrs rp = rb.pointers();
    int k = 0;
    for (int y = Y0; y <= Y1; ++y) {
        const int ly = y - Y0;
        if (!clear && !(k < nc && covered[k] / kTile == ly)) continue;
        rb.background(tw, fr.background_depth);
        for (; k < nc && covered[k] / kTile == ly; ++k) {
            if (k + 12 < nc) {
                const char* a = reinterpret_cast<const char*>(&setup_at(k + 12));
                __builtin_prefetch(a);
                __builtin_prefetch(a + 64);
            }
            if (k + 8 < nc) prefetch_indices(fr, setup_at(k + 8));
            if (k + 4 < nc) prefetch_vertices(fr, setup_at(k + 4));
            const int lx = covered[k] % kTile;
            const TileRef r = ids[covered[k]];
            const Chunk& ch = fr.chunks[r.chunk];
            const TriSetup& t = ch.tris[r.tri];
            std::int64_t e[3];
            edge_values(t, X0 + lx, y, e);
            shade_and_write(fr, ch, t, perspective_bary(t, e), rp, lx, 0);
        }
        rb.stream_row(tp, X0, y, tw);
    }
    _mm_sfence();  // order the non-temporal stores before the task completes
}

// The per-frame vertex and setup buffers (about 70 MB for the 871k dragon at 1080p) are kept
// for the next render call instead of being freed: fresh buffers cost a page fault per 4 KiB on
// first touch in every frame. One set is kept process-wide (concurrent renders beyond the first
// allocate their own); contents never carry over (docs/raster.md).
struct FrameScratch {
    static FrameScratch& get() {
        static FrameScratch g;
        return g;
    }
    static void take(Frame& fr) {
        FrameScratch& g = get();
        std::lock_guard<std::mutex> lock(g.mu);
        fr.draws = std::move(g.draws);
        fr.chunks = std::move(g.chunks);
        g.draws.clear();
        g.chunks.clear();
    }
    static void give(Frame& fr) {
        FrameScratch& g = get();
        std::lock_guard<std::mutex> lock(g.mu);
        if (g.draws.empty() && g.chunks.empty()) {
            g.draws = std::move(fr.draws);
            g.chunks = std::move(fr.chunks);
        }
    }
    std::mutex mu;
    std::vector<DrawVertices> draws;
    std::vector<Chunk> chunks;
};

// Builds the frame constants for a raster grid of W x H (supersampled).
Frame make_frame(const scene::Scene& sc, const scene::Camera& cam, const RenderSettings& s, int W, int H) {
    Frame fr;
    fr.fp.proj = projection_matrix(cam, float(s.width) / float(s.height));
    fr.fp.perspective = !cam.orthographic;
    fr.fp.vp.width = W;
    fr.fp.vp.height = H;
    fr.fp.vp.gb_x = kGuardBandPx / W;
    fr.fp.vp.gb_y = kGuardBandPx / H;
    fr.fp.out_width = s.width;
    fr.fp.out_height = s.height;
    fr.fp.time_s = float(s.frame) / s.fps;
    fr.fp.settings = &s;
    fr.sopt.cull_backfaces = s.cull_backfaces;
    fr.ctx.scene = &sc;
    fr.ctx.ambient = sc.ambient;
    fr.ctx.perspective = !cam.orthographic;
    fr.ctx.substrate = s.substrate_color;
    fr.ctx.object_space_turbulence = s.turbulence == RenderSettings::Turbulence::ObjectSpace;
    fr.ctx.working_space = s.working_space;
    const glm::mat3 v3(cam.view);
    for (const scene::Light& l : sc.lights) {
        ViewLight vl;
        vl.dir = normalize3(v3 * l.direction);
        vl.radiance = l.color * l.intensity;
        fr.ctx.lights.push_back(vl);
    }
    if (fr.ctx.lights.empty()) fr.ctx.lights.push_back(default_view_light());
    fr.tiles_x = (W + kTile - 1) / kTile;
    fr.tiles_y = (H + kTile - 1) / kTile;
    fr.background_depth = cam.zfar;
    return fr;
}

// The ten targets are allocated (and zero-filled by ImageF) in parallel when `parallel`: at
// 1080p they are 224 MB whose first touch (page faults) costs as much as the rasterization.
Targets allocate_targets(int W, int H, float bg_depth, bool parallel = false) {
    struct Spec { const char* name; int channels; float fill; };
    const Spec specs[] = {{target::kColor, 4, 0.0f},         {target::kCtrlPigment, 4, 0.0f},
                          {target::kCtrlSubstrate, 4, 0.0f}, {target::kCtrlEdge, 4, 0.0f},
                          {target::kCtrlAbstraction, 4, 0.0f}, {target::kDepthLinear, 1, bg_depth},
                          {target::kNormal, 3, 0.0f},        {target::kObjectId, 1, 0.0f},
                          {target::kDiffuse, 1, 0.0f},       {target::kSpecular, 1, 0.0f}};
    constexpr std::size_t n = sizeof(specs) / sizeof(specs[0]);
    std::vector<ImageF> imgs(n);
    run_for(parallel, n, [&](std::size_t i) { imgs[i] = ImageF(W, H, specs[i].channels, specs[i].fill); });
    Targets tg;
    for (std::size_t i = 0; i < n; ++i) tg.set(specs[i].name, std::move(imgs[i]));
    return tg;
}

TargetPtrs pointers(Targets& tg) {
    TargetPtrs p;
    p.color = tg.get_mut(target::kColor).data();
    p.ctrl[0] = tg.get_mut(target::kCtrlPigment).data();
    p.ctrl[1] = tg.get_mut(target::kCtrlSubstrate).data();
    p.ctrl[2] = tg.get_mut(target::kCtrlEdge).data();
    p.ctrl[3] = tg.get_mut(target::kCtrlAbstraction).data();
    p.depth = tg.get_mut(target::kDepthLinear).data();
    p.normal = tg.get_mut(target::kNormal).data();
    p.id = tg.get_mut(target::kObjectId).data();
    p.diffuse = tg.get_mut(target::kDiffuse).data();
    p.specular = tg.get_mut(target::kSpecular).data();
    p.width = tg.get(target::kColor).width();
    return p;
}

// ---- SSAA resolve (docs/raster.md "Supersampling") -------------------------------------------

Targets resolve(const Targets& hi, int K, int W, int H, float bg_depth, const Exec& ex) {
    Targets lo = allocate_targets(W, H, bg_depth);
    const int HW = W * K;
    const float inv_total = 1.0f / float(K * K);
    const float* hc = hi.get(target::kColor).data();
    const float* hd = hi.get(target::kDepthLinear).data();
    const float* hn = hi.get(target::kNormal).data();
    const float* hid = hi.get(target::kObjectId).data();
    const float* hdf = hi.get(target::kDiffuse).data();
    const float* hsp = hi.get(target::kSpecular).data();
    const char* ctrl_names[4] = {target::kCtrlPigment, target::kCtrlSubstrate, target::kCtrlEdge,
                                 target::kCtrlAbstraction};
    const float* hctrl[4];
    for (int k = 0; k < 4; ++k) hctrl[k] = hi.get(ctrl_names[k]).data();
    TargetPtrs lp = pointers(lo);
    Exec e = ex;
    for_each_tile(e, Roi{0, 0, W, H}, [&](Roi r) {
        std::vector<std::size_t> cov;
        std::vector<float> ids;
        for (int y = r.y0; y < r.y1; ++y)
            for (int x = r.x0; x < r.x1; ++x) {
                cov.clear();
                ids.clear();
                for (int sy = 0; sy < K; ++sy)
                    for (int sx = 0; sx < K; ++sx) {
                        const std::size_t j = std::size_t(y * K + sy) * HW + (x * K + sx);
                        ids.push_back(hid[j]);
                        if (hc[4 * j + 3] > 0.0f) cov.push_back(j);
                    }
                const std::size_t i = std::size_t(y) * W + x;
                // object_id: majority of all K*K samples (background 0 included); ties go to the
                // value met first in row-major sample order.
                float best = ids[0];
                int best_n = 0;
                for (std::size_t a = 0; a < ids.size(); ++a) {
                    int n = 0;
                    for (std::size_t b2 = 0; b2 < ids.size(); ++b2) n += ids[b2] == ids[a];
                    if (n > best_n) {
                        best_n = n;
                        best = ids[a];
                    }
                }
                lp.id[i] = best;
                if (cov.empty()) continue;  // background values already in place
                const float n = float(cov.size());
                const float alpha = float(cov.size()) * inv_total;
                glm::vec3 c(0), nn(0);
                glm::vec3 cc[4] = {glm::vec3(0), glm::vec3(0), glm::vec3(0), glm::vec3(0)};
                float dmin = std::numeric_limits<float>::infinity(), df = 0, sp = 0;
                for (std::size_t j : cov) {
                    c = c + glm::vec3(hc[4 * j], hc[4 * j + 1], hc[4 * j + 2]);
                    for (int k = 0; k < 4; ++k)
                        cc[k] = cc[k] + glm::vec3(hctrl[k][4 * j], hctrl[k][4 * j + 1], hctrl[k][4 * j + 2]);
                    nn = nn + glm::vec3(hn[3 * j], hn[3 * j + 1], hn[3 * j + 2]);
                    dmin = std::min(dmin, hd[j]);
                    df = df + hdf[j];
                    sp = sp + hsp[j];
                }
                c = c / n;
                lp.color[4 * i] = c.x; lp.color[4 * i + 1] = c.y; lp.color[4 * i + 2] = c.z;
                lp.color[4 * i + 3] = alpha;
                for (int k = 0; k < 4; ++k) {
                    const glm::vec3 v = cc[k] / n;
                    float* q = lp.ctrl[k] + 4 * i;
                    q[0] = v.x; q[1] = v.y; q[2] = v.z; q[3] = alpha;
                }
                nn = normalize3(nn / n);
                lp.normal[3 * i] = nn.x; lp.normal[3 * i + 1] = nn.y; lp.normal[3 * i + 2] = nn.z;
                lp.depth[i] = dmin;
                lp.diffuse[i] = df / n;
                lp.specular[i] = sp / n;
            }
    });
    return lo;
}

enum class Mode { GBuffer, Count };



bool reusable(const Targets& t, int W, int H) {
    const std::pair<const char*, int> want[] = {
        {target::kColor, 4}, {target::kCtrlPigment, 4}, {target::kCtrlSubstrate, 4}, {target::kCtrlEdge, 4},
        {target::kCtrlAbstraction, 4}, {target::kDepthLinear, 1}, {target::kNormal, 3},
        {target::kObjectId, 1}, {target::kDiffuse, 1}, {target::kSpecular, 1}};
    if (t.all().size() != std::size(want)) return false;
    for (const auto& [name, ch] : want) {
        if (!t.has(name)) return false;
        const ImageF& img = t.get(name);
        if (img.width() != W || img.height() != H || img.channels() != ch) return false;
    }
    return true;
}

Targets render(const scene::Scene& sc, const scene::Camera& cam, const RenderSettings& s,
               std::vector<std::string>* warnings, Mode mode, ImageF* count_out, Targets* reuse = nullptr) {
    validate(cam, s);
    std::vector<std::string> local;
    if (!warnings) warnings = &local;
    const int K = s.ssaa, W = s.width * K, H = s.height * K;
    Frame fr = make_frame(sc, cam, s, W, H);
    FrameScratch::take(fr);
    const bool fast = s.exec.traversal == Traversal::Fast;
    Targets tg;
    bool clear = false;
    PhaseTimer timer;
    auto body = [&] {
        prepare(fr, sc, cam, fast, fast, warnings, timer);
        timer.lap("setup+bin");
        float* count = nullptr;
        TargetPtrs tp{};
        if (mode == Mode::Count) {
            *count_out = ImageF(W, H, 1, 0.0f);
            count = count_out->data();
        } else {
            if (reuse && K == 1 && reusable(*reuse, W, H)) {
                tg = std::move(*reuse);
                clear = true;
                if (!fast) {
                    TargetPtrs bp = pointers(tg);
                    for (std::size_t i = 0; i < std::size_t(W) * H; ++i) write_background(bp, i, fr.background_depth);
                }
            } else {
                tg = allocate_targets(W, H, fr.background_depth, fast);
            }
            tp = pointers(tg);
        }
        timer.lap("allocate");
        if (!fast) {
            raster_reference(fr, tp, W, H, count);
        } else {
            const int ntiles = fr.tiles_x * fr.tiles_y;
            tbb::parallel_for(0, ntiles, [&](int tile) { raster_tile(fr, tp, W, H, tile, count, clear); });
        }
        timer.lap("raster");
    };
    if (fast) with_arena(s.exec, body);
    else body();
    timer.lap("arena exit");
    FrameScratch::give(fr);
    if (mode == Mode::GBuffer && K > 1) {
        Targets lo = resolve(tg, K, s.width, s.height, fr.background_depth, s.exec);
        timer.lap("resolve");
        return lo;
    }
    return tg;
}

}  // namespace

Targets render_gbuffer(const scene::Scene& sc, const scene::Camera& cam, const RenderSettings& s,
                       std::vector<std::string>* warnings) {
    return render(sc, cam, s, warnings, Mode::GBuffer, nullptr);
}

void render_gbuffer_into(Targets& out, const scene::Scene& sc, const scene::Camera& cam,
                         const RenderSettings& s, std::vector<std::string>* warnings) {
    out = render(sc, cam, s, warnings, Mode::GBuffer, nullptr, &out);
}

ImageF debug_coverage_count(const scene::Scene& sc, const scene::Camera& cam,
                            const RenderSettings& s, std::vector<std::string>* warnings) {
    ImageF out;
    render(sc, cam, s, warnings, Mode::Count, &out);
    return out;
}

}  // namespace aq::raster
