// stylize/stages/stroke_ink.h — stage "stroke_ink": LD06 §4.4 line strokes, "rendered last": the
// strokes pass's ink-coverage map (any size, resampled bilinearly) painted over the washes in one
// ink colour, mix(dst, ink colour, sat(alpha · coverage)) (wash.h glaze_px, over), the colour kept
// as it is where the coverage is 0.
#pragma once

#include "core/exec.h"
#include "core/image.h"
#include "stylize/kernels.h"
#include "stylize/stage.h"

namespace aq::stylize {

//! Ours: a dark sepia ink.
inline constexpr glm::vec3 kInkColor{0.2f, 0.15f, 0.1f};
inline constexpr float kInkAlpha = 0.85f;

struct StrokeInkParams {
    glm::vec3 color = kInkColor;
    float alpha = kInkAlpha;
};

//! The ink's opacity at coverage cov: sat(alpha · cov). Where it is 0 the colour is kept exactly
//! (not glazed with k = 0, which would turn a -0 channel into +0): what the in-place run leaves
//! untouched.
inline float ink_opacity(float alpha, float cov) { return sat(alpha * cov); }

//! dst (4 channels, color's size); ink: one channel, any size. dst may be `color` itself (in
//! place: only inked pixels are written; StageVariant::in_place_input).
void stroke_ink(ImageF& dst, const ImageF& color, const ImageF& ink, const StrokeInkParams& p, const Exec& ex = {});

//! The fast schedule (stroke_ink.schedule.cpp), which the stage runs for Traversal::Fast after its
//! checks, with dst allocated; in_place: dst is color (only the inked pixels are written).
void stroke_ink_fast(ImageF& dst, const ImageF& color, const ImageF& ink, bool in_place, const StrokeInkParams& p,
                     const Exec& ex);

void register_stroke_ink(Registry& r);

}  // namespace aq::stylize
