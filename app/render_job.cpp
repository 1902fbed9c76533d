// app/render_job.cpp — see render_job.h.
#include "app/render_job.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include <glm/gtc/matrix_transform.hpp>

#include "app/cli_args.h"
#include "scenes/scene_cache.h"
#include "scenes/scene_file.h"
#include "stylize/scene_inputs.h"

namespace aq::app {

namespace {

using stylize::split_step_param;

double ms_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

scene::Camera frame_camera(const RenderJob& job, int frame) {
    scene::Camera cam = job.desc.camera;
    const RenderOptions& o = job.options;
    const double deg = o.orbit_deg * double(frame);
    if (deg == 0.0 && !o.has_view()) return cam;
    const scene::Bounds& b = job.world_bounds;
    if (!b.valid) return cam;
    constexpr double kPi = 3.14159265358979323846;
    const glm::vec3 c = 0.5f * (b.min + b.max);
    // world' = R(c) world: the camera sees the scene turned by -a about `axis` through c, i.e. the
    // camera moves by +a.
    auto turn = [&](double a, glm::vec3 axis) {
        if (a == 0.0) return;
        const glm::mat4 t = glm::translate(glm::mat4(1.0f), c) * glm::rotate(glm::mat4(1.0f), float(-a * kPi / 180.0), axis) *
                            glm::translate(glm::mat4(1.0f), -c);
        cam.view = cam.view * t;  // the product as --orbit always formed it: the same bits
    };
    turn(deg + o.view_yaw, glm::vec3(0, 1, 0));
    // The camera's right axis in world space: the first row of the view's rotation.
    turn(-o.view_pitch, glm::normalize(glm::vec3(cam.view[0][0], cam.view[1][0], cam.view[2][0])));
    if (o.view_zoom != 1.0) {
        if (cam.orthographic) {
            cam.xmag = float(double(cam.xmag) / o.view_zoom);
            cam.ymag = float(double(cam.ymag) / o.view_zoom);
        } else {
            // Dolly along the line to the centre: in eye space everything moves by (1 - 1/zoom) of
            // the centre's offset; near and far move with it (kept in front of the camera).
            const glm::vec3 ce = glm::vec3(cam.view * glm::vec4(c, 1.0f));
            const float k = float(1.0 - 1.0 / o.view_zoom);
            cam.view = glm::translate(glm::mat4(1.0f), -k * ce) * cam.view;
            const float shift = -k * ce.z;  // the eye moves this far forward (ce.z < 0 in front)
            cam.znear = std::max(cam.znear - shift, cam.znear * 1e-3f);
            cam.zfar = std::max(cam.zfar - shift, cam.znear * 2.0f);
        }
    }
    if (o.has_pan()) {
        // The view's half-height at the centre's depth, then a move in the camera's own plane.
        const glm::vec3 ce = glm::vec3(cam.view * glm::vec4(c, 1.0f));
        const double half = cam.orthographic ? double(cam.ymag) : double(-ce.z) * std::tan(0.5 * double(cam.yfov));
        const glm::vec3 t(float(o.view_pan_x * half), float(o.view_pan_y * half), 0.0f);
        cam.view = glm::translate(glm::mat4(1.0f), -t) * cam.view;
    }
    return cam;
}

namespace {

//! The style as the job runs it: the preset or file (the bare model's early one), the Python
//! edit, the scene's values (stylize::apply_scene_inputs), the scene file's style values and
//! variants, --variant, --set, --bypass, the scene file's paper and substrate colour.
stylize::Pipeline configure_style(const RenderOptions& o, const scene::SceneDesc& desc, const std::string& style,
                                  std::optional<stylize::Pipeline>& early_pipeline, const std::string& early_style) {
    // A bare model has no scene file to name another style: the one prepare_render loaded early.
    stylize::Pipeline pipeline =
        early_pipeline && style == early_style ? std::move(*early_pipeline) : stylize::load_pipeline(style);
    if (o.edit_style) o.edit_style(pipeline);
    std::optional<std::pair<float, float>> framed_depth_range;
    if (desc.camera_auto) framed_depth_range = std::make_pair(desc.camera.znear, desc.camera.zfar);
    stylize::apply_scene_inputs(pipeline, stylize::SceneInputs(desc.scene, framed_depth_range));
    if (!o.style_given || o.style == desc.style) {
        for (auto& [k, v] : desc.style_variant) stylize::set_variant(pipeline, k + "=" + v);
        for (auto& [k, v] : desc.style_set) {
            const auto [step, param] = split_step_param(k);
            stylize::set_param_value(pipeline, step, param, v,
                                     "scene file '" + o.scene + "' style value '" + k + "'");
        }
    }
    for (auto& v : o.variants) stylize::set_variant(pipeline, v);
    for (auto& s : o.sets) stylize::set_param(pipeline, s);
    for (auto& b : o.bypass) stylize::bypass_step(pipeline, b);
    if (!desc.paper.empty()) {
        pipeline.paper.file = desc.paper;
        pipeline.has_paper = true;
    }
    if (desc.substrate_color_set) pipeline.substrate_color = desc.substrate_color;
    return pipeline;
}

//! job.styles: the style once, or one per --sweep value or grid combination (every value checked
//! before rendering), with their labels.
void expand_styles(RenderJob& job, const RenderOptions& o, const stylize::Pipeline& pipeline) {
    // A sweep renders the G-buffer once and reruns the style for each value of one parameter.
    job.styles = {pipeline};
    job.sweep_labels = {""};
    if (!o.sweep.empty()) {
        if (!job.stylize) throw cli::UsageError("render: --sweep needs a style (not --style none)");
        job.styles.clear();
        job.sweep_labels.clear();
        const auto [step, param] = split_step_param(o.sweep);
        for (int i = 0; i < o.sweep_count; ++i) {
            const double t = double(i) / double(o.sweep_count - 1);
            const double v = o.sweep_from + (o.sweep_to - o.sweep_from) * t;
            stylize::Pipeline p = pipeline;
            stylize::set_param_value(p, step, param, v, "--sweep");  // every value checked before rendering
            char label[256];
            std::snprintf(label, sizeof label, "%s=%.9g", o.sweep.c_str(), v);
            job.styles.push_back(std::move(p));
            job.sweep_labels.push_back(label);
        }
    }
    if (!o.combinations.empty()) {
        if (!job.stylize) throw cli::UsageError("grid: combinations need a style (not --style none)");
        if (!o.sweep.empty()) throw cli::UsageError("grid: combinations and --sweep cannot be combined");
        job.styles.clear();
        job.sweep_labels.clear();
        for (const RenderOptions::Combination& c : o.combinations) {
            stylize::Pipeline p = pipeline;  // every assignment checked before rendering
            for (const std::string& v : c.variants) stylize::set_variant(p, v);
            for (const std::string& a : c.sets) stylize::set_param(p, a);
            job.styles.push_back(std::move(p));
            job.sweep_labels.push_back(c.label);
        }
    }
}

//! The scene the raster passes draw, per compiled style: built once (the implicit surface is
//! view-independent), through the content cache and, for the live server's preloaded scene, its
//! memo; its warnings and what the foliage became are reported.
void prepare_pass_scenes(RenderJob& job, const RenderOptions& o, cache::Store* store, const std::string& scene_key,
                         const std::string& default_control_applied, const Reporter& report) {
    for (const stylize::CompiledPipeline& c : job.compiled) {
        if (!c.has_passes) {
            job.pass_scenes.emplace_back();
            job.pass_layers.emplace_back();
            job.pass_contours.emplace_back();
            continue;
        }
        raster::FoliageParams fp = c.foliage;
        fp.abstract = c.has_foliage && c.foliage.abstract;
        const scene::SceneDesc& d = job.desc;  // the scene file's values win over the style's
        if (d.foliage_threshold) fp.threshold = *d.foliage_threshold, fp.fit = false;  // a chosen T is used as is
        if (d.foliage_radius) fp.radius = *d.foliage_radius;
        if (d.foliage_relative) fp.relative = *d.foliage_relative;
        if (d.foliage_cells_per_radius) fp.cells_per_radius = *d.foliage_cells_per_radius;
        if (d.foliage_technique) fp.technique = raster::parse_technique(*d.foliage_technique);
        const auto t0 = std::chrono::steady_clock::now();
        std::vector<std::string> warnings;
        // A live render of the server's preloaded scene: the memo (the scene file's edits, the
        // default control and the parameters name the entry; the server drops the memo when the
        // files change).
        const std::string memo_key = o.pass_memo && o.preloaded
                                         ? "edits " + scene::edits_key(o.scene_edits) + "default control " + default_control_applied +
                                               "\n" + raster::foliage_params_key(fp)
                                         : std::string();
        std::shared_ptr<const RenderOptions::PassSceneMemo::Entry> memo;
        if (!memo_key.empty()) {
            std::lock_guard<std::mutex> lock(o.pass_memo->m);
            if (auto it = o.pass_memo->entries.find(memo_key); it != o.pass_memo->entries.end()) memo = it->second;
        }
        if (!memo) {
            auto e = std::make_shared<RenderOptions::PassSceneMemo::Entry>();
            std::vector<std::string> notes;
            e->scene = raster::abstract_foliage_cached(job.desc.scene, fp, job.settings.exec, &e->warnings,
                                                       store, scene_key, &notes);
            for (auto& n : notes) report.progress("cache: " + n);
            e->layers = raster::abstracted_layer_table(job.desc.scene, *e->scene);
            e->contours = raster::build_contour_cache(e->scene->scene);
            memo = e;
            if (!memo_key.empty()) {
                std::lock_guard<std::mutex> lock(o.pass_memo->m);
                o.pass_memo->put(memo_key, memo);
            }
        }
        warnings = memo->warnings;
        job.pass_scenes.push_back(memo->scene);
        job.pass_layers.push_back(memo->layers);
        job.pass_contours.push_back(memo->contours);
        for (auto& w : warnings) report.warning(w);
        if (const auto& a = job.pass_scenes.back(); a->abstracted) {
            char fit[160];
            std::snprintf(fit, sizeof fit, " (T = %.4g, r = %.4g, %.0f %% of the leaves' vertices inside, silhouette %.2f x the leaves')",
                          double(a->threshold), double(a->radius), 100.0 * double(a->surface.inside_fraction), double(a->crown_ratio));
            report.progress("foliage: " + std::to_string(a->foliage_triangles) + " triangles abstracted to an implicit surface of " +
                            std::to_string(a->surface.indices.size() / 3) + fit + " in " + std::to_string(int(ms_since(t0))) + " ms");
        } else if (a->texture_technique) {
            char why[160];
            if (a->crown_ratio > 0)
                std::snprintf(why, sizeof why, "a sparse crown: the implicit surface's silhouette is %.2f x the leaves'", double(a->crown_ratio));
            else
                std::snprintf(why, sizeof why, "median leaf %.1f %% of the plant height, %zu foliage triangles", 100.0 * double(a->leaf_share),
                              a->foliage_triangles);
            report.progress("foliage: " + std::to_string(a->foliage_triangles) +
                            " triangles painted as modelled with intensity-texture detail (LD06 §4.3; " + why + ")");
        }
    }
}

}  // namespace

RenderJob prepare_render(const RenderOptions& o, const Reporter& report) {
    const auto t0 = std::chrono::steady_clock::now();
    RenderJob job;
    job.options = o;
    // A bare .gltf/.glb has no scene file to name its style or paper: its paper is known now and
    // decodes on a second thread while the model loads (issue 13 item 3: the one-shot render's
    // single-threaded stretches). The same file, decoded once: prepare_paper waits for it.
    // The style is loaded once: its pipeline is used below.
    const std::string scene_ext = lower_extension(o.scene);
    const std::string early_style = o.style_given ? o.style : "wc18";
    std::optional<stylize::Pipeline> early_pipeline;
    if ((scene_ext == ".gltf" || scene_ext == ".glb") && early_style != "none") {
        early_pipeline = stylize::load_pipeline(early_style);
        if (early_pipeline->has_paper) job.paper_prefetch = stylize::prefetch_paper(early_pipeline->paper);
    }
    scene::LoadOptions load_options;
    load_options.allow_outside_files = o.allow_outside_files;
    load_options.edits = o.scene_edits;
    // A scene file naming its paper: the same, decoded while the model loads. The layout is the
    // style's when --style names one, else the presets' (every preset is "mnpr"; a scene whose own
    // style file reads its paper in another layout decodes it again, and the prefetch is wasted).
    if (!early_pipeline && early_style != "none")
        load_options.paper_known = [&job, &o](const std::string& file) {
            try {
                stylize::PaperSpec spec = o.style_given ? stylize::load_pipeline(o.style).paper : stylize::PaperSpec{};
                spec.file = file;
                job.paper_prefetch = stylize::prefetch_paper(spec);
            } catch (const Error&) {
                // a bad --style file is reported below, after the scene, as without the prefetch
            }
        };
    // Loading runs parallel loops too (texture decodes, mip levels): within --threads, as the frame.
    std::optional<cache::Store> store;
    if (o.cache) store.emplace(*o.cache);
    scene::SceneCacheUse cache_use;
    with_arena(o.reference ? Exec::reference() : Exec::fast(o.threads), [&] {
        if (o.preloaded) {
            job.desc = *o.preloaded;
            if (!job.desc.paper.empty() && load_options.paper_known) load_options.paper_known(job.desc.paper);
        } else {
            job.desc = scene::load_scene_cached(o.scene, load_options, store ? &*store : nullptr, &cache_use);
        }
    });
    if (o.keep_loaded) job.loaded = std::make_shared<const scene::SceneDesc>(job.desc);
    job.prepare_phases.emplace_back("load", ms_since(t0));
    const auto t_prepare = std::chrono::steady_clock::now();
    scene::SceneDesc& desc = job.desc;
    for (auto& n : cache_use.notes) report.progress("cache: " + n);
    if (!o.preloaded)
        for (auto& w : desc.scene.warnings) report.warning(w);
    report.progress("scene: " + o.scene + " (" + std::to_string(desc.scene.triangle_count()) + " triangles) loaded in " +
        std::to_string(int(ms_since(t0))) + " ms" + (cache_use.hit ? " from the cache" : ""));
    // The key of the scene as the raster passes get it (the default control below changes it).
    std::string scene_key = cache_use.key;
    std::string default_control_applied;  // the rules' text when they changed the scene

    raster::RenderSettings& rs = job.settings;
    rs.width = o.width ? o.width : (desc.width ? desc.width : 1280);
    rs.height = o.height ? o.height : (desc.height ? desc.height : 720);
    rs.ssaa = o.ssaa;
    rs.antialias = o.antialias;
    rs.fps = float(o.fps > 0 ? o.fps : desc.fps);
    rs.exec = o.reference ? Exec::reference() : Exec::fast(o.threads);
    check_image_size(rs.width, rs.height, "output");
    check_image_size(rs.width * rs.ssaa, rs.height * rs.ssaa, "supersampled render (--ssaa)");
    const float aspect = float(rs.width) / float(rs.height);
    if (desc.camera_auto && aspect != desc.auto_aspect)  // reframe for the size actually rendered
        desc.camera = scene::frame_bounds(desc.scene.world_bounds(), aspect, desc.auto_view_dir, desc.auto_yfov);

    const std::string style = o.style_given ? o.style : (desc.style.empty() ? "wc18" : desc.style);
    job.stylize = style != "none";
    stylize::Pipeline pipeline;  // configured after the camera: depth range may follow it
    if (job.stylize) {
        pipeline = configure_style(o, desc, style, early_pipeline, early_style);
    } else if (!o.sets.empty() || !o.variants.empty() || !o.bypass.empty()) {
        throw cli::UsageError("render: --set/--variant/--bypass need a style (not --style none)");
    }

    rs.substrate_color = job.stylize ? pipeline.substrate_color : desc.substrate_color;
    rs.working_space = o.working_space;
    if (o.working_space == WorkingSpace::Linear) {
        // The paper colour is given as a display value; the maths and the G-buffer run in linear.
        for (int k = 0; k < 3; ++k) rs.substrate_color[k] = srgb_to_linear(rs.substrate_color[k]);
        if (job.stylize) pipeline.substrate_color = rs.substrate_color;
    }
    if (job.stylize) {
        // WC17 §3.2: pigment turbulence is object-space in a pipeline without an image-space
        // density step (wc16, wc17): the material applies eq. 6 from ctrl.pigment.b.
        if (!stylize::has_image_space_turbulence(pipeline)) rs.turbulence = raster::RenderSettings::Turbulence::ObjectSpace;
        // Default art-direction (docs/look.md) for primitives without painted control, unless the
        // scene file has its own rules or --control neutral.
        if (!o.neutral_control && !desc.control_rules && !pipeline.default_control.empty()) {
            const auto rules =
                scene::parse_control_rules(pipeline.default_control, "style '" + pipeline.name + "' default_control");
            const std::size_t n = scene::apply_default_control(desc.scene, rules);
            if (n) default_control_applied = pipeline.default_control;
            if (n && !scene_key.empty()) scene_key = cache::key({scene_key, "default_control", pipeline.default_control});
            if (n) report.progress("default control of style " + pipeline.name + " on " + std::to_string(n) + " primitive(s)");
        }
    }

    expand_styles(job, o, pipeline);
    // Compiled once per run (every name, value and binding resolved and checked); each frame then
    // only checks the G-buffer it is given.
    for (const stylize::Pipeline& p : job.styles)
        if (job.stylize) job.compiled.push_back(stylize::compile_pipeline(p));
    prepare_pass_scenes(job, o, store ? &*store : nullptr, scene_key, default_control_applied, report);
    job.world_bounds = job.desc.scene.world_bounds();
    job.prepare_phases.emplace_back("prepare", ms_since(t_prepare));
    return job;
}

namespace {

//! The image --out receives: the final target, converted where the output needs it.
void convert_final(RenderedImage& img, const ImageF& fin, bool linear, bool drop_alpha) {
    if (!linear && !drop_alpha) return;
    if (!linear && fin.channels() == 4) {  // the usual case: RGB of the RGBA target, when asked
        img.drop_alpha = true;
        return;
    }
    const int nc = drop_alpha ? 3 : fin.channels();
    ensure_output(img.converted, fin.width(), fin.height(), nc);
    const std::size_t n = std::size_t(fin.width()) * std::size_t(fin.height());
    const int sc = fin.channels();
    const float* s = fin.data();
    float* d = img.converted.data();
    for (std::size_t i = 0; i < n; ++i)
        for (int c = 0; c < nc; ++c) {
            const float v = s[i * std::size_t(sc) + std::size_t(c)];
            // output transform linear -> sRGB on colour, never on alpha
            d[i * std::size_t(nc) + std::size_t(c)] = linear && c != 3 ? linear_to_srgb(std::clamp(v, 0.0f, 1.0f)) : v;
        }
    img.converted_ = true;
}

}  // namespace

const ImageF& RenderedImage::final_image() {
    if (taken_) throw Error("render job: the final image was handed to the writer");
    if (drop_alpha && !converted_) {
        rgb_of(targets.get(final_target), converted);
        converted_ = true;
    }
    return converted_ ? converted : targets.get(final_target);
}

namespace {

//! Moves the G-buffer targets between two sets — the rasterizer's (reused by render_gbuffer_into
//! when it holds exactly them) and a frame's (G-buffer + paper + intermediates, reused by
//! run_pipeline with reuse_outputs). Moves, not copies.
void move_gbuffer(Targets& from, Targets& to) {
    for (const target::GBufferTarget& g : target::kGBufferLayout)
        if (from.has(g.name)) {
            to.set(g.name, std::move(from.get_mut(g.name)));
            from.erase(g.name);
        }
}

}  // namespace

Targets lend_gbuffer(Targets& gbuffer, const std::function<void(Targets&)>& run) {
    Targets t;
    move_gbuffer(gbuffer, t);
    try {
        run(t);
    } catch (...) {
        move_gbuffer(t, gbuffer);
        throw;
    }
    move_gbuffer(t, gbuffer);
    return t;
}

Targets run_style_on(const RenderJob& job, Targets& gbuffer, int frame, stylize::RunOptions ro) {
    ro.fuse = ro.in_place = ro.release_dead = ro.reuse_outputs = false;  // the G-buffer's images stay as they are
    Targets t = lend_gbuffer(gbuffer, [&](Targets& set) { run_style(job, 0, frame_camera(job, frame), set, ro); });
    ImageF fin = output_image(job, t, job.styles.at(0).output);
    t.set("final", std::move(fin));
    return t;
}

ImageF output_image(const RenderJob& job, Targets& targets, const std::string& final_target) {
    RenderedImage img{job.options.frame_first, job.options.frame_first, 0, "", targets, final_target, {}, {}, {}, false};
    const ImageF& fin = targets.get(final_target);
    convert_final(img, fin, job.options.working_space == WorkingSpace::Linear, job.stylize && fin.channels() == 4);
    return img.final_image();
}

ImageF RenderedImage::take_final_rgba() {
    if (!drop_alpha || converted_ || taken_) throw Error("render job: no RGBA final image to hand over");
    ImageF img = std::move(targets.get_mut(final_target));
    targets.erase(final_target);
    taken_ = true;
    return img;
}

void run_style(const RenderJob& job, std::size_t si, const scene::Camera& camera, Targets& targets, stylize::RunOptions ro) {
    const raster::RenderSettings& rs = job.settings;
    ro.exec = rs.exec;
    // Raster passes (LD06) draw the scene themselves, at the output size's scales.
    std::optional<raster::PassScene> pass_scene;
    raster::PassFrameCache pass_frames;  // this frame's prepared geometry, shared by its passes
    if (job.compiled.at(si).has_passes) {
        const raster::AbstractedScene& a = *job.pass_scenes.at(si);
        pass_scene = raster::make_pass_scene(a.scene, camera, rs.width, rs.height);
        pass_scene->layers = &job.pass_layers[si];
        pass_scene->contours = &job.pass_contours[si];
        pass_scene->frames = &pass_frames;
        if (a.abstracted) {
            pass_scene->foliage_surface = &a.surface;
            pass_scene->plant_height = a.height;
        }
        pass_scene->foliage_detail = a.texture_technique;
        ro.scene = &*pass_scene;
    }
    stylize::run_pipeline(job.compiled[si], targets, ro);
}

Targets render_gbuffer(const RenderJob& job, int frame, std::vector<std::string>* warnings) {
    raster::RenderSettings rs = job.settings;
    rs.targets = job.gbuffer_targets();
    rs.frame = frame;
    Targets t;
    raster::render_gbuffer_into(t, job.desc.scene, frame_camera(job, frame), rs, warnings);
    return t;
}

namespace {

//! Where a live render (RenderOptions::LiveFrame) continues the previous image: from the first
//! step whose parameters changed, on the previous image's targets (moved into frame_targets), when
//! the pipeline's structure is the same. {0, false}: from the start.
struct LiveStart {
    int first_step = 0;
    bool continued = false;
};
LiveStart live_start(const RenderJob& job, RenderOptions::LiveFrame* live, Targets& frame_targets) {
    LiveStart st;
    if (!(live && live->valid && job.stylize && job.compiled.size() == 1 && !job.sweeping() && live->key == live->key_next &&
          live->steps.size() == job.compiled[0].steps.size()))
        return st;
    const auto& now = job.compiled[0].steps;
    std::size_t k = 0;
    bool same_structure = true;
    for (std::size_t i = 0; i < now.size(); ++i) {
        const stylize::CompiledStep &a = live->steps[i], &b = now[i];
        same_structure = same_structure && a.variant == b.variant && a.inputs == b.inputs && a.outputs == b.outputs;
        if (a.params == b.params && k == i) ++k;
    }
    if (same_structure) {
        st = {int(k), true};
        frame_targets = std::move(live->targets);
    }
    return st;
}

//! The frame's G-buffer into `gbuffer`; a one-shot job then releases its scene (its memory goes
//! to the stylization) unless a style draws raster passes.
void render_frame_gbuffer(RenderJob& job, Targets& gbuffer, const scene::Camera& camera, bool one_shot_memory,
                          const std::string& prefix, std::chrono::steady_clock::time_point frame_start, PhaseTimes& phases,
                          const Reporter& report) {
    const raster::RenderSettings& rs = job.settings;
    std::vector<std::string> warnings;
    const auto tg = std::chrono::steady_clock::now();
    raster::render_gbuffer_into(gbuffer, job.desc.scene, camera, rs, &warnings);
    for (auto& w : warnings) report.warning(w);
    bool passes = false;
    for (const stylize::CompiledPipeline& c : job.compiled) passes = passes || c.has_passes;
    if (one_shot_memory && !passes) {
        job.desc.scene = scene::Scene{};
        job.consumed = true;
#ifdef __GLIBC__
        malloc_trim(0);  // give the freed heap back: the peak is 9 MB lower (docs/performance.md)
#endif
    }
    phases.emplace_back("gbuffer", ms_since(tg));
    report.progress(prefix + "G-buffer " + std::to_string(rs.width) + "x" + std::to_string(rs.height) + " in " +
                    std::to_string(int(ms_since(frame_start))) + " ms");
}

//! How a style runs in this job: intermediates released, fused, in place and in row groups unless
//! they are kept (or a live render continues from first_step); progress per stage for one image.
stylize::RunOptions style_run_options(const RenderOptions& o, RenderOptions::LiveFrame* live, int first_step, bool sweeping,
                                      bool one_shot_memory, const Reporter& report) {
    stylize::RunOptions ro;
    ro.reuse_outputs = !sweeping;
    ro.release_dead = !o.keep_intermediates;
    ro.fuse = !o.keep_intermediates;  // fused steps write no intermediate (stage.h Fusion)
    ro.in_place = ro.fuse;            // nor do in-place steps keep their input (StageVariant::in_place_input)
    ro.row_groups = o.row_groups;
    ro.release_inputs = one_shot_memory;
    if (live) {
        ro.first_step = first_step;
        ro.fuse = ro.in_place = ro.row_groups = ro.release_dead = false;
    }
    if (!o.quiet && !o.animation && !sweeping)
        ro.progress = [&report](int i, int n, const std::string& step) {
            report.progress("  stage " + std::to_string(i + 1) + "/" + std::to_string(n) + ": " + step);
        };
    return ro;
}

}  // namespace

void run_render(RenderJob& job, const std::function<void(RenderedImage&)>& sink, const Reporter& report) {
    const RenderOptions& o = job.options;
    raster::RenderSettings& rs = job.settings;
    rs.targets = job.gbuffer_targets();
    const bool sweeping = job.sweeping();
    const int nframes = o.frame_last - o.frame_first + 1;
    // Kept from frame to frame (issue 13): the G-buffer's memory (render_gbuffer_into), and for one
    // style the paper, every intermediate and the converted final image (run_pipeline with
    // reuse_outputs), so a frame neither allocates nor first-touches ~0.5 GB at 1080p, nor prepares
    // the paper again. Every target is written again each frame, except the G-buffer tiles that held
    // only background in the previous frame and still do (docs/raster.md "Background tiles kept
    // between frames"): the bytes are those of a fresh render (tests/app/golden_test.cpp
    // GoldenAnimation.*).
    if (job.consumed) throw Error("render job: a one-shot job renders once (its scene was released)");
    // One image, nothing kept (RenderJob::one_shot): buffers released as soon as they are dead,
    // a smaller image pool (restored on return), the scene released after its G-buffer.
    const bool one_shot_memory = job.one_shot();
    struct PoolLimit {
        std::size_t previous;
        bool set;
        ~PoolLimit() {
            if (set) set_image_pool_limit(previous);
        }
    } pool_limit{one_shot_memory ? set_image_pool_limit(kOneShotPoolBytes) : 0, one_shot_memory};
    Targets gbuffer, frame_targets;
    ImageF converted;
    // A live render continuing the previous image (RenderOptions::LiveFrame): from which step.
    RenderOptions::LiveFrame* live = o.live_frame;
    const LiveStart start = live_start(job, live, frame_targets);
    const int first_step = start.first_step;
    const bool continued = start.continued;
    if (live) {
        live->valid = false;  // until this render completes
        live->first_step = first_step;
    }
    for (int f = o.frame_first; f <= o.frame_last; ++f) {
        if (o.animation && !o.in_shard(f - o.frame_first)) continue;  // another shard's frame
        const auto tf = std::chrono::steady_clock::now();
        const std::string prefix =
            o.animation ? "[frame " + std::to_string(f - o.frame_first + 1) + "/" + std::to_string(nframes) + "] " : "";
        rs.frame = f;
        const scene::Camera camera = frame_camera(job, f);
        PhaseTimes phases;
        if (!continued && one_shot_memory && job.stylize && job.compiled[0].has_paper && !job.compiled[0].has_passes && job.needs_gbuffer()) {
            // One-shot: the paper first, while nothing else large is alive; the decoded file is
            // then dropped, so its decoding is not on top of the G-buffer (issue 13 item 6).
            frame_targets.set(stylize::kPaperTarget, stylize::prepare_paper(job.compiled[0].paper, rs.width, rs.height, rs.exec));
            stylize::clear_paper_cache();
            image_pool_release();  // the decoded file's buffer: no later image has its size
            phases.emplace_back("paper", ms_since(tf));
        }
        if (job.needs_gbuffer() && !continued)
            render_frame_gbuffer(job, gbuffer, camera, one_shot_memory, prefix, tf, phases, report);

        for (std::size_t si = 0; si < job.styles.size(); ++si) {
            if (sweeping && !o.in_shard(int(si))) continue;  // another shard's sweep value
            const stylize::Pipeline& style = job.styles[si];
            const std::string tag = sweeping ? "[sweep " + std::to_string(si + 1) + "/" +
                                                   std::to_string(job.styles.size()) + " " + job.sweep_labels[si] + "] "
                                             : prefix;
            // A sweep runs several styles on one G-buffer: each gets a copy. One style takes the
            // G-buffer's images into the frame's set and gives them back after the sink.
            Targets sweep_targets;
            if (sweeping) sweep_targets = gbuffer;
            else move_gbuffer(gbuffer, frame_targets);
            Targets& targets = sweeping ? sweep_targets : frame_targets;
            std::string final_name = target::kColor;
            std::vector<double> step_ms;
            if (job.stylize) {
                const auto ts = std::chrono::steady_clock::now();
                std::vector<std::string> step_warnings;
                stylize::RunOptions ro = style_run_options(o, live, first_step, sweeping, one_shot_memory, report);
                ro.warnings = &step_warnings;
                ro.step_ms = &step_ms;
                run_style(job, si, camera, targets, ro);
                for (auto& w : step_warnings) report.warning(w);
                final_name = style.output;
                report.progress(tag + "style " + style.name + " (" + std::to_string(style.steps.size()) + " stages) in " +
                    std::to_string(int(ms_since(ts))) + " ms");
            }
            PhaseTimes image_phases = phases;  // a sweep's images share the frame's G-buffer phases
            if (job.stylize)
                for (std::size_t i = 0; i < step_ms.size() && i < job.compiled[si].steps.size(); ++i)
                    image_phases.emplace_back("stage " + job.compiled[si].steps[i].label, step_ms[i]);
            RenderedImage img{f, sweeping ? int(si) : f, si, tag, targets, final_name, std::move(step_ms), std::move(image_phases),
                              std::move(converted), false};
            const ImageF& fin = targets.get(final_name);
            // A stylised image is a painting on its paper: written opaque (RGB). The G-buffer
            // colour (--style none) keeps its coverage alpha for compositing.
            const auto tc = std::chrono::steady_clock::now();
            convert_final(img, fin, o.working_space == WorkingSpace::Linear, job.stylize && fin.channels() == 4);
            img.phases.emplace_back("convert", ms_since(tc));
            sink(img);
            converted = std::move(img.converted);
            if (live) {
                live->targets = std::move(targets);  // G-buffer included: the next image may start past it
                live->steps = job.compiled[0].steps;
                live->key = live->key_next;
                live->valid = true;
                continue;
            }
            if (!sweeping) move_gbuffer(frame_targets, gbuffer);
        }
    }
}

}  // namespace aq::app
