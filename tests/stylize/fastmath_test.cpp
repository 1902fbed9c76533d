// tests/stylize/fastmath_test.cpp — core/fastmath.h: the deterministic vectorisable pow_c of
// the colour-transmittance model against std::pow, and its exact cases.
#include "stylize/kernels.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace aq::stylize {
namespace {

TEST(FastMath, PowCMatchesStdPow) {
    double worst = 0;
    for (int i = 1; i <= 2000; ++i) {
        const float x = std::pow(10.0f, -6.0f * float(i) / 2000.0f);  // 1e-6 .. 1
        for (float d : {0.0f, 0.3f, 1.0f, 1.0001f, 1.5f, 2.4f, 3.7f, 7.0f, 12.5f, 30.0f}) {
            const double want = std::pow(double(x), double(d));
            const double got = pow_c(x, d);
            if (want > 1e-30) worst = std::max(worst, std::fabs(got - want) / want);
        }
    }
    EXPECT_LT(worst, 1e-5);  // relative; far below an 8-bit output step
    EXPECT_EQ(pow_c(0.0f, 2.0f), 0.0f);
    EXPECT_EQ(pow_c(-0.5f, 2.0f), 0.0f);
    EXPECT_EQ(pow_c(1.0f, 7.0f), 1.0f);
    EXPECT_EQ(pow_c(0.3f, 1.0f), 0.3f);
    EXPECT_TRUE(std::isnan(pow_c(std::nanf(""), 2.0f)));
    EXPECT_TRUE(std::isnan(pow_c(0.5f, std::nanf(""))));
    EXPECT_TRUE(std::isinf(pow_c(INFINITY, 2.0f)));
    for (int i = 1; i < 1000; ++i) {  // darkening never brightens: x^d <= x for d >= 1
        const float x = float(i) / 1000.0f;
        EXPECT_LE(pow_c(x, 1.0000001f), x);
    }
}

std::uint32_t bits_of(float v) { return std::bit_cast<std::uint32_t>(v); }
float from_bits(std::uint32_t b) { return std::bit_cast<float>(b); }

// pow_c_many (eight values in lanes, the rest one by one) gives pow_c's bits for every value: the
// exact cases, the clamps, denormals, infinities, NaNs with payloads, and random bit patterns.
TEST(FastMath, PowCLanesHaveTheScalarBits) {
    std::vector<float> special = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, 2.0f, 1e-40f, -1e-40f, 1.17549435e-38f, 3.0e38f,
                                  3.4e38f, INFINITY, -INFINITY, from_bits(0x7fc00001u), from_bits(0xff812345u),
                                  from_bits(0x7f800001u), 0.999999f, 1.000001f, 1e-7f, 127.0f, -126.0f, 30.0f};
    std::vector<float> xs, ds;
    for (float x : special)
        for (float d : special) xs.push_back(x), ds.push_back(d);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), expo(-2.0f, 12.0f);
    for (int i = 0; i < 200000; ++i) {
        if (i % 2) {
            xs.push_back(from_bits(rng()));
            ds.push_back(i % 4 == 1 ? from_bits(rng()) : expo(rng));
        } else {
            xs.push_back(unit(rng));
            ds.push_back(expo(rng));
        }
    }
    std::vector<float> r(xs.size());
    pow_c_many(xs.data(), ds.data(), r.data(), xs.size());
    std::size_t bad = 0;
    for (std::size_t i = 0; i < xs.size(); ++i) bad += bits_of(r[i]) != bits_of(pow_c(xs[i], ds[i]));
    EXPECT_EQ(bad, 0u);
    // Every tail length, and in place (r is d, then r is x).
    for (std::size_t n = 0; n <= 19; ++n) {
        std::vector<float> d(ds.begin() + 100, ds.begin() + 100 + n), x(xs.begin() + 100, xs.begin() + 100 + n);
        pow_c_many(x.data(), d.data(), d.data(), n);
        for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(bits_of(d[i]), bits_of(pow_c(xs[100 + i], ds[100 + i]))) << n << " " << i;
        std::copy(ds.begin() + 100, ds.begin() + 100 + n, d.begin());
        pow_c_many(x.data(), d.data(), x.data(), n);
        for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(bits_of(x[i]), bits_of(pow_c(xs[100 + i], ds[100 + i]))) << n << " " << i;
    }
}

// A NaN in gives the quiet NaN of x's payload when x is NaN, else of d's, in both forms (not the
// compiler's choice of operand order for x + d).
TEST(FastMath, PowCNaNPayloadComesFromXThenD) {
    const float nx = from_bits(0x7f812345u), nd = from_bits(0xffc54321u);  // x signalling, d quiet
    const std::uint32_t qx = 0x7fc12345u, qd = 0xffc54321u;
    volatile float vx[8] = {nx, nx, 0.5f, nx, 0.5f, nx, 0.25f, nx}, vd[8] = {nd, 2.0f, nd, nd, nd, 0.0f, nd, 1.0f};
    float x8[8], d8[8], r8[8];  // through volatile: computed at run time, not folded by the compiler
    for (int i = 0; i < 8; ++i) x8[i] = vx[i], d8[i] = vd[i];
    pow_c_many(x8, d8, r8, 8);
    for (int i = 0; i < 8; ++i) {
        const std::uint32_t want = x8[i] != x8[i] ? qx : qd;
        EXPECT_EQ(bits_of(pow_c(x8[i], d8[i])), want) << i;
        EXPECT_EQ(bits_of(r8[i]), want) << i;
    }
}

}  // namespace
}  // namespace aq::stylize
