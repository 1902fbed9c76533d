// stylize/schedule/bands.cpp — the banded schedule of a row group (bands.h).
#include "stylize/schedule/bands.h"

#include <algorithm>
#include <cstdint>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace aq::stylize::schedule {

void run_bands(int h, const std::vector<int>& depth, int max_depth, int band_rows, const Exec& ex,
               const std::function<void(std::size_t j, int y0, int y1)>& rows) {
    const std::size_t n = depth.size();
    const int threads = ex.threads > 0 ? ex.threads : tbb::this_task_arena::max_concurrency();
    const int min_stripe = std::max(kMinStripeRows, 4 * max_depth + 4);
    const int S = std::max(1, std::min(kStripesPerThread * threads, h / min_stripe));
    const int R = std::max(1, band_rows);
    auto edge = [&](int k) { return int(std::int64_t(h) * k / S); };
    // Stripe k: each step computes its rows as soon as the rows it reads exist, staying
    // depth rows inside the stripe's inner boundaries.
    auto stripe = [&](int k) {
        const int a = edge(k), b = edge(k + 1);
        std::vector<int> done(n), end(n);
        for (std::size_t j = 0; j < n; ++j) {
            done[j] = a == 0 ? 0 : a + depth[j];
            end[j] = b == h ? h : b - depth[j];
        }
        for (int t = a; t < b;) {
            t = std::min(b, t + R);
            for (std::size_t j = 0; j < n; ++j) {
                const int target = t == b ? end[j] : std::min(end[j], t - depth[j]);
                if (target > done[j]) {
                    rows(j, done[j], target);
                    done[j] = target;
                }
            }
        }
    };
    // The seam at boundary k: the rows each step left on both sides of it.
    auto seam = [&](int k) {
        const int b = edge(k);
        for (std::size_t j = 0; j < n; ++j)
            if (depth[j] > 0) rows(j, b - depth[j], b + depth[j]);
    };
    with_arena(ex, [&] {
        tbb::parallel_for(0, S, stripe);
        tbb::parallel_for(1, S, seam);
    });
}

}  // namespace aq::stylize::schedule
