// raster/raster.cpp — render_gbuffer: validates the settings, drives one frame (binning.cpp:
// vertex stage -> setup/binning; tile.cpp: per-tile visibility and deferred watercolor shading
// (fast, oneTBB) or the plain reference rasterizer; resolve.cpp: SSAA resolve) and keeps the
// per-frame scratch for the next frame.
//
// Determinism (docs/raster.md): every per-vertex, per-triangle and per-fragment result is a pure
// function of its inputs; the fast path only changes the schedule. Each tile has exactly one
// writer and visits triangles in submission order.
#include "raster/raster.h"

#include <atomic>
#include <bit>
#include <cmath>
#include <mutex>

#include "raster/raster_internal.h"

namespace aq::raster {

namespace {

using namespace detail;

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

    // Background tiles kept between frames (docs/raster.md): what the fast traversal last wrote.
    // Its stamp is on every target image it wrote (ImageF::stamp); a render into images that still
    // carry it, at the same size and background depth, need not write again a tile that held only
    // background then and does now — the ARM Mali "transaction elimination" idea for the one tile
    // content known without computing it. One record process-wide: another render in between
    // (other targets) only costs the next frame its full write.
    struct Written {
        std::uint64_t stamp = 0;
        int W = 0, H = 0;
        std::uint32_t bg_depth_bits = 0;
        std::vector<std::uint8_t> background;  //!< per tile: only background written
    };
    Written last;
    //! The previous frame's background tiles when `tg` holds exactly what it wrote, else empty.
    static std::vector<std::uint8_t> kept_background(const Targets& tg, int W, int H, float bg_depth) {
        if (tg.all().empty()) return {};
        const std::uint64_t s = tg.all().begin()->second.stamp();
        for (const auto& [name, img] : tg.all())
            if (img.stamp() != s) return {};
        FrameScratch& g = get();
        std::lock_guard<std::mutex> lock(g.mu);
        const Written& w = g.last;
        if (s == 0 || w.stamp != s || w.W != W || w.H != H || w.bg_depth_bits != std::bit_cast<std::uint32_t>(bg_depth))
            return {};
        return w.background;
    }
    //! Stamps every image of `tg` (just written whole) and records its background tiles.
    static void record(Targets& tg, int W, int H, float bg_depth, std::vector<std::uint8_t> background) {
        static std::atomic<std::uint64_t> next{0};
        const std::uint64_t s = ++next;
        for (const std::string& name : tg.names()) tg.get_mut(name).set_stamp(s);
        FrameScratch& g = get();
        std::lock_guard<std::mutex> lock(g.mu);
        g.last = Written{s, W, H, std::bit_cast<std::uint32_t>(bg_depth), std::move(background)};
    }
};

}  // namespace

// Builds the frame constants for a raster grid of W x H (supersampled).
Frame detail::make_frame(const scene::Scene& sc, const scene::Camera& cam, const RenderSettings& s, int W, int H) {
    // TriSetup's 16-bit pixel bounds hold every pixel of a grid that passes this check.
    check_image_size(W, H, "raster grid");
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
    fr.grid = TileGrid(W, H);
    fr.background_depth = cam.zfar;
    return fr;
}

namespace {

enum class Mode { GBuffer, Count };



Targets render(const scene::Scene& sc, const scene::Camera& cam, const RenderSettings& s,
               std::vector<std::string>* warnings, Mode mode, ImageF* count_out, Targets* reuse = nullptr) {
    validate(cam, s);
    std::vector<std::string> local;
    if (!warnings) warnings = &local;
    const int K = s.ssaa, W = s.width * K, H = s.height * K;
    Frame fr = make_frame(sc, cam, s, W, H);
    FrameScratch::take(fr);
    const bool fast = s.exec.traversal == Traversal::Fast;
    // Only the fast single-sample traversal leaves out targets (its row streaming skips them);
    // colour and depth always exist. mask = the targets produced.
    const std::uint32_t mask = fast && K == 1 && mode == Mode::GBuffer
                                   ? s.targets | target::gbuffer_bit(target::kColor) | target::gbuffer_bit(target::kDepthLinear)
                                   : target::kAllGBufferTargets;
    Targets tg;
    bool clear = false;
    std::vector<std::uint8_t> kept;  // per tile: the reused targets hold only background there
    PhaseTimer timer;
    // Coverage antialiasing (docs/raster.md): single-sample G-buffers only.
    const bool aa = mode == Mode::GBuffer && K == 1 && s.antialias == RenderSettings::Antialias::Coverage;
    fr.sopt.keep_subpixel = aa;
    auto body = [&] {
        prepare(fr, sc, cam, fast, fast, warnings, timer);
        timer.lap("setup+bin");
        float* count = nullptr;
        TargetPtrs tp{};
        if (mode == Mode::Count) {
            *count_out = ImageF(W, H, 1, 0.0f);
            count = count_out->data();
        } else {
            if (reuse && K == 1 && reusable(*reuse, W, H, mask)) {
                tg = std::move(*reuse);
                clear = true;
                if (fast) kept = FrameScratch::kept_background(tg, W, H, fr.background_depth);
                if (!fast) {
                    TargetPtrs bp = pointers(tg);
                    for (std::size_t i = 0; i < std::size_t(W) * H; ++i) write_background(bp, i, fr.background_depth);
                }
            } else if (fast) {
                // Fresh targets: the tiles write every pixel (background included), so the memory
                // is not filled first (one write per byte; the page faults happen in the tiles).
                tg = allocate_targets_unfilled(W, H, mask);
                clear = true;
            } else {
                tg = allocate_targets(W, H, fr.background_depth, mask);
            }
            tp = pointers(tg);  // clears the stamps: stamped again below once written whole
        }
        timer.lap("allocate");
        CoverageBits cov;
        if (aa) cov.reset(W, H);
        // Per tile (fast): no triangle binned to it, so it shows only background.
        const int ntiles = fr.grid.count();
        std::vector<std::uint8_t> background(fast ? std::size_t(ntiles) : 0, 0);
        if (fast) {
            for (int t = 0; t < ntiles; ++t) background[std::size_t(t)] = !tile_binned(fr, t);
            if (kept.size() != background.size()) kept.assign(background.size(), 0);
            if (timer.on) {
                int n = 0;
                for (int t = 0; t < ntiles; ++t) n += kept[std::size_t(t)] && background[std::size_t(t)];
                std::fprintf(stderr, "  raster tiles %d, background kept from the previous frame %d\n", ntiles, n);
            }
        }
        traverse_tiles(s.exec, fr.grid, [&] { raster_reference(fr, tp, W, H, count); },
                       [&](int tile, TileRect tr) {
                           const std::size_t t = std::size_t(tile);
                           raster_tile(fr, tp, tile, tr, count, clear && !(kept[t] && background[t]), aa ? &cov : nullptr);
                       });
        if (aa) {
            timer.lap("raster");
            // A tile along a silhouette may have been written by the pass even if no triangle
            // was binned to it: not kept as background for the next frame.
            traverse_tiles(
                s.exec, fr.grid,
                [&] {
                    cov.from_alpha(tp);
                    coverage_reference(fr, tp, cov);
                },
                [&](int tile, TileRect tr) {
                    if (coverage_tile(fr, tp, cov, tile, tr)) background[std::size_t(tile)] = 0;
                });
            timer.lap("coverage");
        }
        if (fast && mode == Mode::GBuffer && K == 1) FrameScratch::record(tg, W, H, fr.background_depth, std::move(background));
        timer.lap(aa ? "record" : "raster");  // after the coverage pass: what remains of the body
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
