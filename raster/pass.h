// raster/pass.h — LD06 raster passes (Luft & Deussen 2006, ../shared/spec/ld06.md §1-3): the
// scene drawn from the camera or from a directional light's orthographic view into one
// single-channel target, with a depth mode (binary test, or the blurred depth test of eq. 1-2,
// optionally through the paper's RGBA8 depth coding, eq. 3-4) and a blend mode (replace,
// additive with clamp as eq. 12, alpha over). docs/ld06.md "Raster passes".
//
// Same machinery as the G-buffer rasterizer (raster/raster.h): vertex stage without tremor,
// homogeneous clipping, fixed-point setup with the top-left rule, binning into 64x64 tiles.
// Determinism: one writer per tile, fragments of a tile in submission order, every per-fragment
// value a pure function of its inputs; Exec::traversal == Reference runs the plain per-triangle
// loop over the whole image with the same per-fragment function (tests/raster/pass_test.cpp).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/exec.h"
#include "core/image.h"
#include "raster/implicit_surface.h"
#include "core/maths.h"
#include "scenes/layers.h"
#include "scenes/scene.h"

namespace aq::raster {

// ---- LD06 eq. 1-4: the blurred depth test -------------------------------------------------------

//! LD06 eq. 1, Δstep(l, u, v) = 3v̂² − 2v̂³ with v̂ = clamp((v − l)/(u − l), 0, 1) (GLSL smoothstep).
//! l == u (δ = 0, the binary limit) is a step: 1 where v >= l, else 0.
//! Inline: the per-fragment functions of every pass call it.
inline float ld06_step(float l, float u, float v) {
    if (!(u > l)) return v >= l ? 1.0f : 0.0f;
    return maths::smoothstep(l, u, v);
}
//! LD06 eq. 2: visibility of a fragment of normalised depth fd against the stored (blurred) depth
//! D: f_v = Δstep(−δ, +δ, D − fd + β).
inline float blurred_visibility(float D, float fd, float delta, float beta) {
    return ld06_step(-delta, delta, (D - fd) + beta);
}
//! LD06 eq. 3-4: d (clamped to [0, 1]) through the paper's RGBA8 depth texture — channel k holds
//! clamp(4d − k, 0, 1) in 8 bits — and decoded as the channel sum / 4 (about 10 bits).
float quantize_depth_rgba8(float d);

// ---- Pass description -----------------------------------------------------------------------------

enum class PassView { Camera = 0, Light = 1 };
//! Binary: the usual "less" test with depth writes. Blurred: eq. 2 against `depth_map` (no depth
//! writes, f_v weights the fragment). BlurredRgba8: as Blurred, D through quantize_depth_rgba8.
enum class DepthTest { Binary = 0, Blurred = 1, BlurredRgba8 = 2 };
//! Replace: dst = f_v·v. Add: dst = clamp(dst + f_v·v, 0, 1) (eq. 12). Over: a = f_v·alpha,
//! dst = v·a + dst·(1 − a).
enum class Blend { Replace = 0, Add = 1, Over = 2 };
//! Which primitives a pass draws (scene::is_foliage decides what is foliage).
enum class DrawSet { All = 0, Foliage = 1, NonFoliage = 2 };
//! What a fragment writes. Depth: its normalised linear depth (0 near, 1 far; the pass view's
//! range). Lighting: (1 + n·l) / 2, Gooch's t (ld06.md §3). Coverage: 1 (an intensity mask).
//! Shadow: 1 − f_s, the shadow intensity of eq. 5 from a blurred light-view depth map.
//! IntensityTexture: channel `channel` of the material's intensity texture (LD06 §4.3) at the
//! fragment's TEXCOORD_0; 0 for materials without one (they still occlude).
//! LayerId: 1 + the draw's layer (PassScene::layers; 0 = background or no layer); ObjectId: the
//! draw's instance object_id (LD06 §3.1 ID images before they are split into layers).
enum class PassValue { Depth = 0, Lighting = 1, Coverage = 2, Shadow = 3, IntensityTexture = 4, LayerId = 5, ObjectId = 6 };

struct ContourCache;  // raster/strokes.h

//! Prepared frames — the geometry transformed, clipped, set up and binned — shared by the triangle
//! passes of one frame that draw the same view, size and draw set (LD06's depth, shadow, lighting
//! and layer-ID passes all draw the camera view at 520 px). Owned by whoever owns the PassScene of
//! that frame (the render job); not thread-safe: a pipeline's steps run one after the other. The
//! values are those of preparing anew (tests/raster/pass_test.cpp).
class PassFrameCache {
public:
    PassFrameCache();
    ~PassFrameCache();
    PassFrameCache(const PassFrameCache&) = delete;
    PassFrameCache& operator=(const PassFrameCache&) = delete;
    struct Entry;  // raster/pass.cpp
    std::vector<std::unique_ptr<Entry>> entries;
};

//! The scene as every pass of one frame sees it.
struct PassScene {
    const scene::Scene* scene = nullptr;
    scene::Camera camera;
    int width = 0, height = 0;  //!< output image size; pass sizes are scales of it
    scene::Bounds bounds;       //!< world bounds (make_pass_scene)
    glm::vec3 light_dir{0, 0, 1};  //!< world, unit, towards the light (first scene light, else the key light)
    //! The foliage's implicit surface when the scene was abstracted (raster/foliage.h; particles
    //! are placed on it), else null; plant_height is its tree height h.
    const ImplicitSurface* foliage_surface = nullptr;
    float plant_height = 0;
    //! The plant's foliage is painted with LD06 §4.3's technique (raster/foliage.h): the particle
    //! pass renders the foliage materials' intensity-texture detail instead of particles.
    bool foliage_detail = false;
    //! Hand-made strokes of the scene (LD06 §4.4; raster/strokes.h), drawn before the automatic
    //! contours; null = none.
    const std::vector<scene::Stroke>* strokes = nullptr;
    //! LD06 §3.1 layer of every draw (scenes/layers.h), for PassValue::LayerId; null = no layers.
    const scene::LayerTable* layers = nullptr;
    //! View-independent contour data of `scene` (raster/strokes.h), built once per job; null =
    //! built by each strokes pass.
    const ContourCache* contours = nullptr;
    //! Prepared frames shared by this frame's passes; null = every pass prepares its own.
    PassFrameCache* frames = nullptr;
};

//! Fills bounds and light direction. Throws aq::Error for a scene without finite extent.
PassScene make_pass_scene(const scene::Scene& sc, const scene::Camera& cam, int width, int height);

//! One view of a pass: the camera used for projection, the raster size, and the eye-depth range
//! mapped to normalised depth 0..1.
struct PassViewSetup {
    scene::Camera camera;
    int width = 0, height = 0;
    float depth_near = 0, depth_far = 1;
    float normalized(float eye_depth) const { return (eye_depth - depth_near) / (depth_far - depth_near); }
};

//! Camera: the scene camera at round(scale·W) x round(scale·H); depth range = the eye depths of
//! the bounds' corners, clipped to [znear, zfar]. Light: orthographic, looking along the light
//! direction at the bounding sphere (centre c, radius R), square round(scale·max(W, H)); depth
//! range = the sphere's [0, 2R]. Throws aq::Error for bad scales or a zero-area light frustum.
PassViewSetup pass_view(const PassScene& ps, PassView view, float scale);

//! Normalised light-view depth and pixel coordinates of a world point (for the shadow test).
struct LightSample {
    float x, y;   //!< continuous pixel coordinates in a light map of size w x h
    float depth;  //!< normalised light depth
};
LightSample light_space(const PassViewSetup& light, glm::vec3 world, int map_w, int map_h);

// Ours: LD06 gives no values for δ and β. δ = 0.05 of the fitted depth range keeps the band of
// semi-visible fragments narrow; β = δ keeps an object just in front fully visible (LD06 §2).
inline constexpr float kPassDelta = 0.05f;
// Ours: LD06 §3.3 gives no values. A lit surface tested against its own (blurred) light depth
// has D - f_d near 0, so it is fully lit only when β >= δ; β a little above δ absorbs the blur of
// foliage depth (on the dense oak, β = 0.01 left most lit leaves in shadow; 0.05 does not).
inline constexpr float kShadowDelta = 0.04f;
inline constexpr float kShadowBeta = 0.05f;

struct TrianglePass {
    PassView view = PassView::Camera;
    float scale = 1.0f;             //!< raster size as a scale of the output size, [0.05, 4]
    DrawSet draw = DrawSet::All;
    PassValue value = PassValue::Coverage;
    DepthTest test = DepthTest::Binary;
    float delta = kPassDelta;       //!< δ of eq. 2 (blurred tests), [0, 1]
    float beta = 0.0f;              //!< β of eq. 2, [-1, 1]
    Blend blend = Blend::Replace;
    float alpha = 1.0f;             //!< fragment alpha for Blend::Over, [0, 1]
    int channel = 0;                //!< IntensityTexture: 0 = R, 1 = G, 2 = B
    //! LayerId, ObjectId: false = foliage (the implicit surface, or the modelled leaves under the
    //! texture technique) occludes but writes the background, so no object layer paints the crown:
    //! the particle pass's crown map does (docs/ld06.md "Leafy outlines").
    bool foliage_layer = true;
    float lighting_background = 0;  //!< Lighting: value where nothing is drawn, [0, 1]
    const ImageF* depth_map = nullptr;   //!< Blurred tests: the (blurred) depth of this view, 1 channel
    //! Shadow value: the blurred light-view depth map (1 channel) and its test.
    const ImageF* shadow_map = nullptr;
    DepthTest shadow_test = DepthTest::Blurred;
    float shadow_delta = kShadowDelta, shadow_beta = kShadowBeta;  //!< β >= δ keeps lit surfaces fully lit
};

//! Renders `p` into `out` (1 channel at the pass view's size; background 1 for Depth,
//! lighting_background for Lighting, else 0).
//! `out`'s storage is reused when it already has that size. Throws aq::Error on invalid
//! parameters or missing maps (checked before allocating). Warnings (dropped triangles, nothing
//! drawn) are appended to *warnings.
void render_triangle_pass(ImageF& out, const PassScene& ps, const TrianglePass& p, const Exec& ex = {},
                          std::vector<std::string>* warnings = nullptr);

}  // namespace aq::raster
