// raster/gbuffer.cpp — the G-buffer targets (core/targets.h target::kGBufferLayout): allocation, raw pointers for the traversals, reuse check.
#include "raster/raster_internal.h"

namespace aq::raster::detail {

Targets allocate_targets(int W, int H, float bg_depth, std::uint32_t mask) {
    Targets tg;
    for (const target::GBufferTarget& t : target::kGBufferLayout)
        if (mask & target::gbuffer_bit(t.name)) tg.set(t.name, ImageF(W, H, t.channels, t.far_background ? bg_depth : 0.0f));
    return tg;
}

// The tiled traversal's fresh targets (issue 13): at 1080p 174-224 MB whose fill was a second
// pass over memory the tiles then overwrite.
Targets allocate_targets_unfilled(int W, int H, std::uint32_t mask) {
    Targets tg;
    for (const target::GBufferTarget& t : target::kGBufferLayout)
        if (mask & target::gbuffer_bit(t.name)) tg.set(t.name, ImageF(W, H, t.channels, kUninitialized));
    return tg;
}

namespace {
template <class T, class Tg>
TargetPtrsOf<T> pointers_of(Tg& tg) {
    TargetPtrsOf<T> p;
    for (std::size_t i = 0; i < gbuffer_slot::kCount; ++i) {
        const char* name = target::kGBufferLayout[i].name;
        if (!tg.has(name)) continue;
        if constexpr (std::is_const_v<T>)
            p.at[i] = tg.get(name).data();
        else
            p.at[i] = tg.get_mut(name).data();
    }
    p.width = tg.get(target::kColor).width();
    return p;
}
}  // namespace

TargetPtrs pointers(Targets& tg) { return pointers_of<float>(tg); }
TargetPtrsOf<const float> pointers(const Targets& tg) { return pointers_of<const float>(tg); }

bool reusable(const Targets& t, int W, int H, std::uint32_t mask) {
    std::size_t want = 0;
    for (std::size_t i = 0; i < std::size(target::kGBufferLayout); ++i) {
        if (!(mask & (1u << i))) continue;
        const target::GBufferTarget& g = target::kGBufferLayout[i];
        ++want;
        if (!t.has(g.name)) return false;
        const ImageF& img = t.get(g.name);
        if (img.width() != W || img.height() != H || img.channels() != g.channels) return false;
    }
    return t.all().size() == want;
}

}  // namespace aq::raster::detail
