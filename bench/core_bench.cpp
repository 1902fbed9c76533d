// bench/core_bench.cpp — core helpers on hot paths.
//   core/sine/{libm,sine,sine8}/{fast,large}  the hand tremor's sine (core/sine.h) over 2^16
//       arguments: glibc's sinf one call per value (what the tremor used before), the scalar
//       definition, and eight per call; `fast`: |y| < 120 (one fused reduction), `large`:
//       120 <= y < 2120 (the Payne-Hanek reduction: an animation's phase grows 1000 per second)
// Run only these: aquarelle_bench --benchmark_filter=core/
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/sine.h"

namespace {

enum class Sine { kLibm, kScalar, kEight };

std::vector<float> sine_args(bool large) {
    std::vector<float> v(1 << 16);
    for (std::size_t i = 0; i < v.size(); ++i) {
        const float u = float((i * 2654435761u) >> 8 & 0xffffff) / float(1 << 24);  // [0, 1)
        v[i] = large ? 120.0f + 2000.0f * u : -119.0f + 238.0f * u;
    }
    return v;
}

void bm_sine(benchmark::State& st, Sine how, bool large) {
    const std::vector<float> in = sine_args(large);
    std::vector<float> out(in.size());
    for (auto _ : st) {
        if (how == Sine::kEight)
            for (std::size_t i = 0; i < in.size(); i += 8) aq::sine8(&in[i], &out[i]);
        else if (how == Sine::kScalar)
            for (std::size_t i = 0; i < in.size(); ++i) out[i] = aq::sine(in[i]);
        else
            for (std::size_t i = 0; i < in.size(); ++i) out[i] = std::sin(in[i]);
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
    }
    st.SetItemsProcessed(std::int64_t(st.iterations()) * std::int64_t(in.size()));
}

const bool registered = [] {
    for (bool large : {false, true}) {
        const char* range = large ? "large" : "fast";
        benchmark::RegisterBenchmark((std::string("core/sine/libm/") + range).c_str(), bm_sine, Sine::kLibm, large);
        benchmark::RegisterBenchmark((std::string("core/sine/sine/") + range).c_str(), bm_sine, Sine::kScalar, large);
        benchmark::RegisterBenchmark((std::string("core/sine/sine8/") + range).c_str(), bm_sine, Sine::kEight, large);
    }
    return true;
}();

}  // namespace
