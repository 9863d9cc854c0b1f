// Power-proportional light selection: picks in proportion to power, the
// probabilities MIS asks for, and the rescaled number handed back for reuse.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "lights/light_set.h"
#include "lights/power_light_picker.h"

using namespace penumbra;

TEST(PowerLightPicker, PicksInProportionToPowerAndRescalesU) {
    const PowerLightPicker picker(std::vector<double>{1.0, 0.0, 3.0});
    const Vec3f p{1, 2, 3}, n{0, 1, 0};
    EXPECT_FLOAT_EQ(picker.probability(0, p, n), 0.25f);
    EXPECT_FLOAT_EQ(picker.probability(1, p, n), 0.f);
    EXPECT_FLOAT_EQ(picker.probability(2, p, n), 0.75f);
    const LightPicker::Pick a = picker.pick(0.125f, p, n);
    EXPECT_EQ(a.index, 0u);
    EXPECT_FLOAT_EQ(a.probability, 0.25f);
    EXPECT_FLOAT_EQ(a.u, 0.5f);
    const LightPicker::Pick b = picker.pick(0.625f, p, n);
    EXPECT_EQ(b.index, 2u);
    EXPECT_FLOAT_EQ(b.probability, 0.75f);
    EXPECT_FLOAT_EQ(b.u, 0.5f);
    // A light without power is never picked; the rescaled u stays in [0, 1) and
    // is uniform within each light's share.
    int count[3] = {};
    int lowHalf[3] = {};
    constexpr int kN = 4000;
    for (int i = 0; i < kN; ++i) {
        const LightPicker::Pick k = picker.pick((float(i) + 0.5f) / float(kN), p, n);
        ASSERT_LT(k.u, 1.f);
        ASSERT_GE(k.u, 0.f);
        ++count[k.index];
        lowHalf[k.index] += k.u < 0.5f;
    }
    EXPECT_EQ(count[1], 0);
    EXPECT_EQ(count[0], kN / 4);
    EXPECT_EQ(lowHalf[0], count[0] / 2);
    EXPECT_EQ(lowHalf[2], count[2] / 2);
}

TEST(PowerLightPicker, WithoutPowerEveryLightIsEquallyLikely) {
    const PowerLightPicker picker(std::vector<double>{0.0, -2.0, 0.0, 0.0});
    for (size_t j = 0; j < 4; ++j) EXPECT_FLOAT_EQ(picker.probability(j, Vec3f{}, Vec3f{}), 0.25f);
    EXPECT_EQ(picker.pick(0.6f, Vec3f{}, Vec3f{}).index, 2u);
}

// Issue 43: two sphere lights of radiance 3e38 have powers beyond the largest
// float; their float total was infinite and every probability inf / inf, so
// power selection picked neither. In double precision they split evenly.
TEST(PowerLightPicker, LightsBrighterThanTheFloatRangeArePickedByPower) {
    Scene s;
    Material lamp;
    lamp.kd = Rgb(0.f);
    lamp.ke = Rgb(3e38f);
    s.materials = {lamp};
    s.spheres.push_back(Sphere{Vec3f{-1, 2, 0}, 0.5f, 0});
    s.spheres.push_back(Sphere{Vec3f{1, 2, 0}, 0.5f, 0});
    const LightSet lights(s);
    ASSERT_EQ(lights.size(), 2u);
    EXPECT_GT(lights[0].power(), double(std::numeric_limits<float>::max()));
    EXPECT_TRUE(std::isfinite(lights[0].power() + lights[1].power()));
    const PowerLightPicker& picker = lights.powerPicker();
    EXPECT_FLOAT_EQ(picker.probability(0, Vec3f{}, Vec3f{}), 0.5f);
    EXPECT_FLOAT_EQ(picker.probability(1, Vec3f{}, Vec3f{}), 0.5f);
    EXPECT_EQ(picker.pick(0.75f, Vec3f{}, Vec3f{}).index, 1u);
}

TEST(PowerLightPicker, AnInfiniteTotalFallsBackToEqualChances) {
    const double inf = std::numeric_limits<double>::infinity();
    const PowerLightPicker picker(std::vector<double>{inf, 1.0});
    EXPECT_FLOAT_EQ(picker.probability(0, Vec3f{}, Vec3f{}), 0.5f);
    EXPECT_FLOAT_EQ(picker.probability(1, Vec3f{}, Vec3f{}), 0.5f);
}
