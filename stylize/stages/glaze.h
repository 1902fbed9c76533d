// stylize/stages/glaze.h — stage "glaze": LD06 §3.1/§4.2 glazing: four washes (layer_wash) in the
// colours of their ramps (color_ramp, resampled bilinearly from the lighting map's size) painted
// back to front (layer 0 first) over the picture so far, or over the paper colour when there is
// none yet. Variants: multiplicative (subtractive-like, the watercolor glaze; default) and
// alpha-over. Per-pixel maths: stylize/stages/wash.h glaze_px.
#pragma once

#include "core/exec.h"
#include "core/image.h"
#include "stylize/stage.h"
#include "stylize/stages/color_ramp.h"

namespace aq::stylize {

//! dst (4 channels, wash's size, alpha 1): base (4 channels of wash's size, or null = the paper
//! colour `paper_color`) glazed with layer k's ramp colour ramp[k].rgb at opacity
//! sat(ramp[k].a · wash[k]), k = 0..3. ramp[k]: 4 channels, all of one (any) size.
void glaze(ImageF& dst, const ImageF* base, const ImageF& wash, const ImageF* const ramp[4], glm::vec3 paper_color,
           bool multiplicative, const Exec& ex = {});

//! The ramps glaze reads, as color_ramp would write them from `lighting` (1 channel) with `ramps`:
//! the fused schedule of color_ramp -> glaze (stylize/stage.h Fusion) computes each ramp row it
//! needs (color_ramp_row) while glazing — rows of layers it skips are never computed, and no
//! ramp image is written. The bytes are those of color_ramp then glaze, for both traversals
//! (the reference runs exactly that).
struct ComputedRamps {
    const ImageF* lighting = nullptr;
    ColorRampParams ramps;
};
void glaze(ImageF& dst, const ImageF* base, const ImageF& wash, const ComputedRamps& ramps, glm::vec3 paper_color,
           bool multiplicative, const Exec& ex = {});

//! The ramps glaze reads: the color_ramp images (ramp[4]), or computed from the lighting map.
struct GlazeRamps {
    const ImageF* const* images = nullptr;  // ramp[4]
    const ComputedRamps* computed = nullptr;
    int width() const { return images ? images[0]->width() : computed->lighting->width(); }
    int height() const { return images ? images[0]->height() : computed->lighting->height(); }
};

//! The fast schedule (glaze.schedule.cpp), which glaze runs for Traversal::Fast after its checks,
//! with dst allocated: the reference's bytes.
void glaze_fast(ImageF& dst, const ImageF* base, const ImageF& wash, const GlazeRamps& src, glm::vec3 paper_color,
                bool multiplicative, const Exec& ex);

void register_glaze(Registry& r);

}  // namespace aq::stylize
