// Piecewise-constant distributions: the CDF inversion lands in the right cell
// with the right density, and the 2D density integrates to 1.
#include <gtest/gtest.h>

#include <vector>

#include "core/distribution2d.h"

using namespace penumbra;

TEST(Distribution1D, InvertsTheCdfCellByCell) {
    const std::vector<float> f{1.f, 3.f, 0.f, 4.f};
    Distribution1D d(f);
    EXPECT_FLOAT_EQ(d.integral(), 2.f);
    // Densities f / mean(f) on [0, 1).
    EXPECT_FLOAT_EQ(d.pdf(0), 0.5f);
    EXPECT_FLOAT_EQ(d.pdf(1), 1.5f);
    EXPECT_FLOAT_EQ(d.pdf(2), 0.f);
    EXPECT_FLOAT_EQ(d.pdf(3), 2.f);
    // cdf: 0, 1/8, 4/8, 4/8, 1.
    auto s = d.sample(0.0625f);
    EXPECT_EQ(s.cell, 0);
    EXPECT_NEAR(s.x, 0.125f, 1e-6f);
    s = d.sample(0.3125f);
    EXPECT_EQ(s.cell, 1);
    EXPECT_NEAR(s.x, 0.375f, 1e-6f);
    EXPECT_FLOAT_EQ(s.pdf, 1.5f);
    s = d.sample(0.5f);  // the empty cell 2 is skipped
    EXPECT_EQ(s.cell, 3);
    EXPECT_NEAR(s.x, 0.75f, 1e-6f);
    s = d.sample(std::nextafter(1.f, 0.f));
    EXPECT_EQ(s.cell, 3);
    EXPECT_LT(s.x, 1.f);
}

TEST(Distribution1D, AllZeroOrBadValuesSampleUniformly) {
    const std::vector<float> f{0.f, -1.f, std::numeric_limits<float>::quiet_NaN()};
    Distribution1D d(f);
    EXPECT_EQ(d.integral(), 0.f);
    for (int i = 0; i < 3; ++i) EXPECT_FLOAT_EQ(d.pdf(i), 1.f);
    EXPECT_EQ(d.sample(0.5f).cell, 1);
}

TEST(Distribution2D, DensityIntegratesToOneAndMatchesSamples) {
    const int nu = 5, nv = 3;
    std::vector<float> f(nu * nv);
    for (int i = 0; i < nu * nv; ++i) f[size_t(i)] = float((i * 7) % 4);  // some cells empty
    Distribution2D d(f, nu, nv);
    double integral = 0;
    for (int v = 0; v < nv; ++v)
        for (int u = 0; u < nu; ++u) integral += d.pdf(Vec2f{(u + 0.5f) / nu, (v + 0.5f) / nv}) / (nu * nv);
    EXPECT_NEAR(integral, 1.0, 1e-6);
    for (float a = 0.01f; a < 1.f; a += 0.0731f)
        for (float b = 0.02f; b < 1.f; b += 0.0917f) {
            const auto s = d.sample(Vec2f{a, b});
            EXPECT_GT(s.pdf, 0.f);
            EXPECT_FLOAT_EQ(s.pdf, d.pdf(s.uv));
            const int cell = int(s.uv.y * nv) * nu + int(s.uv.x * nu);
            EXPECT_GT(f[size_t(cell)], 0.f);
        }
}
