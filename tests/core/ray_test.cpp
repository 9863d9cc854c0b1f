// nextFloatDown is std::nextafter(x, -inf) for every kind of float; RayLanes::rays
// transposes the lanes into Rays bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "core/hash.h"
#include "core/ray.h"
#include "core/ray_lanes.h"

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

TEST(RayLanes, RaysAreTheLanesBitForBitAndNothingPastTheCount) {
    // Every component of every lane a distinct value (lane and component in
    // the bits), so that a lane or component out of place shows.
    RayLanes lanes;
    float* const components[8] = {lanes.ox, lanes.oy, lanes.oz, lanes.dx, lanes.dy, lanes.dz, lanes.tnear, lanes.tfar};
    for (int c = 0; c < 8; ++c)
        for (int l = 0; l < RayLanes::kWidth; ++l) components[c][l] = float(100 * c + l) + 0.25f;
    lanes.ox[3] = -0.f;
    lanes.tfar[12] = kInfinity;
    for (int count = 0; count <= RayLanes::kWidth; ++count) {
        Ray out[RayLanes::kWidth + 1];
        const Ray sentinel{Vec3f{-7.f}, Vec3f{-7.f}, -7.f, -7.f};
        for (Ray& r : out) r = sentinel;
        lanes.rays(count, out);
        for (int l = 0; l <= RayLanes::kWidth; ++l) {
            const Ray want = l < count ? lanes.ray(l) : sentinel;
            EXPECT_EQ(std::memcmp(&out[l], &want, sizeof(Ray)), 0) << "count " << count << ", lane " << l;
        }
    }
    EXPECT_TRUE(sameBits(lanes.ray(3).o.x, -0.f));
    EXPECT_EQ(lanes.ray(12).tfar, kInfinity);
    EXPECT_EQ(lanes.ray(9).d.y, 409.25f);
}
