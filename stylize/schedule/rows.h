// stylize/schedule/rows.h — the schedules every image stage shares (docs/stylize.md "The one
// traversal, and why whole rows"): the plain reference loop, blocks of whole rows on oneTBB (with
// row windows for banded runs), one row at a time, and a parallel whole-image test. A stage writes
// its maths once and picks one of these; pointwise.h builds on them.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include "core/exec.h"

namespace aq::stylize::schedule {

//! Rows per oneTBB task: tile / 8 within [1, 16] (8 at the default tile). At 1080p ~135 tasks,
//! enough to balance 2-8 threads, few enough rows to stay in L2.
inline int row_grain(const Exec& ex) { return std::max(1, std::min(ex.tile > 0 ? ex.tile / 8 : 8, 16)); }

//! Runs f(y0, y1) over blocks of rows [0, h): one call f(0, h) for Reference, oneTBB blocks of
//! row_grain rows for Fast. Each block writes only its own rows and every value depends only on
//! the inputs, so the bytes are the same for every traversal and thread count. With a row window
//! (Exec::rows, a fused schedule's band): one call over the window's rows within [0, h), on the
//! calling thread, none when they are empty.
template <class F>
void for_each_row_block(const Exec& ex, int h, F&& f) {
    const int y0 = std::max(0, ex.row_begin), y1 = std::min(h, ex.row_end);
    if (y1 <= y0) return;
    if (ex.traversal == Traversal::Reference || ex.windowed()) {
        f(y0, y1);
        return;
    }
    with_arena(ex, [&] {
        tbb::parallel_for(
            tbb::blocked_range<int>(0, h, row_grain(ex)), [&](const tbb::blocked_range<int>& r) { f(r.begin(), r.end()); },
            tbb::simple_partitioner());
    });
}

//! Whether pred(i) holds for some i in [0, n): one loop for Reference, oneTBB blocks for Fast that
//! stop once an answer is found. The answer does not depend on the traversal (no order, no float
//! reduction): for the whole-image checks stages make before choosing a schedule.
template <class F>
bool any_index(const Exec& ex, std::size_t n, F&& pred) {
    if (ex.traversal == Traversal::Reference) {
        for (std::size_t i = 0; i < n; ++i)
            if (pred(i)) return true;
        return false;
    }
    constexpr std::size_t kGrain = 1 << 16, kChunk = 256;
    std::atomic<bool> found{false};
    with_arena(ex, [&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kGrain), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i < r.end(); i += kChunk) {
                if (found.load(std::memory_order_relaxed)) return;
                // A chunk without early exit: the OR of a simple predicate vectorises.
                bool any = false;
                for (std::size_t j = i, e = std::min(i + kChunk, r.end()); j < e; ++j) any |= bool(pred(j));
                if (any) {
                    found.store(true, std::memory_order_relaxed);
                    return;
                }
            }
        });
    });
    return found.load();
}

//! for_each_row_block, one row at a time: row(y, 0, w) for every row (x0, x1 = the pixels of the
//! row the callee loops over). Whole rows rather than 2-D tiles: the stages are pointwise or read
//! a few pixels around, so tiles buy no cache reuse, while 64-pixel row pieces restart the
//! hardware prefetcher on every row; measured at 1080p, one thread, a tiled traversal was 20-50 %
//! slower than the plain loop (docs/performance.md).
template <class F>
void for_each_row(const Exec& ex, int w, int h, F&& row) {
    if (w <= 0) return;
    for_each_row_block(ex, h, [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y) row(y, 0, w);
    });
}

//! The plain reference schedule (docs/stylize.md "Algorithm and schedule"): px(x, y) for every
//! pixel, row-major, on the calling thread. A stage whose fast schedule restates its per-pixel
//! function in row kernels (chunks, packing, vector code) runs this loop over the per-pixel
//! function itself for Traversal::Reference, so the registry-wide test
//! (tests/stylize/registry_traversal_test.cpp) compares two independent computations.
template <class F>
void plain_loop(int w, int h, F&& px) {
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) px(x, y);
}

}  // namespace aq::stylize::schedule
