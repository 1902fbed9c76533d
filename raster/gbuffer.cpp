// raster/gbuffer.cpp — the G-buffer targets (core/targets.h target::kGBufferLayout): allocation, raw pointers for the traversals, reuse check.
#include "raster/raster_internal.h"

namespace aq::raster::detail {

// The ten targets are allocated (and zero-filled by ImageF) in parallel when `parallel`: at
// 1080p they are 224 MB whose first touch (page faults) costs as much as the rasterization.
Targets allocate_targets(int W, int H, float bg_depth, bool parallel) {
    constexpr std::size_t n = std::size(target::kGBufferLayout);
    std::vector<ImageF> imgs(n);
    run_for(parallel, n, [&](std::size_t i) {
        const target::GBufferTarget& t = target::kGBufferLayout[i];
        imgs[i] = ImageF(W, H, t.channels, t.far_background ? bg_depth : 0.0f);
    });
    Targets tg;
    for (std::size_t i = 0; i < n; ++i) tg.set(target::kGBufferLayout[i].name, std::move(imgs[i]));
    return tg;
}

TargetPtrs pointers(Targets& tg) {
    TargetPtrs p;
    p.color = tg.get_mut(target::kColor).data();
    p.ctrl[0] = tg.get_mut(target::kCtrlPigment).data();
    p.ctrl[1] = tg.get_mut(target::kCtrlSubstrate).data();
    p.ctrl[2] = tg.get_mut(target::kCtrlEdge).data();
    p.ctrl[3] = tg.get_mut(target::kCtrlAbstraction).data();
    p.depth = tg.get_mut(target::kDepthLinear).data();
    p.normal = tg.get_mut(target::kNormal).data();
    p.id = tg.get_mut(target::kObjectId).data();
    p.diffuse = tg.get_mut(target::kDiffuse).data();
    p.specular = tg.get_mut(target::kSpecular).data();
    p.width = tg.get(target::kColor).width();
    return p;
}

bool reusable(const Targets& t, int W, int H) {
    if (t.all().size() != std::size(target::kGBufferLayout)) return false;
    for (const target::GBufferTarget& g : target::kGBufferLayout) {
        if (!t.has(g.name)) return false;
        const ImageF& img = t.get(g.name);
        if (img.width() != W || img.height() != H || img.channels() != g.channels) return false;
    }
    return true;
}

}  // namespace aq::raster::detail
