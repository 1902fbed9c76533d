// app/main.cpp — the `aquarelle` command line: render, stages, styles, compare.
//
// Every failure prints one clear message to stderr and exits non-zero; nothing is written unless
// the whole image was computed (core/io.h writes through a temporary file and a rename).
#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "app/cli_args.h"
#include "app/visualize.h"
#include "core/color.h"
#include "core/compare.h"
#include "core/io.h"
#include "raster/raster.h"
#include "scenes/scene_file.h"
#include "stylize/pipeline.h"
#include "stylize/stage.h"

namespace fs = std::filesystem;
using aq::cli::Args;
using aq::cli::UsageError;

namespace {

constexpr const char* kMainHelp = R"(aquarelle — deterministic art-directed watercolor rendering of glTF scenes

usage: aquarelle <command> [options]

commands:
  render SCENE     render a scene file (.json), a bare .gltf/.glb or procedural:NAME
  stages           list every stylization stage, its variants and parameters (defaults, ranges)
  styles           list the pipeline presets
  compare A B      compare two images (mean/max abs error, fraction over 1/255, PSNR)
  help [COMMAND]   this text, or a command's options

Run `aquarelle COMMAND --help` for a command's options. Exit status: 0 on success, 1 on an
error in the input or while rendering, 2 on a usage error.
)";

constexpr const char* kRenderHelp = R"(usage: aquarelle render SCENE --out FILE.png [options]

SCENE is a scene file (.json, see docs/scenes.md), a bare .gltf/.glb (automatic camera, default
light, the style's default control) or procedural:NAME (e.g. procedural:swatches).

options:
  --out FILE            output image (.png 8-bit display, .exr float); required.
                        With --frames, FILE must contain #### (replaced by the frame number).
  --targets DIR         also write every G-buffer target and every pipeline intermediate as EXR
  --targets-png DIR     also write display versions (PNG) of every target (see docs/gallery.md)
  --style S             wc18 | wc17 | wc16 | mnpr | FILE.json | none (G-buffer colour only);
                        default: the scene file's style, else wc18
  --control C           default | neutral. default: a model without painted control (no scene-file
                        "control" rules, no material control) gets the style's default
                        art-direction (noise fields, docs/look.md); neutral: all control zero,
                        the papers' equations in isolation (default: default)
  --working-space W     display | linear: colour space of the watercolor maths (default display,
                        as the papers; linear encodes the result to sRGB at the end; docs/look.md)
  --set STAGE.PARAM=V   override a stage parameter (repeatable)
  --variant STAGE=VAR   choose a stage variant (repeatable)
  --width W, --height H output size in pixels (default: scene file, else 1280x720)
  --frame N             frame number; the hand tremor is driven by time N/fps (default 0)
  --frames A-B          render frames A..B inclusive (animation), with progress
  --sweep S.P=A:B:N     render N images with parameter P of step S from A to B (G-buffer
                        rendered once); --out must contain #### (the sweep index), with progress
  --fps F               frames per second for the tremor clock (default: scene file, else 24)
  --ssaa K              ordered-grid supersampling K x K, K in [1, 4] (default 1)
  --threads N           worker threads, 0 = all cores (default 0); output does not depend on it
  --reference           use the plain reference traversals (slow; the oracle)
  --allow-outside-files let a glTF read buffers and images outside its own folder (by default
                        refused after resolving '..', percent-encoding and links; docs/limits.md)
  --quiet               no progress on stderr
  --help                this text
)";

constexpr const char* kCompareHelp = R"(usage: aquarelle compare A B [--diff OUT.png] [--threshold T]

Prints mean and max absolute error, the fraction of values differing by more than T (default
1/255) and PSNR (peak 1.0) of two images of the same size and channel count (any format
OpenImageIO reads). --diff writes a heatmap of the per-pixel max error. Exit status 0 when the
images could be compared (whatever the difference), 1 on error.
)";

struct RenderOptions {
    std::string scene, out, targets_dir, targets_png_dir, style;
    bool style_given = false;
    std::vector<std::string> sets, variants;
    int width = 0, height = 0, ssaa = 1, threads = 0;
    int frame_first = 0, frame_last = 0;
    bool animation = false;
    double fps = 0;
    bool reference = false, quiet = false, allow_outside_files = false;
    bool neutral_control = false;
    aq::WorkingSpace working_space = aq::WorkingSpace::Display;
    std::string sweep;  //!< "step.param" swept by --sweep
    double sweep_from = 0, sweep_to = 0;
    int sweep_count = 0;
};

std::string frame_path(const std::string& pattern, int frame) {
    auto pos = pattern.find("####");
    if (pos == std::string::npos) return pattern;
    char num[32];
    std::snprintf(num, sizeof num, "%04d", frame);
    return pattern.substr(0, pos) + num + pattern.substr(pos + 4);
}

void check_output_path(const std::string& path, const std::string& opt) {
    const fs::path p(path);
    std::string ext = p.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".png" && ext != ".exr" && ext != ".tif" && ext != ".tiff" && ext != ".jpg")
        throw UsageError(opt + ": '" + path + "' must end in .png, .exr, .tif or .jpg");
    const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
    if (!fs::is_directory(dir)) throw aq::Error(opt + ": folder '" + dir.string() + "' does not exist");
}

RenderOptions parse_render(Args& a) {
    RenderOptions o;
    while (!a.done()) {
        const std::string arg = a.next();
        if (arg == "--help" || arg == "-h") {
            std::cout << kRenderHelp;
            std::exit(0);
        } else if (arg == "--out" || arg == "-o") {
            o.out = a.value(arg);
        } else if (arg == "--targets") {
            o.targets_dir = a.value(arg);
        } else if (arg == "--targets-png") {
            o.targets_png_dir = a.value(arg);
        } else if (arg == "--style") {
            o.style = a.value(arg);
            o.style_given = true;
        } else if (arg == "--control") {
            const std::string v = a.value(arg);
            if (v == "neutral") o.neutral_control = true;
            else if (v == "default") o.neutral_control = false;
            else throw UsageError("--control expects default or neutral, got '" + v + "'");
        } else if (arg == "--working-space") {
            const std::string v = a.value(arg);
            if (v == "display") o.working_space = aq::WorkingSpace::Display;
            else if (v == "linear") o.working_space = aq::WorkingSpace::Linear;
            else throw UsageError("--working-space expects display or linear, got '" + v + "'");
        } else if (arg == "--set") {
            o.sets.push_back(a.value(arg));
        } else if (arg == "--variant") {
            o.variants.push_back(a.value(arg));
        } else if (arg == "--width") {
            o.width = int(aq::cli::parse_int(arg, a.value(arg), 1, aq::kMaxImageSide));
        } else if (arg == "--height") {
            o.height = int(aq::cli::parse_int(arg, a.value(arg), 1, aq::kMaxImageSide));
        } else if (arg == "--frame") {
            o.frame_first = o.frame_last = int(aq::cli::parse_int(arg, a.value(arg), 0, 10'000'000));
        } else if (arg == "--frames") {
            const std::string v = a.value(arg);
            const auto dash = v.find('-');
            if (dash == std::string::npos || dash == 0) throw UsageError("--frames expects A-B, e.g. 0-23");
            o.frame_first = int(aq::cli::parse_int(arg, v.substr(0, dash), 0, 10'000'000));
            o.frame_last = int(aq::cli::parse_int(arg, v.substr(dash + 1), 0, 10'000'000));
            if (o.frame_last < o.frame_first) throw UsageError("--frames: last frame before first");
            if (o.frame_last - o.frame_first >= 100'000) throw UsageError("--frames: more than 100000 frames");
            o.animation = true;
        } else if (arg == "--sweep") {
            // STEP.PARAM=FROM:TO:COUNT
            const std::string v = a.value(arg);
            const auto eq = v.find('=');
            const auto c1 = v.find(':', eq == std::string::npos ? 0 : eq);
            const auto c2 = c1 == std::string::npos ? c1 : v.find(':', c1 + 1);
            if (eq == std::string::npos || c1 == std::string::npos || c2 == std::string::npos || eq == 0)
                throw UsageError("--sweep expects STEP.PARAM=FROM:TO:COUNT, e.g. edge_darken.intensity=0:4:9");
            o.sweep = v.substr(0, eq);
            o.sweep_from = aq::cli::parse_double(arg, v.substr(eq + 1, c1 - eq - 1), -1e30, 1e30);
            o.sweep_to = aq::cli::parse_double(arg, v.substr(c1 + 1, c2 - c1 - 1), -1e30, 1e30);
            o.sweep_count = int(aq::cli::parse_int(arg, v.substr(c2 + 1), 2, 1000));
        } else if (arg == "--fps") {
            o.fps = aq::cli::parse_double(arg, a.value(arg), 0.001, 10000.0);
        } else if (arg == "--ssaa") {
            o.ssaa = int(aq::cli::parse_int(arg, a.value(arg), 1, 4));
        } else if (arg == "--threads") {
            o.threads = int(aq::cli::parse_int(arg, a.value(arg), 0, 1024));
        } else if (arg == "--reference") {
            o.reference = true;
        } else if (arg == "--allow-outside-files") {
            o.allow_outside_files = true;
        } else if (arg == "--quiet" || arg == "-q") {
            o.quiet = true;
        } else if (!arg.empty() && arg[0] == '-' && arg != "-") {
            throw UsageError("render: unknown option '" + arg + "' (see aquarelle render --help)");
        } else if (o.scene.empty()) {
            o.scene = arg;
        } else {
            throw UsageError("render: unexpected argument '" + arg + "'");
        }
    }
    if (o.scene.empty()) throw UsageError("render: no SCENE given (see aquarelle render --help)");
    if (o.out.empty()) throw UsageError("render: --out FILE is required");
    if (o.animation && o.out.find("####") == std::string::npos && o.frame_first != o.frame_last)
        throw UsageError("render: with --frames, --out must contain #### for the frame number");
    if (!o.sweep.empty() && o.animation)
        throw UsageError("render: --sweep and --frames cannot be combined");
    if (!o.sweep.empty() && o.out.find("####") == std::string::npos)
        throw UsageError("render: with --sweep, --out must contain #### for the sweep index");
    check_output_path(o.out, "--out");
    return o;
}

int cmd_render(Args& a) {
    RenderOptions o = parse_render(a);
    auto log = [&](const std::string& s) {
        if (!o.quiet) std::cerr << s << std::endl;
    };
    const auto t0 = std::chrono::steady_clock::now();
    auto ms_since = [](auto t) {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
    };

    // 1. Scene, then the style: every name and value is validated before anything is rendered.
    aq::scene::LoadOptions load_options;
    load_options.allow_outside_files = o.allow_outside_files;
    aq::scene::SceneDesc desc = aq::scene::load_scene(o.scene, load_options);
    for (auto& w : desc.scene.warnings) std::cerr << "warning: " << w << "\n";
    log("scene: " + o.scene + " (" + std::to_string(desc.scene.triangle_count()) + " triangles) loaded in " +
        std::to_string(int(ms_since(t0))) + " ms");

    aq::raster::RenderSettings rs;
    rs.width = o.width ? o.width : (desc.width ? desc.width : 1280);
    rs.height = o.height ? o.height : (desc.height ? desc.height : 720);
    rs.ssaa = o.ssaa;
    rs.fps = float(o.fps > 0 ? o.fps : desc.fps);
    rs.exec = o.reference ? aq::Exec::reference() : aq::Exec::fast(o.threads);
    aq::check_image_size(rs.width, rs.height, "output");
    aq::check_image_size(rs.width * rs.ssaa, rs.height * rs.ssaa, "supersampled render (--ssaa)");
    const float aspect = float(rs.width) / float(rs.height);
    if (desc.camera_auto && aspect != desc.auto_aspect)  // reframe for the size actually rendered
        desc.camera = aq::scene::frame_bounds(desc.scene.world_bounds(), aspect, desc.auto_view_dir, desc.auto_yfov);

    std::string style = o.style_given ? o.style : (desc.style.empty() ? "wc18" : desc.style);
    const bool stylize = style != "none";
    aq::stylize::Pipeline pipeline;  // configured after the camera: depth range may follow it
    if (stylize) {
        pipeline = aq::stylize::load_pipeline(style);
        if (!o.style_given || o.style == desc.style) {
            for (auto& [k, v] : desc.style_variant) aq::stylize::set_variant(pipeline, k + "=" + v);
            for (auto& [k, v] : desc.style_set) {
                const auto dot = k.find('.');
                aq::stylize::set_param_value(pipeline, k.substr(0, dot), dot == std::string::npos ? "" : k.substr(dot + 1),
                                             v, "scene file '" + o.scene + "' style value '" + k + "'");
            }
        }
        if (desc.camera_auto) {
            // MNPR normalises depth over 8..50 scene units (a Maya scene in cm). An automatically
            // framed camera hugs the scene's bounding sphere, so its clip range is the scene's
            // depth range whatever the model's units: normalise over it instead.
            for (const auto& step : pipeline.steps)
                if (step.stage == "adjust") {
                    const std::string id = step.id.empty() ? step.stage : step.id;
                    const std::string why = "the automatic depth range of the framed camera";
                    aq::stylize::set_param_value(pipeline, id, "depth_near", double(desc.camera.znear), why);
                    aq::stylize::set_param_value(pipeline, id, "depth_far", double(desc.camera.zfar), why);
                }
        }
        for (auto& v : o.variants) aq::stylize::set_variant(pipeline, v);
        for (auto& s : o.sets) aq::stylize::set_param(pipeline, s);
        if (!desc.paper.empty()) {
            pipeline.paper.file = desc.paper;
            pipeline.has_paper = true;
        }
        if (desc.substrate_color_set) pipeline.substrate_color = desc.substrate_color;
        aq::stylize::validate_pipeline(pipeline);
    } else if (!o.sets.empty() || !o.variants.empty()) {
        throw UsageError("render: --set/--variant need a style (not --style none)");
    }

    rs.substrate_color = stylize ? pipeline.substrate_color : desc.substrate_color;
    rs.working_space = o.working_space;
    if (o.working_space == aq::WorkingSpace::Linear) {
        // The paper colour is given as a display value; the maths and the G-buffer run in linear.
        for (int k = 0; k < 3; ++k) rs.substrate_color[k] = aq::srgb_to_linear(rs.substrate_color[k]);
        if (stylize) pipeline.substrate_color = rs.substrate_color;
    }
    if (stylize) {
        // WC17 §3.2: pigment turbulence is object-space in a pipeline without the image-space
        // density stage (wc16, wc17): the material applies eq. 6 from ctrl.pigment.b.
        bool image_space_density = false;
        for (const auto& step : pipeline.steps) image_space_density |= step.stage == "pigment_density";
        if (!image_space_density) rs.turbulence = aq::raster::RenderSettings::Turbulence::ObjectSpace;
        // Default art-direction (docs/look.md) for primitives without painted control, unless the
        // scene file has its own rules or --control neutral.
        if (!o.neutral_control && !desc.control_rules && !pipeline.default_control.empty()) {
            const auto rules = aq::scene::parse_control_rules(pipeline.default_control,
                                                              "style '" + pipeline.name + "' default_control");
            const std::size_t n = aq::scene::apply_default_control(desc.scene, rules);
            if (n) log("default control of style " + pipeline.name + " on " + std::to_string(n) + " primitive(s)");
        }
    }

    if (!o.targets_dir.empty()) aq::ensure_directory(o.targets_dir);
    if (!o.targets_png_dir.empty()) aq::ensure_directory(o.targets_png_dir);

    // A sweep renders the G-buffer once and reruns the style for each value of one parameter.
    std::vector<aq::stylize::Pipeline> styles{pipeline};
    std::vector<std::string> sweep_labels{""};
    if (!o.sweep.empty()) {
        if (!stylize) throw UsageError("render: --sweep needs a style (not --style none)");
        styles.clear();
        sweep_labels.clear();
        for (int i = 0; i < o.sweep_count; ++i) {
            const double t = double(i) / double(o.sweep_count - 1);
            const double v = o.sweep_from + (o.sweep_to - o.sweep_from) * t;
            char assign[256];
            std::snprintf(assign, sizeof assign, "%s=%.9g", o.sweep.c_str(), v);
            aq::stylize::Pipeline p = pipeline;
            aq::stylize::set_param(p, assign);  // every value checked before anything is rendered
            styles.push_back(std::move(p));
            sweep_labels.push_back(assign);
        }
    }
    const bool sweeping = styles.size() > 1;

    const int nframes = o.frame_last - o.frame_first + 1;
    for (int f = o.frame_first; f <= o.frame_last; ++f) {
        const auto tf = std::chrono::steady_clock::now();
        const std::string prefix =
            o.animation ? "[frame " + std::to_string(f - o.frame_first + 1) + "/" + std::to_string(nframes) + "] " : "";
        rs.frame = f;
        std::vector<std::string> warnings;
        aq::Targets gbuffer = aq::raster::render_gbuffer(desc.scene, desc.camera, rs, &warnings);
        for (auto& w : warnings) std::cerr << "warning: " << w << "\n";
        log(prefix + "G-buffer " + std::to_string(rs.width) + "x" + std::to_string(rs.height) + " in " +
            std::to_string(int(ms_since(tf))) + " ms");

        for (std::size_t si = 0; si < styles.size(); ++si) {
            const int index = sweeping ? int(si) : f;  // the number that replaces #### in paths
            const std::string tag = sweeping ? "[sweep " + std::to_string(si + 1) + "/" + std::to_string(styles.size()) +
                                                   " " + sweep_labels[si] + "] "
                                             : prefix;
            aq::Targets targets = sweeping ? gbuffer : std::move(gbuffer);
            std::string final_name = aq::target::kColor;
            if (stylize) {
                const auto ts = std::chrono::steady_clock::now();
                aq::stylize::RunOptions ro;
                ro.exec = rs.exec;
                if (!o.quiet && !o.animation && !sweeping)
                    ro.progress = [&](int i, int n, const std::string& step) {
                        std::cerr << "  stage " << (i + 1) << "/" << n << ": " << step << std::endl;
                    };
                aq::stylize::run_pipeline(styles[si], targets, ro);
                final_name = styles[si].output;
                log(tag + "style " + styles[si].name + " (" + std::to_string(styles[si].steps.size()) +
                    " stages) in " + std::to_string(int(ms_since(ts))) + " ms");
            }

            // Intermediates first, the display image last: a listener waiting for --out sees a
            // complete set.
            const bool numbered = o.animation || sweeping;
            const std::string sub = frame_path(sweeping ? "sweep####" : "frame####", index);
            if (!o.targets_dir.empty()) {
                const std::string dir = numbered ? o.targets_dir + "/" + sub : o.targets_dir;
                aq::ensure_directory(dir);
                for (auto& [name, img] : targets.all())
                    aq::write_image(dir + "/" + aq::safe_file_name(name) + ".exr", img);
            }
            if (!o.targets_png_dir.empty()) {
                const std::string dir = numbered ? o.targets_png_dir + "/" + sub : o.targets_png_dir;
                aq::ensure_directory(dir);
                for (auto& [name, img] : targets.all())
                    aq::write_image(dir + "/" + aq::safe_file_name(name) + ".png", aq::app::visualize_target(name, img));
            }
            const std::string out = frame_path(o.out, index);
            aq::ImageF encoded;
            if (o.working_space == aq::WorkingSpace::Linear) {  // output transform: linear -> sRGB
                encoded = targets.get(final_name);
                float* d = encoded.data();
                const int nc = encoded.channels();
                for (std::size_t i = 0; i < encoded.num_values(); ++i)
                    if (nc < 4 || i % std::size_t(nc) != 3) d[i] = aq::linear_to_srgb(std::clamp(d[i], 0.0f, 1.0f));
            }
            const aq::ImageF& final_img = o.working_space == aq::WorkingSpace::Linear ? encoded : targets.get(final_name);
            // A stylised image is a painting on its paper: written opaque (RGB). The G-buffer
            // colour (--style none) keeps its coverage alpha for compositing; --targets keeps
            // every channel.
            if (stylize && final_img.channels() == 4) {
                aq::ImageF rgb(final_img.width(), final_img.height(), 3);
                for (int y = 0; y < rgb.height(); ++y)
                    for (int x = 0; x < rgb.width(); ++x)
                        for (int c = 0; c < 3; ++c) rgb.at(x, y, c) = final_img.at(x, y, c);
                aq::write_image(out, rgb);
            } else {
                aq::write_image(out, final_img);
            }
            log(tag + "wrote " + out);
        }
    }
    log("done in " + std::to_string(int(ms_since(t0))) + " ms");
    return 0;
}

const char* kind_name(aq::stylize::ParamKind k) {
    switch (k) {
        case aq::stylize::ParamKind::Int: return "int";
        case aq::stylize::ParamKind::Bool: return "bool";
        default: return "float";
    }
}

int cmd_stages(Args& a) {
    if (!a.done()) {
        std::string arg = a.next();
        if (arg == "--help" || arg == "-h") {
            std::cout << "usage: aquarelle stages\n\nLists every registered stage variant: ports "
                         "(port -> default target, channels), parameters (default, range).\n";
            return 0;
        }
        throw UsageError("stages: unexpected argument '" + arg + "'");
    }
    const auto& reg = aq::stylize::builtin_registry();
    for (const std::string& stage : reg.stages()) {
        std::cout << stage << "\n";
        for (const auto* v : reg.variants(stage)) {
            std::cout << "  " << v->variant << " — " << v->doc << "\n";
            for (auto& p : v->inputs)
                std::cout << "      in  " << p.name << " <- " << p.default_target << " (" << p.channels << " ch"
                          << (p.optional ? ", optional" : "") << ")\n";
            for (auto& p : v->outputs)
                std::cout << "      out " << p.name << " -> " << p.default_target << " (" << p.channels << " ch)\n";
            for (auto& p : v->params) {
                std::printf("      %-22s %-5s default %-8g range [%g, %g]  %s\n", p.name.c_str(), kind_name(p.kind),
                            p.def, p.lo, p.hi, p.doc.c_str());
                std::fflush(stdout);
            }
        }
    }
    return 0;
}

int cmd_styles(Args& a) {
    if (!a.done()) {
        std::string arg = a.next();
        if (arg == "--help" || arg == "-h") {
            std::cout << "usage: aquarelle styles\n\nLists the pipeline presets and their stages.\n";
            return 0;
        }
        throw UsageError("styles: unexpected argument '" + arg + "'");
    }
    for (const std::string& name : aq::stylize::preset_names()) {
        const aq::stylize::Pipeline p = aq::stylize::load_pipeline(name);
        std::cout << name << " — " << p.doc << "\n    ";
        for (std::size_t i = 0; i < p.steps.size(); ++i)
            std::cout << (i ? " -> " : "") << p.steps[i].stage << ":" << p.steps[i].variant;
        std::cout << "\n";
    }
    return 0;
}

int cmd_compare(Args& a) {
    std::vector<std::string> files;
    std::string diff;
    double threshold = 1.0 / 255.0;
    while (!a.done()) {
        const std::string arg = a.next();
        if (arg == "--help" || arg == "-h") {
            std::cout << kCompareHelp;
            return 0;
        } else if (arg == "--diff") {
            diff = a.value(arg);
            check_output_path(diff, "--diff");
        } else if (arg == "--threshold") {
            threshold = aq::cli::parse_double(arg, a.value(arg), 0.0, 1e30);
        } else if (!arg.empty() && arg[0] == '-') {
            throw UsageError("compare: unknown option '" + arg + "'");
        } else {
            files.push_back(arg);
        }
    }
    if (files.size() != 2) throw UsageError("compare: expects exactly two images (see aquarelle compare --help)");
    const aq::ImageF A = aq::read_image(files[0]);
    const aq::ImageF B = aq::read_image(files[1]);
    const aq::CompareStats s = aq::compare_images(A, B, threshold);
    std::cout << "size        " << A.width() << "x" << A.height() << "x" << A.channels() << "\n"
              << "mean_abs    " << s.mean_abs << "\n"
              << "max_abs     " << s.max_abs << " at (" << s.max_x << ", " << s.max_y << ") channel " << s.max_c << "\n"
              << "over " << threshold << "  " << 100.0 * s.frac_over << " %\n"
              << "psnr        " << s.psnr << " dB\n"
              << "nonfinite   " << s.nonfinite << "\n";
    if (!diff.empty()) {
        aq::write_image(diff, aq::diff_heatmap(A, B));
        std::cout << "diff        " << diff << "\n";
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    // A file-size limit (ulimit -f) must fail a write with EFBIG, reported like a full disk,
    // instead of killing the process with SIGXFSZ.
    std::signal(SIGXFSZ, SIG_IGN);
    if (argc < 2) {
        std::cerr << kMainHelp;
        return 2;
    }
    const std::string cmd = argv[1];
    Args args(argc, argv, 2);
    try {
        if (cmd == "--help" || cmd == "-h" || cmd == "help") {
            const std::string sub = args.done() ? "" : args.next();
            if (sub == "render") std::cout << kRenderHelp;
            else if (sub == "compare") std::cout << kCompareHelp;
            else std::cout << kMainHelp;
            return 0;
        }
        if (cmd == "--version") {
            std::cout << "aquarelle 0.1.0\n";
            return 0;
        }
        if (cmd == "render") return cmd_render(args);
        if (cmd == "stages") return cmd_stages(args);
        if (cmd == "styles") return cmd_styles(args);
        if (cmd == "compare") return cmd_compare(args);
        std::cerr << "aquarelle: unknown command '" << cmd << "'\n\n" << kMainHelp;
        return 2;
    } catch (const UsageError& e) {
        std::cerr << "aquarelle: " << e.what() << "\n";
        return 2;
    } catch (const aq::Error& e) {
        std::cerr << "aquarelle: error: " << e.what() << "\n";
        return 1;
    } catch (const std::bad_alloc&) {
        std::cerr << "aquarelle: error: out of memory\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "aquarelle: error: " << e.what() << "\n";
        return 1;
    }
}
