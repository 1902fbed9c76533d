// tests/stylize/fastmath_test.cpp — stylize/fastmath.h: the deterministic vectorisable pow_c of
// the colour-transmittance model against std::pow, and its exact cases.
#include "stylize/fastmath.h"

#include <algorithm>
#include <cmath>

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

}  // namespace
}  // namespace aq::stylize
