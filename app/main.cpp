// app/main.cpp — the `aquarelle` command line: render, stages, styles, compare, reproduce.
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
#include "app/coherence.h"
#include "app/grid.h"
#include "app/manifest.h"
#include "app/render_files.h"
#include "app/render_job.h"
#include "app/serve.h"
#include "core/build_info.h"
#include "core/color.h"
#include "core/compare.h"
#include "core/io.h"
#include "core/oiio.h"
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
  scene-values F   list the art-direction values of a scene file that --scene-set (and the
                   live page) can edit
  compare A B      compare two images (mean/max abs error, fraction over 1/255, PSNR)
  reproduce M      render an image again from its manifest (IMAGE.json) and say whether it is
                   identical (docs/provenance.md)
  serve SCENE      a local web page that art-directs the scene live: every parameter of the
                   style, variants, shown target, camera by mouse, Save (docs/serve.md)
  grid SCENE       combinations of styles, variants and parameter values side by side: a labelled
                   contact sheet and an HTML report (docs/grid.md)
  coherence F...   temporal coherence of a rendered --frames sequence, as numbers
                   (docs/coherence.md)
  help [COMMAND]   this text, or a command's options

Run `aquarelle COMMAND --help` for a command's options. Exit status: 0 on success, 1 on an
error in the input or while rendering, 2 on a usage error.
)";

constexpr const char* kServeHelp = R"(usage: aquarelle serve SCENE [options] [render options]

Starts a local web server and prints the page's URL (with its access token). The page shows the
rendered image and a panel generated from the stage registry: every step of the style with its
variant and parameters (range, default, doc), the style, the target shown (the final image, any
G-buffer target or intermediate), the frame (tremor clock) and size; drag the image to turn the
camera, scroll to move closer. Each change renders the newest state only; the page prints the
equivalent `aquarelle render` command line, and Save writes the PNG, its manifest and the state
into --out-dir (docs/serve.md).

options:
  --port P          port to listen on (default 0: a free one)
  --bind ADDR       address to listen on (default 127.0.0.1; anything else is reachable from other
                    machines: a warning is printed; the token still guards every request)
  --out-dir DIR     where Save writes (default aquarelle-saved)
  --quiet           print only the URL
  --help            this text
Any `aquarelle render` option (--style, --width, --height, --set, --variant, --ssaa, --threads,
--no-cache, ...) sets the starting state; the page's changes come after it.
)";

constexpr const char* kRenderHelp = R"(usage: aquarelle render SCENE --out FILE.png [options]

SCENE is a scene file (.json, see docs/scenes.md), a bare .gltf/.glb (automatic camera, default
light, the style's default control) or procedural:NAME (e.g. procedural:swatches).

options:
  --out FILE            output image (.png 8-bit display, .exr float); required.
                        With --frames, FILE must contain #### (replaced by the frame number).
                        Each image gets its provenance manifest FILE.json (also embedded in the
                        file; `aquarelle reproduce FILE.json` renders it again; docs/provenance.md)
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
  --scene-set PTR=V     edit a value of the scene file's art direction before it is read: a JSON
                        pointer under control, layers, foliage, lights, ambient, substrate_color
                        or materials and a JSON value of the same kind, e.g.
                        /layers/1/color=[0.3,0.5,0.2] or /foliage/T=60 (repeatable;
                        `aquarelle scene-values FILE` lists them; docs/scenes.md)
  --variant STAGE=VAR   choose a stage variant (repeatable)
  --bypass STEP         leave a step out: its readers get its input instead, so the image shows
                        what the step adds (repeatable; e.g. --bypass edge_darken)
  --width W, --height H output size in pixels (default: scene file, else 1280x720)
  --frame N             frame number; the hand tremor is driven by time N/fps (default 0)
  --frames A-B | N      render frames A..B inclusive (animation), with progress; N: frame N only
  --shard I/N           render only shard I of N (0 <= I < N) of --frames or --sweep: the items k
                        (frame - first frame, or sweep index) with k mod N == I; N runs together
                        write exactly the files of one unsharded run (docs/shards.md)
  --orbit DEG           camera orbit: frame N sees the scene turned by N x DEG degrees about
                        the vertical (+Y) axis through the centre of its bounds (default 0)
  --view Y,P,Z[,X,V]    the camera turned by Y degrees about +Y and P degrees up (|P| <= 89) through
                        the centre of the scene's bounds, then Z times closer (Z in [0.05, 20]),
                        then moved X right and V up, in half-heights of the view at the centre
                        (|X|, |V| <= 20); after --orbit (what `aquarelle serve`'s mouse sets;
                        default 0,0,1,0,0)
  --sweep S.P=A:B:N     render N images with parameter P of step S from A to B (G-buffer
                        rendered once); --out must contain #### (the sweep index), with progress
  --fps F               frames per second for the tremor clock (default: scene file, else 24)
  --ssaa K              ordered-grid supersampling K x K, K in [1, 4] (default 1)
  --antialias A         coverage | none: at --ssaa 1, silhouette pixels get the coverage of the
                        4x4 samples of --ssaa 4 (default coverage); none: one sample per pixel
  --compression C       fast | none: how PNG and EXR files are compressed, losslessly either way
                        (default fast: PNG deflated by ISA-L's igzip at level 2, EXR PIZ). none
                        writes ~2.3x larger 1080p PNG frames, faster where the disk keeps up
                        (docs/performance.md "Writing files")
  --threads N           worker threads, 0 = all cores (default 0); output does not depend on it
  --row-groups          run the pipeline's row groups band by band (a fused schedule, the same
                        bytes; pays where the cache is smaller than a frame, docs/stylize.md)
  --reference           use the plain reference traversals (slow; the oracle)
  --allow-outside-files let a glTF read buffers and images outside its own folder (by default
                        refused after resolving '..', percent-encoding and links; docs/limits.md)
  --no-cache            neither read nor write the cache of loaded scenes and abstracted foliage
                        (default: on, in $AQUARELLE_CACHE_DIR, else $XDG_CACHE_HOME/aquarelle, else
                        ~/.cache/aquarelle, at most $AQUARELLE_CACHE_MAX_MB, default 4096; the
                        same bytes either way; docs/cache.md)
  --cache-dir DIR       keep that cache in DIR
  --timings             print where each image's time went (load, G-buffer, each stage, encode
                        and write; wall ms) and record it in its manifest (not part of the
                        image's identity; shown even with --quiet)
  --quiet               no progress on stderr
  --help                this text
)";

constexpr const char* kCompareHelp = R"(usage: aquarelle compare A B [--diff OUT.png] [--threshold T]

Prints mean and max absolute error, the fraction of values differing by more than T (default
1/255) and PSNR (peak 1.0) of two images of the same size and channel count (any format
OpenImageIO reads). --diff writes a heatmap of the per-pixel max error. Exit status 0 when the
images could be compared (whatever the difference), 1 on error.
)";

constexpr const char* kReproduceHelp = R"(usage: aquarelle reproduce MANIFEST.json [options]

Every image `aquarelle render` writes gets a manifest beside it (IMAGE.json: build, request,
every input file's SHA-256, the compiled pipeline, every output file's SHA-256; docs/provenance.md).
reproduce checks that this build is the manifest's, that the manifest is well formed (its request
typed and in range exactly as render's options), that every input is present and every output
file beside the manifest has its recorded SHA-256; it renders the image again with the recorded
request and compares the files read and every output file's SHA-256. It prints "identical" only
when all of that holds, else what differs: changed or unread inputs, changed or missing originals,
the pipeline, and the first differing output (in pipeline order) with compare's metrics.

options:
  --keep DIR       render into DIR and keep it; DIR must be new or empty (default: a temporary
                   folder, removed, also on Ctrl-C)
  --threads N      worker threads, 0 = all cores (default 0); the bytes do not depend on it
  --any-version    render and compare even when the manifest was made by another build
  --allow-outside-files
                   needed to reproduce an image rendered with --allow-outside-files (a manifest
                   cannot lift the path policy by itself)
  --quiet          no progress on stderr
  --help           this text

Exit status: 0 identical; 3 something differs (reported on stdout); 1 the image cannot be
reproduced (not a manifest, a malformed or out-of-range field, another build without
--any-version, a missing input file, an error while rendering); 2 usage error.
)";

constexpr const char* kCoherenceHelp = R"(usage: aquarelle coherence (FOLDER | IMAGE IMAGE...) --targets DIR [options]

Temporal coherence of a frame sequence rendered with `aquarelle render --frames A-B --targets DIR`
(docs/coherence.md). Frames: every image of FOLDER that has a manifest (sorted by name), or the
images given, in frame order; their manifests give each frame's camera, DIR its G-buffer. Per
consecutive pair, and in total (pixel-weighted):
  static   the change of the image where the G-buffer did not change (same object id, depth and
           normal): paper "shower door", noise flicker, effects pulled by motion nearby
  warp     the change along the true motion: each object pixel reprojected through its depth and
           the two cameras into the previous frame, compared where it is visible there
Each as the mean absolute change per channel and the % of pixels changing by more than 1/255.

options:
  --targets DIR          the --targets folder of the same run (DIR/frame####/depth.linear.exr, ...)
  --json FILE            also write the numbers as JSON
  --depth-tolerance R    relative depth change still "the same" for static pixels (default 1e-4)
  --normal-tolerance N   normal component change still "the same" (default 1e-3)
  --warp-tolerance R     relative depth difference for a reprojected point to count as visible
                         (default 0.01)
  --help                 this text
)";

constexpr const char* kGridHelp = R"(usage: aquarelle grid SCENE --out SHEET.png [axes] [options]

Renders every combination of the axes from one G-buffer per style into a labelled contact sheet
(docs/grid.md). Axes, combined in this order (the last axis with several values runs along the
columns, the others along the rows):
  --styles A,B,...        styles (default: the scene's style, else wc18)
  --variant STAGE=a,b     variants of one stage (repeatable: one axis each)
  --set STEP.PARAM=x,y    values of one parameter (repeatable: one axis each)
At most 64 combinations (refused before rendering).

options:
  --out FILE              the contact sheet (.png, .exr); required
  --report DIR            also write DIR/index.html: one column per combination, one row per
                          pipeline step with thumbnails and timings, the parameters that differ,
                          diff heatmaps and metrics against the baseline column
  --baseline K            the report's reference column (default 0)
  --cells DIR             also write each combination's image as DIR/cell_KKKK.exr
  --shard I/N             render only combinations k with k mod N == I into --cells DIR (no sheet,
                          no report); then assemble with the same axes and --from-cells
  --from-cells            make the sheet from the cells in --cells DIR instead of rendering
  --width W, --height H   size of each combination's image (default 640x360)
  --frame N, --control C, --working-space W, --antialias A, --threads N, --row-groups,
  --allow-outside-files, --no-cache, --cache-dir DIR, --quiet as in render
  --help                  this text
)";

using aq::app::RenderOptions;
namespace lim = aq::app::request_limits;

void check_output_path(const std::string& path, const std::string& opt) {
    const fs::path p(path);
    const std::string ext = aq::lower_extension(path);
    if (ext != ".png" && ext != ".exr" && ext != ".tif" && ext != ".tiff" && ext != ".jpg")
        throw UsageError(opt + ": '" + path + "' must end in .png, .exr, .tif or .jpg");
    const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
    if (!fs::is_directory(dir)) throw aq::Error(opt + ": folder '" + dir.string() + "' does not exist");
}

//! Progress on stderr unless quiet; warnings always.
aq::app::Reporter cli_reporter(bool quiet) {
    aq::app::Reporter r;
    r.progress = [quiet](const std::string& s) {
        if (!quiet) std::cerr << s << std::endl;
    };
    r.warning = [](const std::string& s) { std::cerr << "warning: " << s << "\n"; };
    r.info = [](const std::string& s) { std::cerr << s << std::endl; };
    return r;
}

//! The options render and grid share (size, frame, control, working space, threads, shard, file
//! policy, quiet): consumes `arg` (and its value) into o and returns true, or returns false.
bool parse_image_option(const std::string& arg, Args& a, RenderOptions& o) {
    if (arg == "--width") {
        o.width = int(aq::cli::parse_int(arg, a.value(arg), 1, aq::kMaxImageSide));
    } else if (arg == "--height") {
        o.height = int(aq::cli::parse_int(arg, a.value(arg), 1, aq::kMaxImageSide));
    } else if (arg == "--frame") {
        o.frame_first = o.frame_last = int(aq::cli::parse_int(arg, a.value(arg), 0, lim::kMaxFrame));
        o.frame_given = true;
    } else if (arg == "--control") {
        const std::string v = a.value(arg);
        if (v != "neutral" && v != "default") throw UsageError("--control expects default or neutral, got '" + v + "'");
        o.neutral_control = v == "neutral";
    } else if (arg == "--antialias") {
        const std::string v = a.value(arg);
        if (v != "coverage" && v != "none") throw UsageError("--antialias expects coverage or none, got '" + v + "'");
        o.antialias = v == "none" ? aq::raster::RenderSettings::Antialias::None : aq::raster::RenderSettings::Antialias::Coverage;
    } else if (arg == "--working-space") {
        const std::string v = a.value(arg);
        if (v != "display" && v != "linear") throw UsageError("--working-space expects display or linear, got '" + v + "'");
        o.working_space = v == "linear" ? aq::WorkingSpace::Linear : aq::WorkingSpace::Display;
    } else if (arg == "--threads") {
        o.threads = int(aq::cli::parse_int(arg, a.value(arg), 0, lim::kMaxThreads));
    } else if (arg == "--shard") {
        const std::string v = a.value(arg);
        const auto slash = v.find('/');
        if (slash == std::string::npos) throw UsageError("--shard expects I/N, e.g. 0/4");
        o.shard_count = int(aq::cli::parse_int(arg, v.substr(slash + 1), 1, 100000));
        o.shard_index = int(aq::cli::parse_int(arg, v.substr(0, slash), 0, 99999));
        if (o.shard_index >= o.shard_count) throw UsageError("--shard I/N needs 0 <= I < N (got " + v + ")");
    } else if (arg == "--row-groups") {
        o.row_groups = true;
    } else if (arg == "--allow-outside-files") {
        o.allow_outside_files = true;
    } else if (arg == "--no-cache") {
        o.cache.reset();
    } else if (arg == "--cache-dir") {
        const std::string dir = a.value(arg);
        if (dir.empty()) throw UsageError("--cache-dir expects a folder");
        o.cache = aq::cache::Config{dir, o.cache ? o.cache->max_bytes : aq::cache::kDefaultMaxBytes};
    } else if (arg == "--quiet" || arg == "-q") {
        o.quiet = true;
    } else {
        return false;
    }
    return true;
}

RenderOptions parse_render(Args& a) {
    RenderOptions o;
    o.cache = aq::cache::config_from_environment();
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
        } else if (parse_image_option(arg, a, o)) {
        } else if (arg == "--set") {
            o.sets.push_back(a.value(arg));
        } else if (arg == "--variant") {
            o.variants.push_back(a.value(arg));
        } else if (arg == "--bypass") {
            o.bypass.push_back(a.value(arg));
        } else if (arg == "--scene-set") {
            try {
                o.scene_edits.push_back(aq::scene::parse_scene_edit(a.value(arg)));
            } catch (const aq::Error& e) {
                throw UsageError(e.what());
            }
        } else if (arg == "--timings") {
            o.timings = true;
        } else if (arg == "--frames") {
            const std::string v = a.value(arg);
            const auto dash = v.find('-');
            if (dash == 0 || v.empty()) throw UsageError("--frames expects A-B or N, e.g. 0-23 or 12");
            // N alone: the one frame N, numbered as in an animation (A-A).
            o.frame_first = int(aq::cli::parse_int(arg, v.substr(0, dash), 0, lim::kMaxFrame));
            o.frame_last = dash == std::string::npos ? o.frame_first
                                                     : int(aq::cli::parse_int(arg, v.substr(dash + 1), 0, lim::kMaxFrame));
            if (o.frame_last < o.frame_first) throw UsageError("--frames: last frame before first");
            if (o.frame_last - o.frame_first >= lim::kMaxFramesPerRun)
                throw UsageError("--frames: more than " + std::to_string(lim::kMaxFramesPerRun) + " frames");
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
            o.sweep_from = aq::cli::parse_double(arg, v.substr(eq + 1, c1 - eq - 1), -lim::kMaxSweepValue, lim::kMaxSweepValue);
            o.sweep_to = aq::cli::parse_double(arg, v.substr(c1 + 1, c2 - c1 - 1), -lim::kMaxSweepValue, lim::kMaxSweepValue);
            o.sweep_count = int(aq::cli::parse_int(arg, v.substr(c2 + 1), lim::kMinSweepCount, lim::kMaxSweepCount));
        } else if (arg == "--orbit") {
            o.orbit_deg = aq::cli::parse_double(arg, a.value(arg), -lim::kMaxOrbitDeg, lim::kMaxOrbitDeg);
        } else if (arg == "--view") {
            const std::string v = a.value(arg);
            std::vector<std::string> f;
            for (std::size_t at = 0;;) {
                const std::size_t c = v.find(',', at);
                f.push_back(v.substr(at, c == std::string::npos ? c : c - at));
                if (c == std::string::npos) break;
                at = c + 1;
            }
            if (f.size() != 3 && f.size() != 5)
                throw UsageError("--view expects YAW,PITCH,ZOOM or YAW,PITCH,ZOOM,PANX,PANY, e.g. 30,10,1.5 or 30,10,1.5,0.2,0");
            o.view_yaw = aq::cli::parse_double(arg, f[0], -lim::kMaxOrbitDeg, lim::kMaxOrbitDeg);
            o.view_pitch = aq::cli::parse_double(arg, f[1], -lim::kMaxViewPitchDeg, lim::kMaxViewPitchDeg);
            o.view_zoom = aq::cli::parse_double(arg, f[2], lim::kMinViewZoom, lim::kMaxViewZoom);
            if (f.size() == 5) {
                o.view_pan_x = aq::cli::parse_double(arg, f[3], -lim::kMaxViewPan, lim::kMaxViewPan);
                o.view_pan_y = aq::cli::parse_double(arg, f[4], -lim::kMaxViewPan, lim::kMaxViewPan);
            }
        } else if (arg == "--fps") {
            o.fps = aq::cli::parse_double(arg, a.value(arg), lim::kMinFps, lim::kMaxFps);
        } else if (arg == "--ssaa") {
            o.ssaa = int(aq::cli::parse_int(arg, a.value(arg), 1, lim::kMaxSsaa));
        } else if (arg == "--compression") {
            const std::string v = a.value(arg);
            if (!aq::compression_from_name(v, o.compression))
                throw UsageError("--compression expects fast or none, got '" + v + "'");
        } else if (arg == "--reference") {
            o.reference = true;
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
    if (o.frame_given && o.animation)
        throw UsageError("render: --frame N and --frames A-B cannot be combined (--frames N renders the one frame N)");
    if (o.shard_count > 1 && !o.animation && o.sweep.empty())
        throw UsageError("render: --shard splits --frames or --sweep; give one of them");
    if (!o.sweep.empty() && o.out.find("####") == std::string::npos)
        throw UsageError("render: with --sweep, --out must contain #### for the sweep index");
    check_output_path(o.out, "--out");
    o.keep_intermediates = !o.targets_dir.empty() || !o.targets_png_dir.empty();
    return o;
}

int cmd_render(Args& a) {
    const RenderOptions o = parse_render(a);
    // A render that will write through OpenImageIO (EXR, TIFF, JPEG, targets, the RGBA image of
    // --style none) loads its module on a second thread while the scene loads (core/oiio.h). Grey
    // and RGB PNG output and JPEG papers do not need it: such a render loads it only if a texture
    // or paper in another format asks for it (the one-shot of a bare model never does).
    if (aq::lower_extension(o.out) != ".png" || !o.targets_dir.empty() || !o.targets_png_dir.empty() || (o.style_given && o.style == "none"))
        aq::preload_oiio();
    const aq::app::Reporter report = cli_reporter(o.quiet);
    const auto t0 = std::chrono::steady_clock::now();
    // Every name and value is validated before anything is rendered.
    aq::app::RenderJob job = aq::app::prepare_render(o, report);
    if (!o.targets_dir.empty()) aq::ensure_directory(o.targets_dir);
    if (!o.targets_png_dir.empty()) aq::ensure_directory(o.targets_png_dir);

    aq::app::render_to_files(job, report);
    report.progress("done in " +
                    std::to_string(int(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count())) +
                    " ms");
    return 0;
}

int cmd_stages(Args& a) {
    if (!a.done()) {
        std::string arg = a.next();
        if (arg == "--help" || arg == "-h") {
            std::cout << "usage: aquarelle stages\n\nLists every registered stage variant and raster pass: ports "
                         "(port -> default target, channels, size relation), parameters (default, range, or the names a\n"
                         "parameter with named values takes: --set STEP.border=mirror or the number 1).\n";
            return 0;
        }
        throw UsageError("stages: unexpected argument '" + arg + "'");
    }
    for (const auto* reg : {&aq::stylize::builtin_registry(), &aq::stylize::builtin_pass_registry()}) {
        if (reg == &aq::stylize::builtin_pass_registry())
            std::cout << "\nraster passes (LD06; pipeline files name them with \"pass\" instead of \"stage\")\n";
        for (const std::string& stage : reg->stages()) {
            std::cout << stage << "\n";
            for (const auto* v : reg->variants(stage)) {
                std::cout << "  " << v->variant << " — " << v->doc << "\n";
                for (auto& p : v->inputs)
                    std::cout << "      in  " << p.name << " <- " << p.default_target << " (" << p.channels << " ch"
                              << (p.optional ? ", optional" : "")
                              << (p.size == aq::stylize::SizeRule::Same         ? ", the size of " + p.like
                                  : p.size == aq::stylize::SizeRule::FullOrHalf ? ", the size of " + p.like + " or half"
                                                                                 : std::string())
                              << ")\n";
                for (auto& p : v->outputs)
                    std::cout << "      out " << p.name << " -> " << p.default_target << " (" << p.channels << " ch)\n";
                for (auto& p : v->params) {
                    if (!p.names.empty()) {  // named values: "default mirror  one of clamp|mirror"
                        std::string names;
                        for (const std::string& n : p.names) names += (names.empty() ? "" : "|") + n;
                        std::printf("      %-22s %-5s default %-8s one of %s  %s\n", p.name.c_str(), "name",
                                    p.names[std::size_t(p.def)].c_str(), names.c_str(), p.doc.c_str());
                        std::fflush(stdout);
                        continue;
                    }
                    std::printf("      %-22s %-5s default %-8g range [%g, %g]  %s\n", p.name.c_str(), aq::stylize::param_kind_name(p.kind),
                                p.def, p.lo, p.hi, p.doc.c_str());
                    std::fflush(stdout);
                }
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

int cmd_scene_values(Args& a) {
    std::string file;
    while (!a.done()) {
        const std::string arg = a.next();
        if (arg == "--help" || arg == "-h") {
            std::cout << "usage: aquarelle scene-values SCENE.json\n\nLists the values of a scene file's art direction "
                         "that `render --scene-set POINTER=VALUE` (and the live page's scene panel) can edit: JSON\n"
                         "pointer, kind, value, and where it is (docs/scenes.md \"Editing the art direction\").\n";
            return 0;
        }
        if (!arg.empty() && arg[0] == '-') throw UsageError("scene-values: unknown option '" + arg + "'");
        if (!file.empty()) throw UsageError("scene-values: one scene file, got '" + file + "' and '" + arg + "'");
        file = arg;
    }
    if (file.empty()) throw UsageError("scene-values: expected a scene file (.json)");
    if (aq::lower_extension(file) != ".json")
        throw aq::Error("scene-values: '" + file + "' is not a scene file (.json); a bare model has no art direction to edit");
    for (const aq::scene::SceneKnob& k : aq::scene::scene_knobs(file))
        std::cout << k.pointer << "\t" << k.kind << "\t" << k.value << "\t" << k.group << ": " << k.name << "\n";
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

int cmd_reproduce(Args& a) {
    aq::app::ReproduceOptions ro;
    while (!a.done()) {
        const std::string arg = a.next();
        if (arg == "--help" || arg == "-h") {
            std::cout << kReproduceHelp;
            return 0;
        } else if (arg == "--keep") {
            ro.keep_dir = a.value(arg);
        } else if (arg == "--threads") {
            ro.threads = int(aq::cli::parse_int(arg, a.value(arg), 0, lim::kMaxThreads));
        } else if (arg == "--any-version") {
            ro.any_version = true;
        } else if (arg == "--allow-outside-files") {
            ro.allow_outside_files = true;
        } else if (arg == "--quiet" || arg == "-q") {
            ro.quiet = true;
        } else if (!arg.empty() && arg[0] == '-') {
            throw UsageError("reproduce: unknown option '" + arg + "' (see aquarelle reproduce --help)");
        } else if (ro.manifest.empty()) {
            ro.manifest = arg;
        } else {
            throw UsageError("reproduce: unexpected argument '" + arg + "'");
        }
    }
    if (ro.manifest.empty()) throw UsageError("reproduce: no MANIFEST given (see aquarelle reproduce --help)");
    const aq::app::Reporter report = cli_reporter(ro.quiet);
    const aq::app::ReproduceResult r = aq::app::reproduce(ro, report);
    for (const std::string& line : r.lines) std::cout << line << "\n";
    return r.status;
}

int cmd_serve(Args& a) {
    aq::app::ServeOptions so;
    std::vector<std::string> rest;
    while (!a.done()) {
        const std::string arg = a.next();
        if (arg == "--help" || arg == "-h") {
            std::cout << kServeHelp;
            return 0;
        } else if (arg == "--port") {
            so.port = int(aq::cli::parse_int(arg, a.value(arg), 0, 65535));
        } else if (arg == "--bind") {
            so.bind = a.value(arg);
        } else if (arg == "--out-dir") {
            so.out_dir = a.value(arg);
        } else if (arg == "--quiet" || arg == "-q") {
            so.quiet = true;
        } else if (arg == "--out" || arg == "-o" || arg == "--frames" || arg == "--sweep" || arg == "--targets" ||
                   arg == "--targets-png" || arg == "--shard") {
            throw UsageError("serve: " + arg + " is not for the live view (Save writes into --out-dir)");
        } else if (so.scene.empty() && !arg.empty() && arg[0] != '-') {
            so.scene = arg;
        } else {
            rest.push_back(arg);
        }
    }
    if (so.scene.empty()) throw UsageError("serve: no SCENE given (see aquarelle serve --help)");
    so.render_args = rest;
    const char* web = std::getenv("AQ_WEB_DIR");
    so.web_dir = web && *web ? web : AQ_WEB_DIR;
    if (so.bind != "127.0.0.1" && so.bind != "::1")
        std::cerr << "aquarelle serve: warning: listening on " << so.bind
                  << ": other machines can reach the server (the token in the URL still guards it)\n";
    const auto parse = [](const std::vector<std::string>& v) {
        Args args(v);
        return parse_render(args);
    };
    return aq::app::serve(so, parse, [&](const std::string& url) {
        if (!so.quiet) std::cerr << "aquarelle serve: " << so.scene << " — open this page (Ctrl-C stops the server):\n";
        std::cout << url << std::endl;
    });
}

int cmd_grid(Args& a) {
    aq::app::GridOptions g;
    RenderOptions& o = g.base;
    o.cache = aq::cache::config_from_environment();
    o.width = 640;
    o.height = 360;
    auto axis = [](const std::string& opt, const std::string& v) {
        const auto eq = v.find('=');
        if (eq == std::string::npos || eq == 0 || eq + 1 == v.size())
            throw UsageError("grid: " + opt + " expects NAME=a,b,... (got '" + v + "')");
        std::vector<std::string> vals;
        std::size_t p = eq + 1;
        while (p <= v.size()) {
            const std::size_t q = std::min(v.find(',', p), v.size());
            vals.push_back(v.substr(p, q - p));
            if (vals.back().empty()) throw UsageError("grid: " + opt + ": an empty value in '" + v + "'");
            p = q + 1;
        }
        return std::make_pair(v.substr(0, eq), vals);
    };
    while (!a.done()) {
        const std::string arg = a.next();
        if (arg == "--help" || arg == "-h") {
            std::cout << kGridHelp;
            return 0;
        } else if (arg == "--styles") {
            const auto [name, vals] = axis(arg, "styles=" + a.value(arg));
            g.styles = vals;
        } else if (arg == "--variant") {
            g.variant_axes.push_back(axis(arg, a.value(arg)));
        } else if (arg == "--set") {
            g.set_axes.push_back(axis(arg, a.value(arg)));
        } else if (arg == "--out" || arg == "-o") {
            g.out = a.value(arg);
        } else if (arg == "--report") {
            g.report_dir = a.value(arg);
        } else if (arg == "--cells") {
            g.cells_dir = a.value(arg);
        } else if (arg == "--from-cells") {
            g.from_cells = true;
        } else if (arg == "--baseline") {
            g.baseline = int(aq::cli::parse_int(arg, a.value(arg), 0, aq::app::kMaxGridCombinations - 1));
        } else if (parse_image_option(arg, a, o)) {
        } else if (!arg.empty() && arg[0] == '-') {
            throw UsageError("grid: unknown option '" + arg + "' (see aquarelle grid --help)");
        } else if (o.scene.empty()) {
            o.scene = arg;
        } else {
            throw UsageError("grid: unexpected argument '" + arg + "'");
        }
    }
    if (o.scene.empty()) throw UsageError("grid: no SCENE given (see aquarelle grid --help)");
    g.shard_index = o.shard_index;
    g.shard_count = o.shard_count;
    if (g.shard_count > 1) {
        if (g.cells_dir.empty()) throw UsageError("grid: --shard writes combinations into --cells DIR; give it");
        if (!g.out.empty() || !g.report_dir.empty())
            throw UsageError("grid: a shard writes only its cells; assemble the sheet with --from-cells (docs/grid.md)");
        if (g.from_cells) throw UsageError("grid: --shard and --from-cells cannot be combined");
    } else {
        if (g.out.empty()) throw UsageError("grid: --out SHEET is required");
        check_output_path(g.out, "--out");
    }
    if (g.from_cells && g.cells_dir.empty()) throw UsageError("grid: --from-cells needs --cells DIR");
    if (g.from_cells && !g.report_dir.empty())
        throw UsageError("grid: --report needs the intermediates of a render, not --from-cells");
    o.out = g.out.empty() ? "grid.png" : g.out;  // a shard writes no sheet; the render job wants a name
    const aq::app::Reporter report = cli_reporter(o.quiet);
    aq::app::run_grid(g, report);
    return 0;
}

int cmd_coherence(Args& a) {
    std::vector<std::string> inputs;
    std::string targets, json_out;
    aq::app::CoherenceParams p;
    while (!a.done()) {
        const std::string arg = a.next();
        if (arg == "--help" || arg == "-h") {
            std::cout << kCoherenceHelp;
            return 0;
        } else if (arg == "--targets") {
            targets = a.value(arg);
        } else if (arg == "--json") {
            json_out = a.value(arg);
        } else if (arg == "--depth-tolerance") {
            p.static_depth_rel = aq::cli::parse_double(arg, a.value(arg), 0.0, 1.0);
        } else if (arg == "--normal-tolerance") {
            p.static_normal = aq::cli::parse_double(arg, a.value(arg), 0.0, 2.0);
        } else if (arg == "--warp-tolerance") {
            p.warp_depth_rel = aq::cli::parse_double(arg, a.value(arg), 0.0, 1.0);
        } else if (!arg.empty() && arg[0] == '-') {
            throw UsageError("coherence: unknown option '" + arg + "' (see aquarelle coherence --help)");
        } else {
            inputs.push_back(arg);
        }
    }
    if (inputs.empty()) throw UsageError("coherence: no FOLDER or images given (see aquarelle coherence --help)");
    if (targets.empty()) throw UsageError("coherence: --targets DIR (the G-buffer folder of the same run) is required");
    if (inputs.size() > 100000) throw UsageError("coherence: more than 100000 images");
    std::vector<std::string> images = inputs;
    if (inputs.size() == 1 && fs::is_directory(inputs[0])) images = aq::app::sequence_in_folder(inputs[0]);
    std::cout << aq::app::coherence_report(images, targets, p, json_out);
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
            else if (sub == "reproduce") std::cout << kReproduceHelp;
            else if (sub == "coherence") std::cout << kCoherenceHelp;
            else if (sub == "grid") std::cout << kGridHelp;
            else if (sub == "serve") std::cout << kServeHelp;
            else std::cout << kMainHelp;
            return 0;
        }
        if (cmd == "--version") {
            const aq::BuildInfo& b = aq::build_info();
            std::cout << "aquarelle " << b.describe() << "\n"
                      << "compiler " << b.compiler << ", " << b.build_type << ", flags " << b.flags << "\n";
            return 0;
        }
        if (cmd == "render") return cmd_render(args);
        if (cmd == "stages") return cmd_stages(args);
        if (cmd == "styles") return cmd_styles(args);
        if (cmd == "scene-values") return cmd_scene_values(args);
        if (cmd == "compare") return cmd_compare(args);
        if (cmd == "reproduce") return cmd_reproduce(args);
        if (cmd == "coherence") return cmd_coherence(args);
        if (cmd == "grid") return cmd_grid(args);
        if (cmd == "serve") return cmd_serve(args);
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
