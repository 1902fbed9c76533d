// app/render_job.h — the render job behind `aquarelle render`, apart from option parsing and file
// output: a scene loaded and a style configured once (prepare_render), then frames x sweep values
// rendered, each image handed to a sink (run_render). The CLI's sink writes files; the regression
// goldens (tests/app/golden_test.cpp) hash every target through the same job.
#pragma once

#include <functional>
#include <future>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/cache.h"
#include "core/color.h"
#include "core/io.h"
#include "core/targets.h"
#include "raster/foliage.h"
#include "raster/strokes.h"
#include "raster/raster.h"
#include "scenes/scene_file.h"
#include "stylize/pipeline.h"

namespace aq {
class InputCapture;
}

namespace aq::app {

//! The image pool's limit during a one-shot render (core/image.h set_image_pool_limit): measured
//! on the 871k dragon at 1080p through WC18 (docs/performance.md "Memory of a one-shot render").
inline constexpr std::size_t kOneShotPoolBytes = std::size_t(32) << 20;

//! The ranges of a render request: the command line (app/main.cpp) and a provenance manifest's
//! request (`aquarelle reproduce`, app/manifest.cpp) are checked against these same numbers, so a
//! manifest can ask for nothing the command line refuses (docs/limits.md).
namespace request_limits {
inline constexpr long long kMaxFrame = 10'000'000;         //!< --frame, --frames ends
inline constexpr long long kMaxFramesPerRun = 100'000;     //!< --frames A-B: B - A < this
inline constexpr double kMinFps = 0.001, kMaxFps = 10000.0;  //!< --fps
inline constexpr double kMaxOrbitDeg = 360.0;              //!< --orbit in [-this, this]
inline constexpr double kMaxViewPitchDeg = 89.0;           //!< --view pitch in [-this, this]
inline constexpr double kMinViewZoom = 0.05, kMaxViewZoom = 20.0;  //!< --view zoom
inline constexpr double kMaxViewPan = 20.0;  //!< --view pan in [-this, this] half-heights
inline constexpr long long kMaxSsaa = 4;                   //!< --ssaa in [1, this]
inline constexpr long long kMinSweepCount = 2, kMaxSweepCount = 1000;  //!< --sweep count
inline constexpr double kMaxSweepValue = 1e30;             //!< --sweep ends in [-this, this]
inline constexpr long long kMaxThreads = 1024;             //!< --threads
}  // namespace request_limits

//! What `aquarelle render` was asked (app/main.cpp parses it; docs in its --help).
struct RenderOptions {
    std::string scene, out, targets_dir, targets_png_dir, style;
    bool style_given = false;
    std::vector<std::string> sets, variants;
    std::vector<std::string> bypass;  //!< --bypass STEP, applied after --variant and --set
    std::vector<scene::SceneEdit> scene_edits;  //!< --scene-set POINTER=VALUE (scene files only)
    //! A library caller's change of the style's steps, applied as soon as it is loaded (before
    //! --variant, --set and --bypass): the Python module's Style.with_step. No CLI option sets it.
    std::function<void(stylize::Pipeline&)> edit_style;
    int width = 0, height = 0, ssaa = 1, threads = 0;
    int frame_first = 0, frame_last = 0;
    bool animation = false;    //!< --frames given
    bool frame_given = false;  //!< --frame given (refused together with --frames)
    double fps = 0;
    double orbit_deg = 0;  //!< --orbit: camera turned by frame x this about +Y through the bounds' centre
    //! --view YAW,PITCH,ZOOM[,PANX,PANY]: the camera turned by yaw degrees about +Y and pitch degrees
    //! about its right axis through the bounds' centre, then moved towards it to 1/zoom of its
    //! distance (orthographic: its extents scaled by 1/zoom), then moved along its own right and up
    //! axes by PANX, PANY half-heights of the view at the centre's depth (the centre lands at
    //! NDC (-PANX / aspect, -PANY)); after --orbit. The live view's mouse (`aquarelle serve`,
    //! docs/serve.md).
    double view_yaw = 0, view_pitch = 0, view_zoom = 1, view_pan_x = 0, view_pan_y = 0;
    bool has_pan() const { return view_pan_x != 0 || view_pan_y != 0; }
    bool has_view() const { return view_yaw != 0 || view_pitch != 0 || view_zoom != 1 || has_pan(); }
    //! --shard I/N (docs/shards.md): this run renders the items k (frame f - frame_first, or sweep
    //! index) with k mod N == I; the N shards together write exactly the unsharded run's files.
    int shard_index = 0, shard_count = 1;
    bool in_shard(int k) const { return k % shard_count == shard_index; }
    bool reference = false, quiet = false, allow_outside_files = false;
    bool neutral_control = false;
    //! Hand the sink every intermediate (--targets, --targets-png, the regression goldens); else
    //! intermediates are released after their last reader (stylize::RunOptions::release_dead).
    bool keep_intermediates = false;
    //! --row-groups: run the pipelines' row groups band by band (stylize::RunOptions::row_groups);
    //! the same bytes, a schedule for machines whose cache is smaller than a frame.
    bool row_groups = false;
    WorkingSpace working_space = WorkingSpace::Display;
    //! --antialias: coverage antialiasing of the silhouettes at ssaa 1 (docs/raster.md).
    raster::RenderSettings::Antialias antialias = raster::RenderSettings::Antialias::Coverage;
    //! --compression: of every PNG and EXR the render writes (--out, --targets, --targets-png).
    Compression compression = Compression::Fast;
    //! A live server's render (`aquarelle serve`): the scene comes from `preloaded` (a copy of
    //! what loading would return: no file is read) and nothing is released after the image (the
    //! next one reuses the paper and the buffer pool). `keep_loaded`: the job keeps the scene as
    //! loaded (RenderJob::loaded) for such renders.
    std::shared_ptr<const scene::SceneDesc> preloaded;
    bool live = false, keep_loaded = false;
    //! Live renders: the raster passes' scenes (abstracted foliage, layers, contours) of earlier
    //! renders of the same preloaded scene, by foliage parameters, so that a parameter change
    //! does not abstract the foliage again. Shared by the server's renders; guarded by its mutex.
    struct PassSceneMemo {
        struct Entry {
            std::shared_ptr<const raster::AbstractedScene> scene;
            scene::LayerTable layers;
            raster::ContourCache contours;
            std::vector<std::string> warnings;
        };
        //! Entries kept (the newest): a slider over a foliage parameter or a scene edit makes one
        //! per value, each the size of the abstracted scene.
        static constexpr std::size_t kMaxEntries = 4;
        std::mutex m;
        std::map<std::string, std::shared_ptr<const Entry>> entries;
        std::deque<std::string> order;  //!< keys, oldest first
        void put(const std::string& key, std::shared_ptr<const Entry> e) {
            if (!entries.count(key)) order.push_back(key);
            entries[key] = std::move(e);
            while (order.size() > kMaxEntries) {
                entries.erase(order.front());
                order.pop_front();
            }
        }
    };
    std::shared_ptr<PassSceneMemo> pass_memo;
    //! Live renders: what the previous image of the same view left — every target (G-buffer, paper,
    //! intermediates) and its compiled steps. When `key` (the server's: every option but the
    //! parameter values) is unchanged and the steps differ only in parameter values, run_render
    //! re-runs the pipeline from the first step whose values changed (stylize::RunOptions::
    //! first_step) instead of rasterizing and running every step; the bytes are the full run's
    //! (tests/app/serve_test.py compares with the CLI). Then it keeps this image's targets here.
    struct LiveFrame {
        std::string key;       //!< of the kept targets
        std::string key_next;  //!< of the render about to run (set by the caller)
        Targets targets;
        std::vector<stylize::CompiledStep> steps;
        bool valid = false;
        int first_step = 0;  //!< of the last render (0: everything ran)
    };
    LiveFrame* live_frame = nullptr;
    //! The content cache of loaded scenes and abstracted foliage (docs/cache.md): set by the CLI
    //! from the environment unless --no-cache; unset (library callers, tests, `reproduce`): no cache.
    std::optional<cache::Config> cache;
    //! --timings: each image's phases (PhaseTimes) on stderr and in its manifest sidecar.
    bool timings = false;
    //! `aquarelle grid` (app/grid.h): render these combinations of --variant/--set assignments
    //! from one G-buffer instead of one style (labels name each); empty for render.
    struct Combination {
        std::vector<std::string> variants, sets;
        std::string label;
    };
    std::vector<Combination> combinations;
    std::string sweep;  //!< "step.param" swept by --sweep
    double sweep_from = 0, sweep_to = 0;
    int sweep_count = 0;
};

//! Wall times in ms of a render's phases, in order ("load", "gbuffer", "stage LABEL", ...;
//! docs/performance.md "Where a render's time goes").
using PhaseTimes = std::vector<std::pair<std::string, double>>;

//! A scene and its styles, configured and validated: nothing is rendered before every name and
//! value has been checked.
struct RenderJob {
    RenderOptions options;
    scene::SceneDesc desc;
    raster::RenderSettings settings;
    bool stylize = false;                        //!< false: --style none (G-buffer colour only)
    std::vector<stylize::Pipeline> styles;       //!< one, or one per sweep value
    std::vector<stylize::CompiledPipeline> compiled;  //!< styles compiled (empty for --style none)
    std::vector<std::string> sweep_labels;       //!< "step.param=value" per sweep value, else {""}
    //! Per style with raster passes: the scene they draw (the foliage abstracted once per run when
    //! the style asks for it, LD06 §4.1), else null.
    std::vector<std::shared_ptr<const raster::AbstractedScene>> pass_scenes;
    //! Per style with raster passes: the LD06 layers of the scene they draw (scenes/layers.h).
    std::vector<scene::LayerTable> pass_layers;
    //! Per style with raster passes: the contour data of the scene they draw (raster/strokes.h).
    std::vector<raster::ContourCache> pass_contours;
    bool sweeping() const { return styles.size() > 1; }
    //! The scene's world bounds (the orbit's centre), kept when a one-shot render releases the
    //! scene after its G-buffer.
    scene::Bounds world_bounds;
    //! A one-shot render (one image, nothing kept: no --targets, no animation, no sweep) releases
    //! the scene's geometry after the G-buffer and the G-buffer targets after their last reader
    //! (issue 13 item 6: peak memory); such a job renders once.
    bool one_shot() const {
        return !options.live && !options.animation && !options.keep_intermediates && !sweeping() && options.frame_first == options.frame_last;
    }
    bool consumed = false;
    //! The files this job read, when its caller captured them (the Python module: a process that
    //! renders several jobs); unset: every file the process read (core/input.h inputs_read), what
    //! the CLI's manifests list.
    const InputCapture* inputs = nullptr;
    //! The scene as loaded, before the style's default control (RenderOptions::keep_loaded).
    std::shared_ptr<const scene::SceneDesc> loaded;
    //! prepare_render's phases: "load" (the scene, its meshes and textures) and "prepare" (styles,
    //! paper set-up, foliage abstraction).
    PhaseTimes prepare_phases;
    //! A bare model's paper, decoding on another thread while its scene loads (prepare_render;
    //! stylize::prefetch_paper); empty otherwise. Waits for the decode when the job ends.
    std::future<void> paper_prefetch;
    //! False when every style draws the scene with its own raster passes and reads no G-buffer
    //! target (ld06) and --targets was not asked: the G-buffer is then not rendered. With --targets
    //! it is rendered and written, so `aquarelle coherence` has the depth, normal and object ids
    //! of every frame (docs/coherence.md).
    //! The G-buffer targets to render (raster::RenderSettings::targets): those some style reads
    //! (optional inputs included, so no stage falls back), or all ten for --style none and
    //! --targets / a grid report (every target kept: the user asked for the G-buffer). Leaving the
    //! others out changes no value.
    std::uint32_t gbuffer_targets() const {
        if (!stylize || options.keep_intermediates || !options.targets_dir.empty()) return target::kAllGBufferTargets;
        std::uint32_t m = 0;
        for (const stylize::CompiledPipeline& c : compiled)
            for (const stylize::ExternalInput& x : c.external) m |= target::gbuffer_bit(x.target);
        return m;
    }
    bool needs_gbuffer() const {
        if (!stylize || !options.targets_dir.empty()) return true;
        for (const stylize::CompiledPipeline& c : compiled) {
            if (!c.has_passes) return true;
            for (const stylize::ExternalInput& x : c.external)
                if (target::gbuffer_channels(x.target.c_str()) > 0) return true;
        }
        return false;
    }
};

//! Where a job reports: progress (silenced by --quiet) and warnings (always shown by the CLI).
struct Reporter {
    std::function<void(const std::string&)> progress = [](const std::string&) {};
    std::function<void(const std::string&)> warning = [](const std::string&) {};
    //! What the user asked to see (--timings): shown even with --quiet.
    std::function<void(const std::string&)> info = [](const std::string&) {};
};

//! The camera of frame f: the job's camera orbited by f x options.orbit_deg degrees about the
//! vertical (+Y) axis through the centre of the scene's world bounds (the camera itself when 0).
scene::Camera frame_camera(const RenderJob& job, int frame);

//! Loads the scene and configures the style (scene-file values, automatic depth range, --variant,
//! --set, paper, working space, default art-direction, sweep values). Throws aq::Error.
RenderJob prepare_render(const RenderOptions& options, const Reporter& report);

//! Frame `frame`'s G-buffer as run_render renders it (the job's settings, camera and targets
//! mask), on its own: what the Python module's rasterize returns. Throws aq::Error.
Targets render_gbuffer(const RenderJob& job, int frame, std::vector<std::string>* warnings = nullptr);

//! Runs style `si` of the job on `targets` (a frame's G-buffer in them, seen by `camera`): its
//! intermediates and final target (styles[si].output) are added. Raster passes (LD06) draw the
//! job's scene through `camera`. `ro` says how (fusion, progress, ...); its exec and scene are
//! the job's. What run_render does for each style; throws aq::Error.
void run_style(const RenderJob& job, std::size_t si, const scene::Camera& camera, Targets& targets, stylize::RunOptions ro);

//! Lends the G-buffer's images to `run` (moved into a new set and back, also when `run` throws;
//! moves, not copies: their memory stays where it is):
//! returns the set without them — every target `run` added. `run` must not write the G-buffer's
//! images (an unfused pipeline run writes only new ones).
Targets lend_gbuffer(Targets& gbuffer, const std::function<void(Targets&)>& run);

//! Runs the job's (first) style on a frame's G-buffer without changing it: its images are lent to
//! the run (moved in and back: their memory stays where it is), the run unfused, so every
//! intermediate is a new image. Returns every target the style produced and "final", the image
//! `--out` receives (output_image). What the Python module's Style.run does (python/module.cpp).
Targets run_style_on(const RenderJob& job, Targets& gbuffer, int frame, stylize::RunOptions ro = {});

//! The image `--out` receives for `final_target` of `targets` (converted as run_render converts
//! it: linear working space to sRGB, a stylised painting without its alpha), as a copy.
ImageF output_image(const RenderJob& job, Targets& targets, const std::string& final_target);

//! One rendered image: all targets (G-buffer and every intermediate) and the final image as it
//! is written (display-encoded; opaque RGB for a stylised image).
struct RenderedImage {
    int frame = 0;
    int index = 0;                //!< the number replacing #### in paths (frame, or sweep index)
    std::size_t style_index = 0;  //!< into RenderJob::styles
    std::string tag;              //!< progress prefix, e.g. "[frame 3/24] "
    Targets& targets;
    std::string final_target;
    std::vector<double> step_ms;  //!< wall time of each pipeline step (stylize::RunOptions::step_ms)
    //! This image's phases: "paper", "gbuffer", "stage LABEL" per step, "convert".
    PhaseTimes phases;
    //! The image `--out` receives: the final target, converted where the output needs it (linear
    //! working space -> sRGB; a stylised painting written opaque, RGB: the RGB copy is made by the
    //! first call, see drop_alpha). Throws aq::Error after take_final_rgba().
    const ImageF& final_image();
    //! With drop_alpha and no RGB copy made: the final target itself (RGBA), moved out of
    //! `targets`, for a writer that leaves the alpha out (FrameWriter::File::drop_alpha): an
    //! animation's PNG frames are encoded from it without a full-frame copy (issue 13).
    ImageF take_final_rgba();
    ImageF converted;
    bool converted_ = false;
    bool drop_alpha = false;  //!< the output is the RGB of the RGBA final target (made lazily)
    bool taken_ = false;      //!< take_final_rgba() was called
};

//! Renders every frame x sweep value in order and calls sink for each. Throws aq::Error.
void run_render(RenderJob& job, const std::function<void(RenderedImage&)>& sink, const Reporter& report);

}  // namespace aq::app
