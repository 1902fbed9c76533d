// stylize/schedule/bands.h — the banded schedule of a row group (pipeline.h RowGroup; Halide's
// compute_at with sliding windows): the image is cut into horizontal stripes run in parallel;
// within a stripe each step computes the next rows its inputs allow, a band at a time, so a band's
// intermediate rows are read by the next steps while they are in the cache; the rows around the
// stripe boundaries (the seams) follow once every stripe is done. Every row of every step is
// computed exactly once.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "core/exec.h"

namespace aq::stylize::schedule {

//! Stripes of a row group: at least this many rows, and four times the group's depth (the seams'
//! windows of neighbouring boundaries and their reads then never meet).
inline constexpr int kMinStripeRows = 32;
//! Stripes per thread: a stalled thread's stripe is taken over by the others (oneTBB stealing);
//! 8 measured 1-3 % faster than 4 at 2 threads (the synthetic frame's rows differ in cost).
inline constexpr int kStripesPerThread = 8;

//! Runs rows(j, y0, y1) for every step j of a group over rows [0, h): step j's rows stay depth[j]
//! rows behind the rows the steps before it have computed (RowGroup::depth; max_depth their
//! largest), band_rows rows at a time, in ex's arena and thread count. Each (j, row) is computed
//! once; calls for one step never overlap in rows.
void run_bands(int h, const std::vector<int>& depth, int max_depth, int band_rows, const Exec& ex,
               const std::function<void(std::size_t j, int y0, int y1)>& rows);

}  // namespace aq::stylize::schedule
