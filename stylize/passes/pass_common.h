// stylize/passes/pass_common.h — what every raster-pass registry entry shares: the scene it draws,
// where it reports, the depth-test variants (LD06 §2) and the draw/scale parameters' ranges and docs.
#pragma once

#include <string>
#include <vector>

#include "raster/pass.h"
#include "stylize/declare.h"
#include "stylize/stage.h"

namespace aq::stylize::passes {

//! One depth-test variant of a pass (registered as that pass's variant name).
struct DepthTestVariant {
    const char* name;
    raster::DepthTest test;
    const char* doc;
};
//! The three tests, blurred first (the default wherever LD06 uses the blurred test).
inline constexpr DepthTestVariant kDepthTests[] = {
    {"blurred", raster::DepthTest::Blurred, "the blurred depth test, LD06 eq. 1-2, float depth"},
    {"blurred_rgba8", raster::DepthTest::BlurredRgba8, "the blurred depth test through the paper's RGBA8 depth coding, eq. 3-4"},
    {"binary", raster::DepthTest::Binary, "the binary depth test (LD06 Fig. 2, red; Fig. 9a for particles)"},
};

inline constexpr const char* kViewDoc = "camera, or light: the light's orthographic view fitted to the scene";
inline constexpr const char* kDrawDoc = "all, foliage only, or not_foliage: everything but foliage (docs/ld06.md \"Foliage\")";
inline constexpr const char* kScaleDoc = "raster size as a scale of the output size (LD06: 520/720 = 0.722)";
inline constexpr double kMinScale = 0.05, kMaxScale = 4;

//! The scene a pass draws; throws aq::Error when the pipeline runs without one.
inline const raster::PassScene& scene_of(const StageIO& io) {
    if (!io.globals || !io.globals->scene) throw Error("a raster pass needs a scene (run it through aquarelle render)");
    return *io.globals->scene;
}
//! Where a pass reports non-fatal problems (may be null).
inline std::vector<std::string>* warnings_of(const StageIO& io) { return io.globals ? io.globals->warnings : nullptr; }

}  // namespace aq::stylize::passes
