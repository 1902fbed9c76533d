// core/exec.h — execution policy: how many threads, and reference vs fast traversal.
//
// Algorithms never depend on the policy: a stage's per-pixel maths is a pure function, and the
// traversal only decides the order in which independent output pixels are computed (one writer
// per pixel: stages run blocks of whole rows, the rasterizer tiles), so the bytes cannot depend
// on the thread count.
#pragma once

#include <algorithm>
#include <climits>
#include <cstddef>
#include <memory>
#include <mutex>
#include <vector>

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/image.h"

namespace aq {

enum class Traversal {
    Reference,  //!< plain single-threaded row-major loop: obviously correct, the oracle
    Fast,       //!< oneTBB-parallel (stages: blocks of rows; rasterizer: tiles), vectorisable
};

struct Exec {
    int threads = 0;                        //!< 0 = all hardware threads; >= 1 caps the arena
    Traversal traversal = Traversal::Fast;  //!< Reference forces one thread, row-major
    int tile = 64;                          //!< for_each_tile's tile side; stages run tile / 8 rows per task
    //! Row window of a fused schedule (stylize/pipeline.h CompiledPipeline::row_groups): only the
    //! output rows [row_begin, row_end), clipped to the image, are computed, on the calling thread
    //! (the schedule runs windows of several stripes in parallel). Only variants that declare a row
    //! halo (stylize/stage.h StageVariant::row_halo) are run with a window. Default: every row.
    int row_begin = 0, row_end = INT_MAX;

    static Exec reference() { return {1, Traversal::Reference, 64}; }
    static Exec fast(int threads = 0) { return {threads, Traversal::Fast, 64}; }
    //! This policy restricted to output rows [y0, y1).
    Exec rows(int y0, int y1) const {
        Exec e = *this;
        e.row_begin = y0, e.row_end = y1;
        return e;
    }
    bool windowed() const { return row_begin > 0 || row_end < INT_MAX; }
};

//! The task arena of concurrency n (>= 1), created on first use and kept for the process.
//! A stage pass makes several parallel loops per frame; a fresh arena per loop paid its creation
//! and made the workers join it again each time. task_arena::execute is safe from any thread.
inline tbb::task_arena& arena_for(int n) {
    static std::mutex m;
    static std::vector<std::unique_ptr<tbb::task_arena>> arenas;
    std::lock_guard<std::mutex> lock(m);
    if (arenas.size() <= std::size_t(n)) arenas.resize(std::size_t(n) + 1);
    auto& a = arenas[std::size_t(n)];
    if (!a) a = std::make_unique<tbb::task_arena>(n);
    return *a;
}

//! Runs body() inside a task arena honouring ex.threads.
template <class F>
void with_arena(const Exec& ex, F&& body) {
    const int n = ex.threads > 0 ? ex.threads : tbb::this_task_arena::max_concurrency();
    arena_for(n).execute([&] { body(); });
}

//! Calls f(begin, end) over [0, n) in blocks of `block` indices: one call for Reference (or when
//! n <= block), oneTBB tasks for Fast. f must write only what its own indices own (then the result
//! does not depend on the traversal or the thread count).
template <class F>
void for_each_block(const Exec& ex, std::size_t n, std::size_t block, F&& f) {
    if (ex.traversal == Traversal::Reference || n <= block) {
        f(std::size_t(0), n);
        return;
    }
    with_arena(ex, [&] {
        tbb::parallel_for(std::size_t(0), (n + block - 1) / block,
                          [&](std::size_t b) { f(b * block, std::min(n, (b + 1) * block)); });
    });
}

//! Calls f(Roi tile) over roi: one row-major loop for Reference, tiles on oneTBB for Fast.
//! Each output pixel belongs to exactly one tile; f must only write pixels inside its tile.
template <class F>
void for_each_tile(const Exec& ex, Roi roi, F&& f) {
    if (roi.empty()) return;
    if (ex.traversal == Traversal::Reference) {
        f(roi);
        return;
    }
    const int t = std::max(8, ex.tile);
    with_arena(ex, [&] {
        tbb::parallel_for(
            tbb::blocked_range2d<int>(roi.y0, roi.y1, t, roi.x0, roi.x1, t),
            [&](const tbb::blocked_range2d<int>& r) {
                f(Roi{r.cols().begin(), r.rows().begin(), r.cols().end(), r.rows().end()});
            },
            tbb::simple_partitioner());
    });
}

}  // namespace aq
