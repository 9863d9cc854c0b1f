#include "core/srgb8.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "core/image_io.h"

namespace penumbra {
namespace {

TEST(Srgb8, CodeIsRoundedTransferFunction) {
    EXPECT_EQ(srgb8Code(0.f), 0);
    EXPECT_EQ(srgb8Code(1.f), 255);
    EXPECT_EQ(srgb8Code(0.5f), 188);  // 255 * 0.7354 = 187.5..., rounded
    EXPECT_EQ(srgb8Code(0.18f), 118);
}

TEST(Srgb8, ThresholdsAreWhereTheCodesStart) {
    const Srgb8 srgb8;
    for (unsigned code = 1; code < 256; ++code) {
        const float t = srgb8.threshold(code);
        EXPECT_EQ(srgb8Code(t), code) << code;
        EXPECT_EQ(srgb8Code(std::nextafter(t, 0.f)), code - 1) << code;
        EXPECT_EQ(srgb8(t), code) << code;
        EXPECT_EQ(srgb8(std::nextafter(t, 0.f)), code - 1) << code;
        if (code > 1) {
            EXPECT_GT(t, srgb8.threshold(code - 1));
        }
    }
}

TEST(Srgb8, AgreesWithTheDefinitionOnRandomFloats) {
    const Srgb8 srgb8;
    std::mt19937 rng(7);
    // Every float in [0, 1] by its bit pattern (the linear segment included), then beyond.
    std::uniform_int_distribution<uint32_t> bits(0, std::bit_cast<uint32_t>(1.f));
    std::uniform_real_distribution<float> wide(-4.f, 64.f);
    for (int i = 0; i < 1'000'000; ++i) {
        const float v = std::bit_cast<float>(bits(rng));
        ASSERT_EQ(srgb8(v), srgb8Code(v)) << v;
        const float w = wide(rng);
        ASSERT_EQ(srgb8(w), srgb8Code(w)) << w;
    }
}

TEST(Srgb8, CodesOfManyValuesAreEachValuesCode) {
    // codes() (the loop that vectorises) against operator(), value by value: the
    // thresholds and the floats either side of them, random floats in [0, 1] and
    // beyond, and what clamps; a count that is no multiple of its blocks.
    const Srgb8 srgb8;
    std::vector<float> values;
    for (unsigned code = 1; code < 256; ++code) {
        const float t = srgb8.threshold(code);
        values.insert(values.end(), {t, std::nextafter(t, 0.f), std::nextafter(t, 2.f)});
    }
    values.insert(values.end(), {-1.f, -0.f, 0.f, 1.f, 2.f, std::numeric_limits<float>::quiet_NaN(),
                                 std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                                 std::numeric_limits<float>::denorm_min()});
    std::mt19937 rng(11);
    std::uniform_int_distribution<uint32_t> bits(0, std::bit_cast<uint32_t>(1.f));
    std::uniform_real_distribution<float> wide(-4.f, 64.f);
    while (values.size() < 100'003) {
        values.push_back(std::bit_cast<float>(bits(rng)));
        values.push_back(wide(rng));
    }
    std::vector<uint8_t> codes(values.size());
    srgb8.codes(values.data(), values.size(), codes.data());
    for (size_t i = 0; i < values.size(); ++i) ASSERT_EQ(codes[i], srgb8(values[i])) << i << ": " << values[i];
    // The codes span the whole range.
    EXPECT_EQ(*std::min_element(codes.begin(), codes.end()), 0);
    EXPECT_EQ(*std::max_element(codes.begin(), codes.end()), 255);
}

TEST(Srgb8, IsSmallEnoughForAThreadsStack) {
    // Image writers make one as a local, also on the preview server's threads,
    // whose stacks are small: its 64 KiB table lives on the heap.
    EXPECT_LE(sizeof(Srgb8), 2048u);
}

TEST(Srgb8, OutOfRangeValuesClamp) {
    const Srgb8 srgb8;
    EXPECT_EQ(srgb8(-1.f), 0);
    EXPECT_EQ(srgb8(-0.f), 0);
    EXPECT_EQ(srgb8(std::numeric_limits<float>::denorm_min()), 0);
    EXPECT_EQ(srgb8(std::numeric_limits<float>::quiet_NaN()), 0);
    EXPECT_EQ(srgb8(2.f), 255);
    EXPECT_EQ(srgb8(std::numeric_limits<float>::infinity()), 255);
    EXPECT_EQ(srgb8(-std::numeric_limits<float>::infinity()), 0);
}

}  // namespace
}  // namespace penumbra
