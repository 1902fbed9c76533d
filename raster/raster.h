// raster/raster.h — deterministic tile rasterizer: scene -> watercolor G-buffer (spec §1-3).
//
// Pipeline (docs/raster.md): vertex stage (MVP, WC17 eq. 1-2 hand tremor, WC17 §3.2 bleeding
// displacement) -> homogeneous clipping (near, far, guard band) -> fixed-point triangle setup
// (8 subpixel bits, top-left rule) -> binning into 64x64 tiles in submission order -> per-tile
// visibility + deferred watercolor material (spec §3, WC17 eq. 3-6) -> optional SSAA resolve.
// Exec::traversal == Reference runs the plain single-threaded per-triangle bounding-box
// rasterizer with the same fixed-point rules and the same per-fragment functions; the tiled
// oneTBB path must match it bit for bit (tests/raster).
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/color.h"
#include "core/exec.h"
#include "core/targets.h"
#include "scenes/scene.h"

namespace aq::raster {

//! The tile side in pixels of every tiled traversal in raster — the G-buffer's triangles, the LD06
//! passes, sprites and strokes: each bins its primitives into tiles of this side and gives every
//! tile one writer. 64: one 64-bit coverage word per tile row (raster_internal.h CoverageBits).
inline constexpr int kTile = 64;

//! Hand tremor, spec §2 / WC17 eq. 1-2 in MNPR's form; defaults are MNPR's.
struct TremorParams {
    float tremor_px = 4;    //!< amplitude in output pixels, [0, 50]
    float front = 0.4f;     //!< a in eq. 2; the weight is min(sat(1.2 N.V), 1 - front)
    float speed = 10;       //!< s in eq. 1 (MNPR scales it by 100)
    float frequency = 10;   //!< f in eq. 1 (MNPR scales it by 10)
    bool enabled = true;
};

struct RenderSettings {
    int width = 1280, height = 720;
    int ssaa = 1;                   //!< ordered-grid supersampling factor per axis, [1, 4]
    //! Silhouette antialiasing when ssaa == 1 (docs/raster.md "Coverage antialiasing"): Coverage
    //! gives the pixels along silhouettes the coverage of the 4x4 samples of ssaa 4 as alpha (and
    //! the uncovered ones there their covered neighbours' values); None keeps one sample per pixel.
    enum class Antialias { None, Coverage } antialias = Antialias::Coverage;
    int frame = 0;                  //!< frame number; T = frame / fps drives the tremor
    float fps = 24;
    Exec exec;                      //!< threads; Reference = plain per-pixel reference rasterizer
    bool cull_backfaces = false;    //!< never culls double-sided materials
    TremorParams tremor;
    bool bleed_displacement = true; //!< WC17 §3.2: push bleeding vertices along their normal
    enum class Turbulence { ImageSpace, ObjectSpace } turbulence = Turbulence::ImageSpace;  //!< eq. 6 variant
    glm::vec3 substrate_color{1};   //!< Cp, paper colour for dilution / fading (in the working space)
    //! Colour space of the G-buffer colour (core/color.h; docs/look.md "Colour management").
    WorkingSpace working_space = WorkingSpace::Display;
    //! The G-buffer targets the caller needs (target::gbuffer_bit of each; colour and depth are
    //! always produced). The fast single-sample traversal allocates and writes only these: a
    //! WC18 frame reads 21 of the 27 floats per pixel (no normal, object_id, diffuse, specular),
    //! ~50 MB less memory written per 1080p frame. The values of every target produced are the
    //! same as with all targets; the reference traversal and supersampling produce all ten.
    std::uint32_t targets = target::kAllGBufferTargets;
};

//! Renders the G-buffer of `scene` seen by `camera` (docs/raster.md "Targets"):
//! color (RGBA, straight alpha = coverage), ctrl.pigment, ctrl.substrate, ctrl.edge,
//! ctrl.abstraction (RGB control in [-1,1], A coverage), depth.linear (eye-space distance along
//! -Z, background = camera.zfar), normal (view space, background 0), object_id (exact integer,
//! 0 = background), diffuse and specular (key-light terms). All at width x height.
//! Throws aq::Error on invalid settings or sizes (checked before allocating). Non-fatal problems
//! (dropped non-finite triangles, ...) are appended to *warnings.
Targets render_gbuffer(const scene::Scene& scene, const scene::Camera& camera,
                       const RenderSettings& settings,
                       std::vector<std::string>* warnings = nullptr);

//! Same as render_gbuffer, writing into `out`: when `out` already holds the targets at this
//! size (a previous frame) and ssaa == 1 their memory is reused, which saves the allocation and
//! first-touch of ~224 MB per 1080p frame (animations, benchmarks); otherwise `out` is replaced.
//! Tiles that held only background in the frame that last wrote `out` and do again are not
//! written, when every target still carries that frame's stamp (ImageF::stamp; any mutable
//! access to an image clears it). The bytes are identical to render_gbuffer's, provided nobody
//! writes a target through a pointer taken before the previous render (docs/raster.md
//! "Background tiles kept between frames"). On an exception `out` is left valid but unspecified.
void render_gbuffer_into(Targets& out, const scene::Scene& scene, const scene::Camera& camera,
                         const RenderSettings& settings,
                         std::vector<std::string>* warnings = nullptr);

//! Debug hook for watertightness tests: per pixel (of the supersampled grid), the number of
//! triangles whose coverage test passes there, after clipping, culling and snapping, with no depth
//! test. One channel, exact small integers. Uses the traversal chosen in settings.exec.
ImageF debug_coverage_count(const scene::Scene& scene, const scene::Camera& camera,
                            const RenderSettings& settings,
                            std::vector<std::string>* warnings = nullptr);

}  // namespace aq::raster
