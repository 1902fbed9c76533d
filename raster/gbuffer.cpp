// raster/gbuffer.cpp — the G-buffer targets (core/targets.h target::kGBufferLayout): allocation, raw pointers for the traversals, reuse check.
#include "raster/raster_internal.h"

namespace aq::raster::detail {

// The ten targets are allocated (and zero-filled by ImageF) in parallel when `parallel`: at
// 1080p they are 224 MB whose first touch (page faults) costs as much as the rasterization.
Targets allocate_targets(int W, int H, float bg_depth, bool parallel, std::uint32_t mask) {
    constexpr std::size_t n = std::size(target::kGBufferLayout);
    std::vector<ImageF> imgs(n);
    run_for(parallel, n, [&](std::size_t i) {
        const target::GBufferTarget& t = target::kGBufferLayout[i];
        if (mask & (1u << i)) imgs[i] = ImageF(W, H, t.channels, t.far_background ? bg_depth : 0.0f);
    });
    Targets tg;
    for (std::size_t i = 0; i < n; ++i)
        if (mask & (1u << i)) tg.set(target::kGBufferLayout[i].name, std::move(imgs[i]));
    return tg;
}

TargetPtrs pointers(Targets& tg) {
    auto ptr = [&](const char* name) { return tg.has(name) ? tg.get_mut(name).data() : nullptr; };
    TargetPtrs p;
    p.color = ptr(target::kColor);
    p.ctrl[0] = ptr(target::kCtrlPigment);
    p.ctrl[1] = ptr(target::kCtrlSubstrate);
    p.ctrl[2] = ptr(target::kCtrlEdge);
    p.ctrl[3] = ptr(target::kCtrlAbstraction);
    p.depth = ptr(target::kDepthLinear);
    p.normal = ptr(target::kNormal);
    p.id = ptr(target::kObjectId);
    p.diffuse = ptr(target::kDiffuse);
    p.specular = ptr(target::kSpecular);
    p.width = tg.get(target::kColor).width();
    return p;
}

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
