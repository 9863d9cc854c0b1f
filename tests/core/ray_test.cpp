// nextFloatDown is std::nextafter(x, -inf) for every kind of float.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "core/hash.h"
#include "core/ray.h"

using namespace penumbra;

namespace {
bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }
}  // namespace

TEST(Ray, NextFloatDownEqualsNextafter) {
    const float lim = std::numeric_limits<float>::max(), tiny = std::numeric_limits<float>::denorm_min();
    for (float x : {0.f, -0.f, 1.f, -1.f, tiny, -tiny, lim, -lim, kInfinity, 1e-38f, -1e-38f, 3.5e7f, 0.1f})
        EXPECT_TRUE(sameBits(nextFloatDown(x), std::nextafter(x, -kInfinity))) << x;
    EXPECT_TRUE(std::isnan(nextFloatDown(std::numeric_limits<float>::quiet_NaN())));
    EXPECT_EQ(nextFloatDown(-kInfinity), -kInfinity);
    for (uint64_t i = 0; i < 100000; ++i) {
        uint32_t bits = static_cast<uint32_t>(mix64(i));
        float x;
        std::memcpy(&x, &bits, sizeof x);
        if (std::isnan(x)) continue;
        ASSERT_TRUE(sameBits(nextFloatDown(x), std::nextafter(x, -kInfinity))) << x;
    }
}
