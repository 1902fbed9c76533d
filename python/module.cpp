// python/module.cpp — the `aquarelle` Python module's native part, `aquarelle._aquarelle`
// (pybind11; docs/python.md). Every call goes through the library the CLI runs (app/render_job.h:
// prepare_render, render_gbuffer, run_style, render_to_files), so what Python gets is what
// `aquarelle render` computes; targets come out as read-only NumPy views of the library's images
// (no copy), each keeping its owner alive. The GIL is released while C++ works.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "app/coherence.h"
#include "app/render_files.h"
#include "app/render_job.h"
#include "core/cache.h"
#include "core/compare.h"
#include "core/input.h"
#include "core/io.h"
#include "core/json_file.h"
#include "core/targets.h"
#include "raster/vertex.h"
#include "scenes/scene_cache.h"
#include "stylize/pipeline.h"
#include "stylize/stage.h"

namespace py = pybind11;

namespace aq::python {
namespace {

// --- values in and out ---------------------------------------------------------------------------

//! A read-only NumPy view (H x W x C float32) of `img`, kept alive by `owner`.
py::array view_of(const ImageF& img, py::handle owner) {
    const py::ssize_t h = img.height(), w = img.width(), c = img.channels();
    const py::ssize_t f = sizeof(float);
    py::array a(py::dtype::of<float>(), {h, w, c}, {w * c * f, c * f, f}, img.data(), owner);
    a.attr("setflags")(py::arg("write") = false);
    return a;
}

//! An image from a NumPy array: float32, H x W or H x W x C (C = `channels` when given), any
//! strides (copied), finite values, a size the library accepts. Throws aq::Error naming `what`.
ImageF image_from(const py::array& a, const std::string& what, int channels = 0) {
    if (!a.dtype().is(py::dtype::of<float>()))
        throw Error(what + ": expected a float32 array, got " + std::string(py::str(a.dtype())));
    if (a.ndim() != 2 && a.ndim() != 3) throw Error(what + ": expected H x W or H x W x C, got " + std::to_string(a.ndim()) + " dimensions");
    const py::ssize_t h = a.shape(0), w = a.shape(1), c = a.ndim() == 3 ? a.shape(2) : 1;
    if (h <= 0 || w <= 0 || c <= 0) throw Error(what + ": empty array");
    if (h > kMaxImageSide || w > kMaxImageSide) throw Error(what + ": " + std::to_string(w) + " x " + std::to_string(h) + " is larger than " + std::to_string(kMaxImageSide) + " on a side");
    check_image_size(int(w), int(h), what);
    if (channels && c != channels)
        throw Error(what + ": expected " + std::to_string(channels) + " channel(s), got " + std::to_string(c));
    if (c > 4) throw Error(what + ": at most 4 channels, got " + std::to_string(c));
    const auto cont = py::array_t<float, py::array::c_style>::ensure(a);  // a copy when strided
    if (!cont) throw Error(what + ": cannot read the array");
    ImageF img{int(w), int(h), int(c)};
    const float* src = cont.data();
    float* dst = img.data();
    for (std::size_t i = 0, n = img.num_values(); i < n; ++i) {
        if (!std::isfinite(src[i])) {
            const std::size_t px = i / std::size_t(c);
            throw Error(what + ": non-finite value at (" + std::to_string(px % std::size_t(w)) + ", " + std::to_string(px / std::size_t(w)) + ")");
        }
        dst[i] = src[i];
    }
    return img;
}

std::string value_text(const py::handle& v, const std::string& what) {
    if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
    if (py::isinstance<py::int_>(v) || py::isinstance<py::float_>(v)) {
        const double d = v.cast<double>();
        if (!std::isfinite(d)) throw Error(what + ": must be finite");
        return py::str(v).cast<std::string>();
    }
    if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
        std::string t = "[";
        bool first = true;
        for (const py::handle& x : v) {
            t += (first ? "" : ",") + value_text(x, what);
            first = false;
        }
        return t + "]";
    }
    throw Error(what + ": expected a number, a bool or a list of numbers");
}

std::string number_text(double v, const std::string& what) {
    if (!std::isfinite(v)) throw Error(what + ": must be finite");
    return exact_number_text(v);
}

// --- the objects -----------------------------------------------------------------------------

struct Scene {
    std::string spec;
    std::vector<scene::SceneEdit> edits;
    bool allow_outside_files = false;
    bool cache = true;
    std::shared_ptr<const scene::SceneDesc> desc;
};

//! A step added to a style (Style.with_step): a registered Python stage after the step `after`.
struct InsertedStep {
    std::string stage, after, id;
    std::map<std::string, double> params;
    std::map<std::string, std::string> in, out;
};

struct Style {
    std::string name = "wc18";
    std::vector<std::string> sets, variants, bypass;
    std::vector<InsertedStep> inserted;
    std::string key() const {
        std::string k = name + "\n";
        for (const auto* l : {&sets, &variants, &bypass}) {
            for (const auto& s : *l) k += s + "\n";
            k += "|\n";
        }
        for (const InsertedStep& i : inserted) {
            // the registration too: a stage registered again is another stage for a new compile
            k += i.stage + " " + i.after + " " + i.id + " " + std::to_string(reinterpret_cast<std::uintptr_t>(stylize::runtime_registry(i.stage))) + "\n";
            for (const auto& [a, b] : i.params) k += a + "=" + number_text(b, a) + "\n";
            for (const auto& [a, b] : i.in) k += "in " + a + "=" + b + "\n";
            for (const auto& [a, b] : i.out) k += "out " + a + "=" + b + "\n";
        }
        return k;
    }
};

//! Puts the inserted steps into a loaded pipeline: each after its step, reading that step's first
//! output through its first input (unless bound), writing its first output to "ID.PORT" (unless
//! bound), and every later reader of that output (and the style's output) reads the new one.
void insert_steps(stylize::Pipeline& p, const std::vector<InsertedStep>& steps) {
    for (const InsertedStep& ins : steps) {
        const stylize::Registry* reg = stylize::runtime_registry(ins.stage);
        if (!reg) throw Error("with_step: no stage '" + ins.stage + "' registered (aquarelle.register_stage)");
        const stylize::StageVariant& v = reg->default_variant(ins.stage);
        std::size_t at = p.steps.size();
        for (std::size_t i = 0; i < p.steps.size(); ++i)
            if ((p.steps[i].id.empty() ? p.steps[i].stage : p.steps[i].id) == ins.after) at = i;
        if (at == p.steps.size()) throw Error("with_step: style '" + p.name + "' has no step '" + ins.after + "'");
        std::vector<stylize::ResolvedStep> resolved;
        for (std::size_t i = 0; i < p.steps.size(); ++i) resolved.push_back(stylize::resolve_step(p, i));
        if (resolved[at].outputs.empty() || v.inputs.empty() || v.outputs.empty())
            throw Error("with_step: '" + ins.stage + "' after '" + ins.after + "' needs an input and an output");
        const std::string from = resolved[at].outputs[0];
        stylize::PipelineStep step;
        step.stage = ins.stage;
        step.variant = v.variant;
        step.id = ins.id.empty() ? ins.stage : ins.id;
        step.params = ins.params;
        step.in = ins.in;
        step.out = ins.out;
        step.in.try_emplace(v.inputs[0].name, from);
        step.out.try_emplace(v.outputs[0].name, step.id + "." + v.outputs[0].name);
        const std::string to = step.out.at(v.outputs[0].name);
        for (std::size_t j = at + 1; j < p.steps.size(); ++j) {
            const stylize::StageVariant& rv = *resolved[j].variant;
            for (std::size_t k = 0; k < rv.inputs.size() && k < resolved[j].inputs.size(); ++k)
                if (resolved[j].inputs[k] == from) p.steps[j].in[rv.inputs[k].name] = to;
        }
        if (p.output == from) p.output = to;
        p.steps.insert(p.steps.begin() + std::ptrdiff_t(at + 1), std::move(step));
    }
}

//! A copy of `img` as a fresh NumPy array (what a Python stage gets: it may keep it).
py::array copy_of(const ImageF& img) {
    const py::ssize_t h = img.height(), w = img.width(), c = img.channels();
    py::array_t<float> a({h, w, c});
    std::copy(img.data(), img.data() + img.num_values(), a.mutable_data());
    return a;
}

//! register_stage: a Python function as a stage (one variant, "python") of the runtime registry.
void register_stage(const std::string& name, const py::function& fn, const std::vector<std::pair<std::string, int>>& inputs,
                    const std::vector<std::pair<std::string, int>>& outputs,
                    const std::map<std::string, std::tuple<double, double, double, std::string>>& params, const std::string& doc) {
    stylize::StageVariant v;
    v.stage = name;
    v.variant = "python";
    v.doc = doc.empty() ? "a stage written in Python (a prototype: slow, one thread)" : doc;
    if (inputs.empty() || outputs.empty()) throw Error("register_stage '" + name + "': needs at least one input and one output");
    for (const auto& [port, ch] : inputs) {
        if (ch < 1 || ch > 4) throw Error("register_stage '" + name + "': input '" + port + "' needs 1-4 channels");
        v.inputs.push_back({port, port, ch, false});
    }
    for (const auto& [port, ch] : outputs) {
        if (ch < 1 || ch > 4) throw Error("register_stage '" + name + "': output '" + port + "' needs 1-4 channels");
        v.outputs.push_back({port, name + "." + port, ch, false});
    }
    for (const auto& [pname, d] : params) {
        const auto& [def, lo, hi, pdoc] = d;
        if (!(lo <= def && def <= hi)) throw Error("register_stage '" + name + "': parameter '" + pname + "' default outside [min, max]");
        v.params.push_back({pname, stylize::ParamKind::Float, def, lo, hi, pdoc});
    }
    // The function is held by a pointer whose deleter takes the GIL (the registry may outlive any
    // Python frame); copies of the stage's run share it.
    std::shared_ptr<py::object> f(new py::object(fn), [](py::object* o) {
        py::gil_scoped_acquire gil;
        delete o;
    });
    const auto ins = v.inputs, outs = v.outputs;
    v.run = [f, ins, outs, name](stylize::StageIO& io, const stylize::ParamValues& values, const Exec&) {
        py::gil_scoped_acquire gil;
        py::dict in, pv;
        const ImageF* first = nullptr;
        for (std::size_t k = 0; k < ins.size(); ++k) {
            if (!io.in[k]) throw Error("Python stage '" + name + "': input '" + ins[k].name + "' is missing");
            if (!first) first = io.in[k];
            in[py::str(ins[k].name)] = copy_of(*io.in[k]);
        }
        for (const auto& [k, x] : values) pv[py::str(k)] = x;
        py::object r;
        try {
            r = (*f)(in, pv);
        } catch (py::error_already_set& e) {
            // The exception and the frame that raised it (pybind11's text lists every frame after "At:").
            std::string what = e.what();
            if (const auto at = what.find("\n\nAt:\n"); at != std::string::npos) {
                const std::string frames = what.substr(at + 7);
                what = what.substr(0, at) + " (at " + frames.substr(frames.find_first_not_of(' '), frames.find('\n') - frames.find_first_not_of(' ')) + ")";
            }
            throw Error("Python stage '" + name + "' raised " + what);
        }
        if (py::isinstance<py::array>(r) && outs.size() == 1) {
            py::dict d;
            d[py::str(outs[0].name)] = r;
            r = d;
        }
        if (!py::isinstance<py::dict>(r))
            throw Error("Python stage '" + name + "' returned " + std::string(py::str(r.get_type())) + "; expected a dict {output: array}");
        const py::dict d = r;
        for (std::size_t k = 0; k < outs.size(); ++k) {
            const std::string what = "Python stage '" + name + "' output '" + outs[k].name + "'";
            if (!d.contains(outs[k].name)) throw Error(what + " is missing");
            py::object o = d[py::str(outs[k].name)];
            if (!py::isinstance<py::array>(o)) throw Error(what + ": expected a NumPy array");
            ImageF img = image_from(o.cast<py::array>(), what, outs[k].channels);
            if (first && (img.width() != first->width() || img.height() != first->height()))
                throw Error(what + ": " + std::to_string(img.width()) + " x " + std::to_string(img.height()) + ", its input is " +
                            std::to_string(first->width()) + " x " + std::to_string(first->height()));
            *io.out[k] = std::move(img);
        }
    };
    stylize::register_runtime_stage(std::move(v));
}

//! The render options every call shares.
struct Request {
    std::optional<int> width, height;
    int frame = 0, threads = 0, ssaa = 1;
    std::string antialias = "coverage", control = "default", working_space = "display";
    std::vector<double> view;  //!< [yaw, pitch, zoom] or with pan x, y
};

struct GBuffer {
    std::shared_ptr<app::RenderJob> job;  //!< null: made from arrays
    Targets targets;
    int frame = 0;
    std::mutex m;  //!< targets are moved into a style's run and back
    //! Jobs of the styles run on this G-buffer (compiled once per style; the newest few).
    std::map<std::string, std::shared_ptr<app::RenderJob>> style_jobs;
    std::deque<std::string> order;
    static constexpr std::size_t kMaxStyleJobs = 8;
};

struct Result {
    Targets targets;  //!< every target the style produced, "final" included
    std::shared_ptr<app::RenderJob> job;
    std::vector<double> step_ms;
};

std::optional<cache::Config> cache_config(bool on) {
    if (!on) return std::nullopt;
    return cache::config_from_environment();
}

//! The style's pipeline with its variants, values and bypasses applied: every name checked now.
stylize::Pipeline pipeline_of(const Style& s) {
    stylize::Pipeline p = stylize::load_pipeline(s.name);
    insert_steps(p, s.inserted);
    for (const auto& v : s.variants) stylize::set_variant(p, v);
    for (const auto& a : s.sets) stylize::set_param(p, a);
    for (const auto& b : s.bypass) stylize::bypass_step(p, b);
    stylize::validate_pipeline(p);
    return p;
}

//! The style's part of the render options: --style, --set, --variant, --bypass and inserted steps.
void set_style(app::RenderOptions& o, const Style& st) {
    o.style = st.name;
    o.style_given = true;
    o.sets = st.sets;
    o.variants = st.variants;
    o.bypass = st.bypass;
    o.edit_style = nullptr;
    if (!st.inserted.empty()) o.edit_style = [ins = st.inserted](stylize::Pipeline& p) { insert_steps(p, ins); };
}

app::RenderOptions options_of(const Scene& s, const Style& st, const Request& r) {
    app::RenderOptions o;
    o.scene = s.spec;
    o.scene_edits = s.edits;
    o.allow_outside_files = s.allow_outside_files;
    set_style(o, st);
    o.width = r.width.value_or(0);
    o.height = r.height.value_or(0);
    if (o.width < 0 || o.height < 0 || o.width > kMaxImageSide || o.height > kMaxImageSide)
        throw Error("width and height must be in [1, " + std::to_string(kMaxImageSide) + "]");
    o.frame_first = o.frame_last = r.frame;
    o.frame_given = true;
    if (r.frame < 0 || r.frame > app::request_limits::kMaxFrame) throw Error("frame must be in [0, " + std::to_string(app::request_limits::kMaxFrame) + "]");
    o.threads = r.threads;
    if (r.threads < 0 || r.threads > app::request_limits::kMaxThreads) throw Error("threads must be in [0, 1024]");
    o.ssaa = r.ssaa;
    if (r.ssaa < 1 || r.ssaa > app::request_limits::kMaxSsaa) throw Error("ssaa must be in [1, 4]");
    if (r.antialias != "coverage" && r.antialias != "none") throw Error("antialias must be 'coverage' or 'none'");
    o.antialias = r.antialias == "none" ? raster::RenderSettings::Antialias::None : raster::RenderSettings::Antialias::Coverage;
    if (r.control != "default" && r.control != "neutral") throw Error("control must be 'default' or 'neutral'");
    o.neutral_control = r.control == "neutral";
    if (r.working_space != "display" && r.working_space != "linear") throw Error("working_space must be 'display' or 'linear'");
    o.working_space = r.working_space == "linear" ? WorkingSpace::Linear : WorkingSpace::Display;
    if (!r.view.empty()) {
        namespace lim = app::request_limits;
        if (r.view.size() != 3 && r.view.size() != 5) throw Error("view must be (yaw, pitch, zoom) or (yaw, pitch, zoom, pan_x, pan_y)");
        auto in = [](double v, double lo, double hi, const char* what) {
            if (!(v >= lo && v <= hi)) throw Error(std::string("view: ") + what + " outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
            return v;
        };
        o.view_yaw = in(r.view[0], -lim::kMaxOrbitDeg, lim::kMaxOrbitDeg, "yaw");
        o.view_pitch = in(r.view[1], -lim::kMaxViewPitchDeg, lim::kMaxViewPitchDeg, "pitch");
        o.view_zoom = in(r.view[2], lim::kMinViewZoom, lim::kMaxViewZoom, "zoom");
        if (r.view.size() == 5) {
            o.view_pan_x = in(r.view[3], -lim::kMaxViewPan, lim::kMaxViewPan, "pan x");
            o.view_pan_y = in(r.view[4], -lim::kMaxViewPan, lim::kMaxViewPan, "pan y");
        }
    }
    o.quiet = true;
    o.cache = cache_config(s.cache);
    return o;
}

Request request_of(std::optional<int> width, std::optional<int> height, int frame, int threads, int ssaa, const std::string& antialias,
                   const std::string& control, const std::string& working_space, const std::vector<double>& view) {
    return {width, height, frame, threads, ssaa, antialias, control, working_space, view};
}

std::string scene_default_style(const Scene& s) {
    return s.desc && !s.desc->style.empty() ? s.desc->style : "wc18";
}

// --- the calls -------------------------------------------------------------------------------

std::shared_ptr<Scene> load_scene(const std::string& spec, const std::map<std::string, py::object>& edits, bool allow_outside_files,
                                  bool cache) {
    auto s = std::make_shared<Scene>();
    s->spec = spec;
    s->allow_outside_files = allow_outside_files;
    s->cache = cache;
    for (const auto& [ptr, v] : edits) s->edits.push_back(scene::parse_scene_edit(ptr + "=" + value_text(v, "edit " + ptr)));
    scene::LoadOptions lo;
    lo.allow_outside_files = allow_outside_files;
    lo.edits = s->edits;
    std::optional<cache::Store> store;
    if (auto c = cache_config(cache)) store.emplace(*c);
    {
        py::gil_scoped_release release;
        s->desc = std::make_shared<const scene::SceneDesc>(scene::load_scene_cached(spec, lo, store ? &*store : nullptr));
    }
    return s;
}

std::shared_ptr<GBuffer> rasterize(const Scene& s, const std::optional<std::string>& style, const Request& r) {
    Style st;
    st.name = style.value_or(scene_default_style(s));
    app::RenderOptions o = options_of(s, st, r);
    o.preloaded = s.desc;
    o.keep_loaded = true;
    o.live = true;                // the job keeps its scene: styles run on it later
    o.keep_intermediates = true;  // every G-buffer target
    auto g = std::make_shared<GBuffer>();
    g->frame = r.frame;
    py::gil_scoped_release release;
    g->job = std::make_shared<app::RenderJob>(app::prepare_render(o, app::Reporter{}));
    g->targets = app::render_gbuffer(*g->job, r.frame);
    return g;
}

std::shared_ptr<GBuffer> gbuffer_from_arrays(const std::map<std::string, py::array>& arrays) {
    auto g = std::make_shared<GBuffer>();
    if (arrays.empty()) throw Error("from_arrays: no targets given");
    int w = 0, h = 0;
    for (const auto& [name, a] : arrays) {
        const int ch = target::gbuffer_channels(name.c_str());
        if (ch <= 0) {
            std::string known;
            for (const target::GBufferTarget& t : target::kGBufferLayout) known += (known.empty() ? "" : ", ") + std::string(t.name);
            throw Error("from_arrays: '" + name + "' is not a G-buffer target (" + known + ")");
        }
        ImageF img = image_from(a, "from_arrays['" + name + "']", ch);
        if (w && (img.width() != w || img.height() != h))
            throw Error("from_arrays['" + name + "']: " + std::to_string(img.width()) + " x " + std::to_string(img.height()) +
                        ", the other targets are " + std::to_string(w) + " x " + std::to_string(h));
        w = img.width();
        h = img.height();
        g->targets.set(name, std::move(img));
    }
    return g;
}

//! The job of `st` on this G-buffer's scene, request and frame (compiled once, kept).
std::shared_ptr<app::RenderJob> style_job(GBuffer& g, const Style& st, int threads) {
    const std::string key = st.key() + std::to_string(threads);
    if (auto it = g.style_jobs.find(key); it != g.style_jobs.end()) return it->second;
    app::RenderOptions o = g.job->options;
    set_style(o, st);
    o.threads = threads;
    o.preloaded = g.job->loaded;
    o.keep_loaded = false;
    auto job = std::make_shared<app::RenderJob>(app::prepare_render(o, app::Reporter{}));
    if (!job->stylize) throw Error("style 'none' has no steps to run");
    g.style_jobs[key] = job;
    g.order.push_back(key);
    while (g.order.size() > GBuffer::kMaxStyleJobs) {
        g.style_jobs.erase(g.order.front());
        g.order.pop_front();
    }
    return job;
}

std::shared_ptr<Result> run_style(const Style& st, GBuffer& g, std::optional<int> threads) {
    auto r = std::make_shared<Result>();
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(g.m);
    stylize::RunOptions ro;
    ro.step_ms = &r->step_ms;
    if (g.job) {
        r->job = style_job(g, st, threads.value_or(g.job->options.threads));
        r->targets = app::run_style_on(*r->job, g.targets, g.frame, ro);
    } else {
        // A G-buffer from arrays: the style alone (no scene: no raster passes, no camera depth range).
        const stylize::Pipeline p = pipeline_of(st);
        const stylize::CompiledPipeline c = stylize::compile_pipeline(p, &g.targets);
        if (c.has_passes) throw Error("style '" + st.name + "' draws the scene with its own raster passes: run it on aq.rasterize's G-buffer");
        stylize::check_gbuffer(c, g.targets);
        ro.exec = Exec::fast(threads.value_or(0));
        ro.fuse = ro.in_place = ro.release_dead = ro.reuse_outputs = false;  // the G-buffer's images stay as they are
        Targets t = app::lend_gbuffer(g.targets, [&](Targets& set) { stylize::run_pipeline(c, set, ro); });
        const ImageF& fin = t.get(p.output);  // a painting is written opaque, as render --out writes it
        ImageF out;
        if (fin.channels() == 4) rgb_of(fin, out);
        else out = fin;
        r->targets = std::move(t);
        r->targets.set("final", std::move(out));
    }
    return r;
}

//! `aquarelle render` in-process: the CLI's files (image, manifest, --targets) when `out` is given,
//! listing the files this call read. Returns nothing; the files are the result.
void render_files(const Scene& s, const std::optional<Style>& st, const Request& r, const std::string& out, const std::string& targets_dir,
                  const std::string& targets_png_dir) {
    if (st && !st->inserted.empty())
        throw Error("render: a style with Python stages has no reproducible manifest; run it with Style.run and write the image with aquarelle.save");
    app::RenderOptions o = options_of(s, st.value_or(Style{}), r);
    if (!st) {  // the scene's own style, as a render without --style (the manifest says so)
        o.style.clear();
        o.style_given = false;
    }
    o.out = out;
    o.targets_dir = targets_dir;
    o.targets_png_dir = targets_png_dir;
    o.frame_given = r.frame != 0;
    py::gil_scoped_release release;
    InputCapture inputs;
    app::RenderJob job = app::prepare_render(o, app::Reporter{});
    job.inputs = &inputs;
    if (!targets_dir.empty()) ensure_directory(targets_dir);
    if (!targets_png_dir.empty()) ensure_directory(targets_png_dir);
    app::render_to_files(job, app::Reporter{});
}

py::list stages() {
    py::list out;
    for (const stylize::Registry* reg : {&stylize::builtin_registry(), &stylize::builtin_pass_registry()})
        for (const stylize::StageVariant* v : reg->all()) {
            py::list params;
            for (const stylize::ParamDesc& d : v->params)
                params.append(py::dict(py::arg("name") = d.name,
                                       py::arg("kind") = stylize::param_kind_name(d.kind),
                                       py::arg("default") = d.def, py::arg("min") = d.lo, py::arg("max") = d.hi, py::arg("doc") = d.doc,
                                       py::arg("names") = d.names));
            py::list ins, outs;
            for (const auto& p : v->inputs) ins.append(p.name);
            for (const auto& p : v->outputs) outs.append(p.name);
            out.append(py::dict(py::arg("stage") = v->stage, py::arg("variant") = v->variant, py::arg("doc") = v->doc,
                                py::arg("pass") = reg == &stylize::builtin_pass_registry(), py::arg("inputs") = ins,
                                py::arg("outputs") = outs, py::arg("params") = params));
        }
    return out;
}

py::dict compare(const py::array& a, const py::array& b, double threshold) {
    const ImageF x = image_from(a, "compare: a"), y = image_from(b, "compare: b");
    if (x.width() != y.width() || x.height() != y.height() || x.channels() != y.channels())
        throw Error("compare: a is " + std::to_string(x.width()) + " x " + std::to_string(x.height()) + " x " + std::to_string(x.channels()) +
                    ", b is " + std::to_string(y.width()) + " x " + std::to_string(y.height()) + " x " + std::to_string(y.channels()));
    CompareStats s;
    {
        py::gil_scoped_release release;
        s = compare_images(x, y, threshold);
    }
    return py::dict(py::arg("mean_abs") = s.mean_abs, py::arg("max_abs") = s.max_abs,
                    py::arg("max_at") = py::make_tuple(s.max_x, s.max_y, s.max_c), py::arg("frac_over") = s.frac_over,
                    py::arg("psnr") = s.psnr, py::arg("threshold") = s.threshold);
}

void save(const std::string& path, const py::array& a) {
    ImageF img = image_from(a, "save '" + path + "'");
    py::gil_scoped_release release;
    write_image(path, img);
}

//! aquarelle coherence's two measures between consecutive frames, on images and the G-buffers
//! (with their cameras) they were made from.
py::dict coherence(GBuffer& g0, const py::array& i0, GBuffer& g1, const py::array& i1, double threshold) {
    if (!g0.job || !g1.job) throw Error("coherence: needs G-buffers from aquarelle.rasterize (their cameras)");
    const ImageF a = image_from(i0, "coherence: image 0"), b = image_from(i1, "coherence: image 1");
    app::CoherenceParams p;
    if (!(threshold > 0.0 && threshold <= 1.0)) throw Error("coherence: threshold must be in (0, 1]");
    p.threshold = threshold;
    auto frame_of = [](const GBuffer& g, const ImageF& img) {
        app::CoherenceFrame f;
        f.image = &img;
        f.depth = &g.targets.get(target::kDepthLinear);
        f.normal = &g.targets.get(target::kNormal);
        f.id = &g.targets.get(target::kObjectId);
        const scene::Camera cam = app::frame_camera(*g.job, g.frame);
        f.view = glm::dmat4(cam.view);
        f.projection = glm::dmat4(raster::projection_matrix(cam, float(g.job->settings.width) / float(g.job->settings.height)));
        f.orthographic = cam.orthographic;
        return f;
    };
    app::CoherenceStats st;
    {
        py::gil_scoped_release release;
        std::unique_lock<std::mutex> l0(g0.m, std::defer_lock), l1(g1.m, std::defer_lock);
        if (&g0 == &g1) l0.lock();
        else std::lock(l0, l1);
        st = app::frame_coherence(frame_of(g0, a), frame_of(g1, b), p);
    }
    auto frac = [](long long n, long long d) { return d ? double(n) / double(d) : 0.0; };
    return py::dict(py::arg("static_mean") = st.static_mean(), py::arg("static_changed") = frac(st.static_changed, st.static_pixels),
                    py::arg("static_pixels") = st.static_pixels, py::arg("warp_mean") = st.warp_mean(),
                    py::arg("warp_changed") = frac(st.warped_changed, st.warped_pixels), py::arg("warped_pixels") = st.warped_pixels,
                    py::arg("object_pixels") = st.object_pixels, py::arg("pixels") = st.pixels);
}

py::list target_names(const Targets& t) {
    py::list l;
    for (const std::string& n : t.names()) l.append(n);
    return l;
}

}  // namespace
}  // namespace aq::python

namespace {

using namespace aq::python;
using aq::Error;

constexpr const char* kRequestArgsDoc = R"(width, height: output size (default: the scene file's, else 1280 x 720); frame: the
tremor clock's frame; threads: worker threads, 0 = all cores (the output does not depend on
it); ssaa: supersampling 1-4; antialias: 'coverage' or 'none'; control: 'default' or 'neutral';
working_space: 'display' or 'linear'; view: (yaw, pitch, zoom[, pan_x, pan_y]) as render --view.)";

std::string style_doc(const Style& s) {
    std::string t = "aquarelle.style('" + s.name + "')";
    for (const auto& v : s.variants) t += ".with_variant('" + v.substr(0, v.find('=')) + "', '" + v.substr(v.find('=') + 1) + "')";
    if (!s.sets.empty()) {
        t += ".with_params({";
        for (std::size_t i = 0; i < s.sets.size(); ++i)
            t += (i ? ", '" : "'") + s.sets[i].substr(0, s.sets[i].find('=')) + "': " + s.sets[i].substr(s.sets[i].find('=') + 1);
        t += "})";
    }
    for (const auto& b : s.bypass) t += ".without('" + b + "')";
    return t;
}


}  // namespace

PYBIND11_MODULE(_aquarelle, m) {
    m.doc() = "Aquarelle's native module; use `import aquarelle` (docs/python.md).";
    py::register_exception<Error>(m, "Error", PyExc_RuntimeError);

    py::class_<Scene, std::shared_ptr<Scene>>(m, "Scene", "A loaded scene (aquarelle.load_scene): a scene file, a .gltf/.glb or procedural:NAME.")
        .def_property_readonly("spec", [](const Scene& s) { return s.spec; }, "What was loaded (path or procedural:NAME).")
        .def_property_readonly("triangles", [](const Scene& s) { return s.desc->scene.triangle_count(); }, "Triangles of the scene.")
        .def_property_readonly("style", &scene_default_style, "The scene file's style, else 'wc18'.")
        .def_property_readonly("size", [](const Scene& s) -> std::optional<std::pair<int, int>> {
            if (!s.desc->width || !s.desc->height) return std::nullopt;
            return std::make_pair(s.desc->width, s.desc->height);
        }, "The scene file's (width, height), or None.")
        .def_property_readonly("edits", [](const Scene& s) {
            py::dict d;
            for (const auto& e : s.edits) d[py::str(e.pointer)] = py::module_::import("json").attr("loads")(e.value);
            return d;
        }, "The edits of the scene file's art direction it was loaded with.")
        .def("values", [](const Scene& s) {
            py::list l;
            if (aq::lower_extension(s.spec) != ".json") return l;
            const py::object loads = py::module_::import("json").attr("loads");
            for (const aq::scene::SceneKnob& k : aq::scene::scene_knobs(s.spec))
                l.append(py::dict(py::arg("pointer") = k.pointer, py::arg("kind") = k.kind, py::arg("value") = loads(k.value),
                                  py::arg("group") = k.group, py::arg("name") = k.name));
            return l;
        }, "The scene file's art-direction values that load_scene(edits=...) may change (aquarelle scene-values).")
        .def("__repr__", [](const Scene& s) { return "<aquarelle.Scene '" + s.spec + "', " + std::to_string(s.desc->scene.triangle_count()) + " triangles>"; });

    m.def("load_scene", &load_scene, py::arg("spec"), py::kw_only(), py::arg("edits") = std::map<std::string, py::object>{},
          py::arg("allow_outside_files") = false, py::arg("cache") = true,
          R"(Loads a scene file (.json), a bare .gltf/.glb or "procedural:NAME", as `aquarelle render` does.

edits: {json_pointer: value} edits of a scene file's art direction (render --scene-set;
Scene.values() lists them). allow_outside_files: let a glTF read files outside its folder.
cache: use the content cache of loaded scenes (docs/cache.md), as the CLI does.
Raises aquarelle.Error with the loader's message.)");

    py::class_<GBuffer, std::shared_ptr<GBuffer>>(m, "GBuffer", "A frame's G-buffer targets by name (aquarelle.rasterize or GBuffer.from_arrays).")
        .def("__getitem__", [](py::object self, const std::string& name) {
            GBuffer& g = self.cast<GBuffer&>();
            std::lock_guard<std::mutex> lock(g.m);
            if (!g.targets.has(name)) throw py::key_error(name);
            return view_of(g.targets.get(name), self);
        }, py::arg("name"), "The target as a read-only float32 H x W x C array sharing the G-buffer's memory.")
        .def("keys", [](GBuffer& g) {
            std::lock_guard<std::mutex> lock(g.m);
            return target_names(g.targets);
        })
        .def("__contains__", [](GBuffer& g, const std::string& n) {
            std::lock_guard<std::mutex> lock(g.m);
            return g.targets.has(n);
        }, py::arg("name"))
        .def("__len__", [](GBuffer& g) {
            std::lock_guard<std::mutex> lock(g.m);
            return g.targets.names().size();
        })
        .def_property_readonly("width", [](GBuffer& g) { return g.job ? g.job->settings.width : g.targets.get(g.targets.names().front()).width(); })
        .def_property_readonly("height", [](GBuffer& g) { return g.job ? g.job->settings.height : g.targets.get(g.targets.names().front()).height(); })
        .def_property_readonly("frame", [](const GBuffer& g) { return g.frame; })
        .def_property_readonly("style", [](const GBuffer& g) -> std::optional<std::string> {
            if (!g.job) return std::nullopt;
            return g.job->options.style;
        }, "The style whose default art direction the G-buffer carries (None: from arrays).")
        .def_static("from_arrays", &gbuffer_from_arrays, py::arg("targets"),
                    R"(A G-buffer from NumPy arrays (e.g. another renderer's passes): {"color": HxWx4, "depth.linear": HxWx1,
"normal": HxWx3, "object_id": HxWx1, "control.*": HxWx4, ...}; float32, finite, one size, the
target's channel count (H x W allowed for one channel). The values are copied.)")
        .def("__repr__", [](GBuffer& g) {
            std::lock_guard<std::mutex> lock(g.m);
            return "<aquarelle.GBuffer " + std::to_string(g.targets.names().size()) + " targets>";
        });

    m.def("rasterize", [](const Scene& s, std::optional<int> width, std::optional<int> height, int frame, int threads,
                          std::optional<std::string> style, int ssaa, const std::string& antialias, const std::string& control,
                          const std::string& working_space, const std::vector<double>& view) {
              return rasterize(s, style, request_of(width, height, frame, threads, ssaa, antialias, control, working_space, view));
          },
          py::arg("scene"), py::arg("width") = py::none(), py::arg("height") = py::none(), py::kw_only(), py::arg("frame") = 0,
          py::arg("threads") = 0, py::arg("style") = py::none(), py::arg("ssaa") = 1, py::arg("antialias") = "coverage",
          py::arg("control") = "default", py::arg("working_space") = "display", py::arg("view") = std::vector<double>{},
          (std::string("Renders the scene's G-buffer (every target) as `aquarelle render` does before its style.\n\nstyle: whose "
                       "default art direction a model without painted control gets (default: the scene's style); ") +
           kRequestArgsDoc).c_str());

    py::class_<Style>(m, "Style", "A style preset (or style file) with parameter values, variants and bypassed steps; immutable.")
        .def_property_readonly("name", [](const Style& s) { return s.name; })
        .def_property_readonly("params", [](const Style& s) {
            py::dict d;
            for (const auto& a : s.sets) d[py::str(a.substr(0, a.find('=')))] = std::stod(a.substr(a.find('=') + 1));
            return d;
        }, "The values set with with_params, by 'step.param'.")
        .def_property_readonly("variants", [](const Style& s) {
            py::dict d;
            for (const auto& a : s.variants) d[py::str(a.substr(0, a.find('=')))] = a.substr(a.find('=') + 1);
            return d;
        })
        .def("with_params", [](const Style& s, const std::map<std::string, std::variant<double, std::string>>& values) {
            Style t = s;
            for (const auto& kv : values) {
                const std::string& k = kv.first;  // not a structured binding: clang 14 captures none
                // A number, or a parameter's named value ("mirror"), as --set takes them.
                const std::string a = k + "=" + (std::holds_alternative<std::string>(kv.second)
                                                     ? std::get<std::string>(kv.second)
                                                     : number_text(std::get<double>(kv.second), k));
                t.sets.erase(std::remove_if(t.sets.begin(), t.sets.end(), [&](const std::string& x) { return x.substr(0, x.find('=')) == k; }),
                             t.sets.end());
                t.sets.push_back(a);
            }
            (void)pipeline_of(t);
            return t;
        }, py::arg("values"), "A copy with these {'step.param': value} set (a number, or a parameter's named value such as 'mirror'; checked against the registry's ranges now).")
        .def("with_variant", [](const Style& s, const std::string& step, const std::string& variant) {
            Style t = s;
            t.variants.erase(std::remove_if(t.variants.begin(), t.variants.end(), [&](const std::string& x) { return x.substr(0, x.find('=')) == step; }),
                             t.variants.end());
            t.variants.push_back(step + "=" + variant);
            (void)pipeline_of(t);
            return t;
        }, py::arg("step"), py::arg("variant"), "A copy with that step's variant (a step's parameters set earlier must exist in it).")
        .def("with_step", [](const Style& s, const std::string& stage, const std::string& after, const std::string& id,
                             const std::map<std::string, double>& params, const std::map<std::string, std::string>& inputs,
                             const std::map<std::string, std::string>& outputs) {
            Style t = s;
            t.inserted.push_back({stage, after, id, params, inputs, outputs});
            (void)pipeline_of(t);
            return t;
        }, py::arg("stage"), py::kw_only(), py::arg("after"), py::arg("id") = "", py::arg("params") = std::map<std::string, double>{},
           py::arg("inputs") = std::map<std::string, std::string>{}, py::arg("outputs") = std::map<std::string, std::string>{},
           R"(A copy with a registered Python stage (aquarelle.register_stage) after the step `after`: its first
input reads that step's first output, its first output is written to "ID.PORT", and every later
step reading the old image reads the new one. inputs/outputs bind other ports to targets.)")
        .def("without", [](const Style& s, const std::string& step) {
            Style t = s;
            t.bypass.push_back(step);
            (void)pipeline_of(t);
            return t;
        }, py::arg("step"), "A copy without that step (render --bypass).")
        .def("steps", [](const Style& s) {
            const aq::stylize::Pipeline p = pipeline_of(s);
            py::list l;
            for (std::size_t i = 0; i < p.steps.size(); ++i) {
                const aq::stylize::ResolvedStep r = aq::stylize::resolve_step(p, i);
                py::dict params;
                for (const auto& [k, v] : r.params) params[py::str(k)] = v;
                l.append(py::dict(py::arg("id") = p.steps[i].id.empty() ? p.steps[i].stage : p.steps[i].id, py::arg("stage") = p.steps[i].stage,
                                  py::arg("variant") = r.variant->variant, py::arg("params") = params));
            }
            return l;
        }, "The steps in order: id, stage, variant and every parameter's value.")
        .def("run", [](const Style& st, GBuffer& g, std::optional<int> threads) { return run_style(st, g, threads); },
             py::arg("gbuffer"), py::kw_only(), py::arg("threads") = py::none(),
             R"(Runs the style on the G-buffer: a Result with every target the pipeline produced and "final",
the image `aquarelle render --out` writes (display-encoded RGB). The first run of a style on a
G-buffer compiles it (kept for later runs). threads: default the G-buffer's.)")
        .def("__repr__", &style_doc);

    m.def("style", [](const std::string& name) {
        Style s;
        s.name = name;
        (void)pipeline_of(s);
        return s;
    }, py::arg("name") = "wc18", "A style: a preset (aquarelle.styles()) or a style file (.json).");

    py::class_<Result, std::shared_ptr<Result>>(m, "Result", "What a style produced: targets by name, 'final' included.")
        .def("__getitem__", [](py::object self, const std::string& name) {
            const Result& r = self.cast<const Result&>();
            if (!r.targets.has(name)) throw py::key_error(name);
            return view_of(r.targets.get(name), self);
        }, py::arg("name"), "The target as a read-only float32 H x W x C array sharing the result's memory.")
        .def("keys", [](const Result& r) { return target_names(r.targets); })
        .def("__contains__", [](const Result& r, const std::string& n) { return r.targets.has(n); }, py::arg("name"))
        .def("__len__", [](const Result& r) { return r.targets.names().size(); })
        .def_property_readonly("step_ms", [](const Result& r) { return r.step_ms; }, "Wall time of each step, ms.")
        .def("__repr__", [](const Result& r) { return "<aquarelle.Result " + std::to_string(r.targets.names().size()) + " targets>"; });

    m.def("render", [](const Scene& s, const std::string& out, const std::optional<Style>& style, std::optional<int> width,
                       std::optional<int> height, int frame, int threads, int ssaa, const std::string& antialias, const std::string& control,
                       const std::string& working_space, const std::vector<double>& view, const std::string& targets,
                       const std::string& targets_png) {
              render_files(s, style, request_of(width, height, frame, threads, ssaa, antialias, control, working_space, view), out, targets,
                           targets_png);
          },
          py::arg("scene"), py::arg("out"), py::kw_only(), py::arg("style") = py::none(), py::arg("width") = py::none(),
          py::arg("height") = py::none(), py::arg("frame") = 0, py::arg("threads") = 0, py::arg("ssaa") = 1,
          py::arg("antialias") = "coverage", py::arg("control") = "default", py::arg("working_space") = "display",
          py::arg("view") = std::vector<double>{}, py::arg("targets") = "", py::arg("targets_png") = "",
          (std::string("Writes what `aquarelle render SCENE --out OUT` writes for the same request: the image, its provenance\n"
                       "manifest (OUT.json, listing the files this call read) and --targets/--targets-png folders.\n\n") +
           kRequestArgsDoc).c_str());

    m.def("register_stage", &register_stage, py::arg("name"), py::arg("fn"), py::kw_only(), py::arg("inputs"), py::arg("outputs"),
          py::arg("params") = std::map<std::string, std::tuple<double, double, double, std::string>>{}, py::arg("doc") = "",
          R"(Registers a Python function as a stage, to prototype an effect between C++ stages (slow: it runs
on one thread with the GIL, its images copied in and out). fn(inputs, params) gets {port: float32
H x W x C array (a copy)} and {param: value} and returns {output port: array} (or one array for a
single output) of the input's size and the port's channels. inputs/outputs: [(port, channels)];
params: {name: (default, min, max, doc)}. Style.with_step puts it into a style.)");
    m.def("coherence", &coherence, py::arg("gbuffer0"), py::arg("image0"), py::arg("gbuffer1"), py::arg("image1"),
          py::arg("threshold") = 1.0 / 255.0,
          R"(aquarelle coherence's measures between frame t-1 (gbuffer0, image0) and frame t (docs/coherence.md): the
change where the G-buffer did not change (static_mean, static_changed: the fraction over threshold)
and the motion-compensated change (warp_mean, warp_changed), with their pixel counts.)");
    m.def("coherence_report", [](const std::vector<std::string>& images, const std::string& targets_dir, const std::string& json_out) {
              py::gil_scoped_release release;
              return aq::app::coherence_report(images, targets_dir, aq::app::CoherenceParams{}, json_out);
          }, py::arg("images"), py::arg("targets_dir"), py::kw_only(), py::arg("json_out") = "",
          "aquarelle coherence on the files of a --frames run rendered with --targets: the report's text (and JSON in json_out).");
    m.def("stages", &stages, "The stage registry: every stage variant with its ports and parameters (kind, default, range, doc).");
    m.def("styles", &aq::stylize::preset_names, "The style presets.");
    m.def("compare", &compare, py::arg("a"), py::arg("b"), py::arg("threshold") = 1.0 / 255.0,
          "aquarelle compare's metrics of two float32 arrays of one shape: mean_abs, max_abs, max_at, frac_over, psnr.");
    m.def("save", &save, py::arg("path"), py::arg("image"),
          "Writes a float32 H x W x C array as the CLI writes images (.png 8-bit display, .exr float), through a temporary file.");
}
