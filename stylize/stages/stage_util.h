// stylize/stages/stage_util.h — helpers shared by the stage group A implementations: entry checks
// that name the offending target, border-resolved index tables for padded row/column access, and
// the half-resolution size/sampling convention (see docs/stylize.md "Resolution conventions").
#pragma once

#include <string>
#include <vector>

#include "core/exec.h"
#include "core/image.h"
#include "stylize/kernels.h"
#include "stylize/stage.h"

namespace aq::stylize::detail {

//! Throws aq::Error unless img is non-empty with `channels` channels ("stage: input 'name' ...").
inline void check_input(const ImageF& img, int channels, const std::string& stage, const std::string& name) {
    if (img.empty())
        throw Error(stage + ": input '" + name + "' is empty");
    if (img.channels() != channels)
        throw Error(stage + ": input '" + name + "' has " + std::to_string(img.channels()) +
                    " channels, expected " + std::to_string(channels));
}

//! Throws aq::Error unless img has the same size as `like`.
inline void check_same_size(const ImageF& img, const ImageF& like, const std::string& stage,
                            const std::string& name, const std::string& like_name) {
    if (!img.same_size(like))
        throw Error(stage + ": input '" + name + "' is " + std::to_string(img.width()) + "x" +
                    std::to_string(img.height()) + " but '" + like_name + "' is " +
                    std::to_string(like.width()) + "x" + std::to_string(like.height()));
}

//! The source index of every padded position -pad..n-1+pad under border rule b.
inline std::vector<int> border_table(int n, int pad, Border b) {
    std::vector<int> t(std::size_t(n + 2 * pad));
    for (int i = -pad; i < n + pad; ++i) t[std::size_t(i + pad)] = resolve_border(i, n, b);
    return t;
}

//! Border parameter (0 = clamp, 1 = mirror) of a parameter map.
inline Border border_param(const ParamValues& p, const char* name = "border") {
    auto it = p.find(name);
    return (it != p.end() && it->second != 0.0) ? Border::Mirror : Border::Clamp;
}

//! The pipeline-wide values of a stage call (defaults when a caller passed none).
inline const Globals& globals_of(const StageIO& io) {
    static const Globals kDefault{};
    return io.globals ? *io.globals : kDefault;
}

//! Runs f(y0, y1) over row blocks: one call for Reference, oneTBB row blocks for Fast. Each block
//! writes only its own rows, so results cannot depend on the thread count.
template <class F>
void for_each_row_block(const Exec& ex, int h, F&& f) {
    if (h <= 0) return;
    if (ex.traversal == Traversal::Reference) {
        f(0, h);
        return;
    }
    const int grain = std::max(1, std::min(ex.tile > 0 ? ex.tile / 8 : 8, 16));
    with_arena(ex, [&] {
        tbb::parallel_for(
            tbb::blocked_range<int>(0, h, grain), [&](const tbb::blocked_range<int>& r) { f(r.begin(), r.end()); },
            tbb::simple_partitioner());
    });
}

}  // namespace aq::stylize::detail
