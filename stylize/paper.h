// stylize/paper.h — paper substrates: the real papers in ../shared/assets/paper, tiled and scaled
// to the output size in the MNPR layout (R,G = normal x,y 0.5-centred; B = height).
#pragma once

#include <future>
#include <string>

#include "core/exec.h"
#include "core/image.h"

namespace aq::stylize {

//! The flat paper's texel values (MNPR layout): normal x, y encoded 0.5 (normal (0, 0, 1)) and
//! height 0.5. Stages read these constants where no paper is bound.
inline constexpr float kFlatPaperNormal = 0.5f;
inline constexpr float kFlatPaperHeight = 0.5f;

struct PaperSpec {
    std::string file;          //!< image path; MNPR layout, or a height/displacement map (see layout)
    std::string layout = "mnpr";  //!< "mnpr": RG normal, B height. "height": normals derived from height
    float scale = 1.0f;        //!< paper texels per output pixel = 1/scale; [0.1, 10]
    float roughness = 1.0f;    //!< MNPR adjust: (tex - 0.5) * roughness + 0.5, [0, 5]
};

//! Loads (cached per file), converts and tiles the paper to width x height, 3 channels; rows in
//! parallel under `ex` (the same values for any traversal or thread count).
//! Throws aq::Error with the path on unreadable files.
ImageF prepare_paper(const PaperSpec& spec, int width, int height, const Exec& ex = Exec::fast());

//! Starts decoding spec's paper file into prepare_paper's cache on another thread, so that it
//! overlaps other work (a one-shot render's scene loading, issue 13 item 3); prepare_paper then
//! waits for that decode instead of starting its own. The returned future waits for the decode
//! when destroyed. An error is not reported here: prepare_paper decodes again and reports it. No
//! value changes: the same file, decoded once.
std::future<void> prefetch_paper(const PaperSpec& spec);

//! Drops the decoded paper files kept by prepare_paper (one-shot renders: the source image is not
//! needed once the paper is prepared at the output size; docs/performance.md "Memory of a
//! one-shot render").
void clear_paper_cache();

//! A flat paper (normal (0,0,1) -> 0.5, 0.5; height 0.5) for pipelines without a paper file.
ImageF flat_paper(int width, int height);

//! max |h - ½| over the paper's heights (channel 2), NaN when some height is NaN: how far the
//! paper can move a wash's border (layer_wash's test for layers that wash to exactly 0). Exact (a
//! maximum), the same on every traversal. run_pipeline computes it once per run for the stages
//! that ask (Globals::paper_height_spread).
float paper_height_spread(const ImageF& paper, const Exec& ex = {});

}  // namespace aq::stylize
