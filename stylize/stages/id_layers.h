// stylize/stages/id_layers.h — stage "id_layers": LD06 §3.1 ID layers. An ID map (the raster pass
// "layer_id": 1 + the layer of the front-most surface, or an object-ID map; 0 = background) is
// split into the intensity maps of four layers, first .. first + 3 (the paper's RGBA ID image:
// "objects having the same identifier are rendered into a separate color channel").
#pragma once

#include "core/exec.h"
#include "core/image.h"
#include "stylize/stage.h"

namespace aq::stylize {

struct IdLayersParams {
    int first = 0;     //!< layer (ID - 1) of output 0, [0, 1 << 24]
    bool fold = true;  //!< IDs beyond first + 3 go into output 3 (layers packed, not dropped)
};

//! Index of the output (0..3) an ID value v goes to, or -1: k = round(v) - 1 - first.
inline int id_layer_slot(float v, const IdLayersParams& p) {
    if (!(v >= 0.5f) || !(v < 16777216.0f)) return -1;
    const int k = int(v + 0.5f) - 1 - p.first;
    if (k < 0) return -1;
    if (k > 3) return p.fold ? 3 : -1;
    return k;
}

//! out[k] = 1 where ids selects layer first + k, else 0; each one channel of ids' size.
void id_layers(ImageF* const out[4], const ImageF& ids, const IdLayersParams& p, const Exec& ex = {});

void register_id_layers(Registry& r);

}  // namespace aq::stylize
