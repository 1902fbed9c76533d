// stylize/stages/id_layers.cpp — see id_layers.h. Pointwise; one row traversal for both schedules.
#include "stylize/stages/id_layers.h"

#include "stylize/stages/toolkit.h"

namespace aq::stylize {

using namespace toolkit;

void id_layers(ImageF* const out[4], const ImageF& ids, const IdLayersParams& p, const Exec& ex) {
    check_input(&ids, 1, Channels::Exactly, "id_layers", "ids");
    const int w = ids.width(), h = ids.height();
    for (int k = 0; k < 4; ++k) {
        check_not_alias(*out[k], &ids, "id_layers", "ids");
        ensure_output(*out[k], w, h, 1);
    }
    const float* in = ids.data();
    for_each_row(ex, w, h, [&](int y, int x0, int x1) {
        float* o[4];
        for (int k = 0; k < 4; ++k) o[k] = out[k]->data() + std::size_t(y) * w;
        const float* r = in + std::size_t(y) * w;
        for (int x = x0; x < x1; ++x) {
            const int s = id_layer_slot(r[x], p);
            for (int k = 0; k < 4; ++k) o[k][x] = s == k ? 1.0f : 0.0f;
        }
    });
}

void register_id_layers(Registry& r) {
    using P = IdLayersParams;
    r.add(declare({.stage = "id_layers",
                   .variant = "split",
                   .doc = "LD06 §3.1: an ID map (1 + layer or object ID, 0 = background) split into four layer intensity maps "
                          "(RGBA ID image)",
                   .inputs = {{"ids", "ld06.layer_id", 1, false}},
                   .outputs = {{"layer0", "ld06.layer.0", 1, false},
                               {"layer1", "ld06.layer.1", 1, false},
                               {"layer2", "ld06.layer.2", 1, false},
                               {"layer3", "ld06.layer.3", 1, false}},
                   .reference = StageVariant::Reference::SharedMaths},
                  ParamTable<P>()
                      .i("first", &P::first, 0, 1 << 24, "layer (ID - 1) written to output layer0; layer1..3 follow")
                      .b("fold", &P::fold,
                         "IDs beyond first + 3 go into layer3 (more layers than one ID image holds are packed, not dropped)"),
                  [](StageIO& io, const P& p, const Exec& ex) {
                      ImageF* const out[4] = {io.out[0], io.out[1], io.out[2], io.out[3]};
                      id_layers(out, *io.in[0], p, ex);
                  }));
}

}  // namespace aq::stylize
