// stylize/stages/stroke_ink.h — stage "stroke_ink": LD06 §4.4 line strokes, "rendered last": the
// strokes pass's ink-coverage map (any size, resampled bilinearly) painted over the washes in one
// ink colour, mix(dst, ink colour, sat(alpha · coverage)) (wash.h glaze_px, over).
#pragma once

#include "core/exec.h"
#include "core/image.h"
#include "stylize/stage.h"

namespace aq::stylize {

//! Ours: a dark sepia ink.
inline constexpr glm::vec3 kInkColor{0.2f, 0.15f, 0.1f};
inline constexpr float kInkAlpha = 0.85f;

struct StrokeInkParams {
    glm::vec3 color = kInkColor;
    float alpha = kInkAlpha;
};

//! dst (4 channels, color's size); ink: one channel, any size.
void stroke_ink(ImageF& dst, const ImageF& color, const ImageF& ink, const StrokeInkParams& p, const Exec& ex = {});

void register_stroke_ink(Registry& r);

}  // namespace aq::stylize
