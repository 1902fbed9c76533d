// raster/raster_internal.h — what the parts of the rasterizer share (raster/raster.cpp drives a
// frame; binning.cpp: vertex stage, triangle setup and binning; tile.cpp: the reference and the
// tiled traversal; resolve.cpp: SSAA resolve; gbuffer.cpp: the G-buffer targets). Not a public
// API: include only from raster/*.cpp.
#pragma once

#include <chrono>
#include <functional>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include <tbb/parallel_for.h>

#include "raster/material.h"
#include "raster/raster.h"
#include "raster/setup.h"
#include "raster/tiles.h"
#include "raster/vertex.h"
#include "raster/visibility.h"

namespace aq::raster::detail {

constexpr std::uint32_t kChunkTris = 32768;  // most triangles per setup chunk (schedule only)
//! Fewest triangles per chunk: a frame of few triangles (LD06's 520 px passes over ~14k) is still
//! cut into about kChunksPerThread chunks per thread so that its setup runs on every thread.
constexpr std::uint32_t kMinChunkTris = 2048;
constexpr std::uint32_t kChunksPerThread = 4;
constexpr std::size_t kVertexGrain = 4096;
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
    //! The sub-pixel setups (coverage pass only), binned apart so that the traversal never reads
    //! them; empty without SetupOptions::keep_subpixel. An item is an index into `tris` (a
    //! TriSetup with kSubpixelBit), or with kMicroItem set into `micro`.
    std::vector<std::uint32_t> fine_offsets, fine_items;
    static constexpr std::uint32_t kMicroItem = 1u << 31;
    //! The batch setup's sub-pixel triangles of opaque materials (setup_triangles' subpixel_out).
    std::vector<SubpixelTri> micro;
    //! A setup's pixel-centre bounds (x0, y0, x1, y1), 8 bytes instead of the 104 of the record.
    struct Bounds {
        std::int16_t x0, y0, x1, y1;
    };
    //! Per setup, in setup order: its coverage_bounds (setup.h; keep_subpixel only; the source of
    //! the two below).
    std::vector<Bounds> bounds;
    //! Per bin entry, beside bin_items and fine_items: the entry's coverage_bounds, for the
    //! coverage pass's scan of a tile's bins, which so reads them in order (keep_subpixel only).
    std::vector<Bounds> bin_bounds, fine_bounds;
    //! Binning's (tile, setup index) pairs before their counting sort, traversal's and sub-pixel
    //! ones (scratch kept with the chunk, as the buffers above, so a frame does not fault them in).
    std::vector<std::uint64_t> pairs, fine_pairs;
    SetupCounters counters;
};

//! Where each G-buffer target sits in target::kGBufferLayout: the order of TargetPtrs::at, the
//! row buffers and every loop over the targets.
namespace gbuffer_slot {
inline constexpr std::size_t kCount = std::size(target::kGBufferLayout);
constexpr std::size_t of(const char* name) {
    for (std::size_t i = 0; i < kCount; ++i)
        if (std::string_view(target::kGBufferLayout[i].name) == name) return i;
    return kCount;
}
inline constexpr std::size_t kColor = of(target::kColor), kCtrl = of(target::kCtrlPigment), kDepth = of(target::kDepthLinear),
                             kNormal = of(target::kNormal), kId = of(target::kObjectId), kDiffuse = of(target::kDiffuse),
                             kSpecular = of(target::kSpecular);
static_assert(of(target::kCtrlSubstrate) == kCtrl + 1 && of(target::kCtrlEdge) == kCtrl + 2 &&
                  of(target::kCtrlAbstraction) == kCtrl + 3 && scene::kNumControlTargets == 4,
              "the control targets follow each other in the layout, in control::kTargets order");
}  // namespace gbuffer_slot

//! The G-buffer targets' values (row-major, channels interleaved), by layout slot.
template <class T>
struct TargetPtrsOf {
    std::array<T*, gbuffer_slot::kCount> at{};  //!< kGBufferLayout[i]'s values; null: not in the set
    int width = 0;                              //!< pixels per row
    T* color() const { return at[gbuffer_slot::kColor]; }
    T* ctrl(int k) const { return at[gbuffer_slot::kCtrl + std::size_t(k)]; }
    T* depth() const { return at[gbuffer_slot::kDepth]; }
    T* normal() const { return at[gbuffer_slot::kNormal]; }
    T* id() const { return at[gbuffer_slot::kId]; }
    T* diffuse() const { return at[gbuffer_slot::kDiffuse]; }
    T* specular() const { return at[gbuffer_slot::kSpecular]; }
};
using TargetPtrs = TargetPtrsOf<float>;

struct Frame {
    FrameParams fp;
    SetupOptions sopt;
    ShadeContext ctx;
    std::vector<DrawVertices> draws;
    std::vector<Chunk> chunks;
    TileGrid grid;  //!< the image's tiles (raster/tiles.h): bins and the tiled traversal
    float background_depth = 0;
};

//! The reference traversal's loop, shared by the G-buffer and the LD06 triangle passes
//! (docs/raster.md "Tiles, traversal, determinism"): every triangle of the frame in submission order, every
//! pixel of its bounding box on the whole image, its edge values computed at the pixel
//! (edge_values: independent of the tiled traversal's stepping); f(chunk, triangle, x, y, e) for
//! each pixel whose centre is inside. Subpixel triangles (kept for the coverage pass only, which
//! covers no pixel centre) are skipped.
template <class F>
void for_each_reference_fragment(const Frame& fr, F&& f) {
    for (const Chunk& ch : fr.chunks)
        for (const TriSetup& t : ch.tris)
            for (int y = t.y0; y <= t.y1 && !t.subpixel(); ++y)
                for (int x = t.x0; x <= t.x1; ++x) {
                    std::int64_t e[3];
                    edge_values(t, x, y, e);
                    if (inside(t, e)) f(ch, t, x, y, static_cast<const std::int64_t*>(e));
                }
}

//! Whether any triangle was binned to `tile` (fast path); a tile without one shows only background.
inline bool tile_binned(const Frame& fr, int tile) {
    bool binned = false;
    for (const Chunk& ch : fr.chunks) binned = binned || ch.bin_offsets[tile] != ch.bin_offsets[tile + 1];
    return binned;
}

template <class F>
void run_for(bool parallel, std::size_t n, F&& f) {
    if (!parallel) {
        for (std::size_t i = 0; i < n; ++i) f(i);
        return;
    }
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) { f(i); });
}

// raster.cpp
//! The frame constants for a raster grid of W x H (supersampled) of settings `s` (kept by pointer).
Frame make_frame(const scene::Scene& sc, const scene::Camera& cam, const RenderSettings& s, int W, int H);

// binning.cpp
//! The material of primitives whose material index is out of range.
const scene::Material& default_material();
//! Which (instance, primitive) pairs a frame draws (raster passes draw subsets).
using DrawFilter = std::function<bool(const scene::Instance&, const scene::Primitive&)>;
//! Vertex stage and chunked triangle setup (+ binning into kTile tiles when `bin`).
void prepare(Frame& fr, const scene::Scene& sc, const scene::Camera& cam, bool parallel, bool bin,
             std::vector<std::string>* warnings, PhaseTimer& timer, const DrawFilter* filter = nullptr);

// coverage.cpp (docs/raster.md "Coverage antialiasing")
constexpr int kCoverageGrid = 4;  //!< samples per axis: those of ssaa 4
constexpr int kCoverageSamples = kCoverageGrid * kCoverageGrid;
//! Which pixels the single-sample traversal covered: one bit per pixel, rows of kTile-pixel words
//! (word tx of row y is tile column tx, so each tile writes its own words).
struct CoverageBits {
    int W = 0, H = 0, words = 0;
    std::vector<std::uint64_t> bits;
    void reset(int w, int h);                       //!< W x H, nothing covered
    void from_alpha(const TargetPtrs& tp);          //!< covered = colour alpha > 0 (the reference's)
    std::uint64_t& word(int tx, int y) { return bits[std::size_t(y) * words + tx]; }
    std::uint64_t word(int tx, int y) const { return bits[std::size_t(y) * words + tx]; }
    bool at(int x, int y) const { return (word(x / 64, y) >> (x % 64)) & 1; }
};
static_assert(kTile == 64, "CoverageBits: one 64-bit word per tile row");
//! The plain reference loop of the coverage pass over the whole image.
void coverage_reference(const Frame& fr, const TargetPtrs& tp, const CoverageBits& cov);
//! The coverage pass of one tile (fast schedule, after every tile's traversal). Returns whether
//! the tile has pixels along a silhouette (it may have written some).
bool coverage_tile(const Frame& fr, const TargetPtrs& tp, const CoverageBits& cov, int tile, TileRect tr);

// tile.cpp
//! Weights of the fragment on the original triangle's vertices (through the clip table for
//! clipped triangles): what interpolate() and the raster passes' lighter gathers use.
//! Inline: a call returning o[] through memory made its caller's wider load of o[1], o[2] wait on
//! a failed store forward (9 % of interpolate's samples on the dragon).
[[gnu::always_inline]] inline void original_weights(const Chunk& ch, const TriSetup& t, const Bary& b, float o[3]) {
    if (t.clip < 0) {
        o[0] = b.b[0];
        o[1] = t.perm() ? b.b[2] : b.b[1];
        o[2] = t.perm() ? b.b[1] : b.b[2];
    } else {
        const ClipVerts& cv = ch.clips[t.clip];
        for (int k = 0; k < 3; ++k) o[k] = (b.b[0] * cv.beta[0][k] + b.b[1] * cv.beta[1][k]) + b.b[2] * cv.beta[2][k];
    }
}
//! The fragment's interpolated vertex data (both traversals and the raster passes).
FragmentInput interpolate(const Frame& fr, const Chunk& ch, const TriSetup& t, const Bary& b);
//! The same into `in` (every field written).
void interpolate(const Frame& fr, const Chunk& ch, const TriSetup& t, const Bary& b, FragmentInput& in);
//! The material's alpha test (alpha-masked materials only; see needs_alpha_test).
bool alpha_pass(const Frame& fr, const Chunk& ch, const TriSetup& t, const Bary& b);
inline bool needs_alpha_test(const Frame& fr, const TriSetup& t) {
    return fr.draws[t.draw].mat->alpha_mode == scene::AlphaMode::Mask;
}
//! The plain reference: per triangle in submission order, bounding box, whole image.
void raster_reference(const Frame& fr, const TargetPtrs& tp, int W, int H, float* count);
//! The visibility of tile `tile` (pixels [X0, X1] x [Y0, Y1]): the triangles binned to it in
//! submission order through depth_test_triangle, alpha-masked ones per pixel with the material's
//! alpha test. zbuf and ids (kTile x kTile, row-major) hold +inf and kNoChunk, or an earlier state.
void resolve_tile(const Frame& fr, int tile, int X0, int Y0, int X1, int Y1, float* zbuf, TileRef* ids);
//! One tile of the tiled traversal: visibility, then deferred shading of each pixel's winner.
//! `clear`: write the background pixels too (else the targets already hold them).
//! `cov`, when given, receives the tile's coverage bits.
void raster_tile(const Frame& fr, const TargetPtrs& tp, int tile, TileRect tr, float* count, bool clear,
                 CoverageBits* cov = nullptr);
//! Writes the background values of pixel i into every target.
void write_background(const TargetPtrs& tp, std::size_t i, float bg_depth);

// gbuffer.cpp
//! The targets of target::kGBufferLayout in `mask` (target::gbuffer_bit) at W x H, holding the
//! background (the reference traversal and the SSAA resolve write covered pixels only).
Targets allocate_targets(int W, int H, float bg_depth, std::uint32_t mask = target::kAllGBufferTargets);
//! The same targets with their values not written: for a writer that writes every pixel (the
//! tiled traversal with `clear`), so each byte is written once and its page first touched there.
Targets allocate_targets_unfilled(int W, int H, std::uint32_t mask);
//! Pointers to the targets of tg; null for a G-buffer target tg does not hold (only the fast
//! traversal's row streaming skips null targets: the other writers need all ten).
TargetPtrs pointers(Targets& tg);
TargetPtrsOf<const float> pointers(const Targets& tg);
//! `t` holds exactly the G-buffer targets of `mask` at W x H (its storage can be reused for a new
//! frame).
bool reusable(const Targets& t, int W, int H, std::uint32_t mask = target::kAllGBufferTargets);

// resolve.cpp
//! SSAA resolve of the K-times supersampled `hi` to W x H (docs/raster.md "Supersampling").
Targets resolve(const Targets& hi, int K, int W, int H, float bg_depth, const Exec& ex);

}  // namespace aq::raster::detail
