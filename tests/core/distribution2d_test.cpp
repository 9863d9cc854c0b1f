// Piecewise-constant distributions: the CDF inversion lands in the right cell
// with the right density, and the 2D density integrates to 1.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
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

// The guided search finds, for every u, the cell whose CDF interval holds it,
// also for u on and next to the interval ends, in a peaky row with runs of
// empty cells and cells far narrower than a guide slot.
TEST(Distribution1D, EveryUFallsInItsCellsCdfInterval) {
    std::mt19937 rng(7);
    std::vector<float> f(300);
    for (size_t i = 0; i < f.size(); ++i) {
        const float r = std::uniform_real_distribution<float>(0.f, 1.f)(rng);
        f[i] = i % 7 == 3 || (i > 100 && i < 140) ? 0.f : std::pow(r, 12.f) * (i == 200 ? 1e6f : 1.f);
    }
    Distribution1D d(f);
    // The CDF as the distribution builds it.
    double sum = 0.0;
    for (float v : f) sum += v;
    std::vector<float> cdf(f.size() + 1, 0.f);
    double acc = 0.0;
    for (size_t i = 0; i < f.size(); ++i) {
        acc += f[i];
        cdf[i + 1] = float(acc / sum);
    }
    cdf.back() = 1.f;
    std::vector<float> us;
    for (float c : cdf)
        for (float u : {std::nextafter(c, 0.f), c, std::nextafter(c, 2.f)})
            if (u >= 0.f && u < 1.f) us.push_back(u);
    for (int k = 0; k < 20000; ++k) us.push_back(std::uniform_real_distribution<float>(0.f, 1.f)(rng));
    for (float u : us) {
        const Distribution1D::Sample s = d.sample(u);
        ASSERT_GT(d.pdf(s.cell), 0.f) << "u = " << u;
        ASSERT_LE(cdf[size_t(s.cell)], u) << "u = " << u;
        ASSERT_LT(u, cdf[size_t(s.cell) + 1]) << "u = " << u;
    }
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

// locateLanes (the environment light's batched search) gives each point what
// locate gives it alone, also past its 16-point chunks; sample's density is
// the located cell's cellPdf.
TEST(Distribution2D, LocateLanesMatchesLocateOnePointAtATime) {
    const int nu = 64, nv = 32;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> uni(0.f, 1.f);
    std::vector<float> f(size_t(nu * nv));
    for (float& v : f) v = uni(rng) < 0.2f ? 0.f : std::pow(uni(rng), 8.f);
    Distribution2D d(f, nu, nv);
    const int n = 37;
    std::vector<float> ux(n), uy(n);
    for (int l = 0; l < n; ++l) {
        ux[size_t(l)] = l == 0 ? 0.f : uni(rng);
        uy[size_t(l)] = l == 1 ? std::nextafter(1.f, 0.f) : uni(rng);
    }
    std::vector<Distribution2D::Cell> cells(n);
    d.locateLanes(ux.data(), uy.data(), n, cells.data());
    for (int l = 0; l < n; ++l) {
        const Vec2f u{ux[size_t(l)], uy[size_t(l)]};
        const Distribution2D::Cell one = d.locate(u);
        const Distribution2D::Cell& lane = cells[size_t(l)];
        EXPECT_EQ(lane.uv.x, one.uv.x) << l;
        EXPECT_EQ(lane.uv.y, one.uv.y) << l;
        EXPECT_EQ(lane.column, one.column) << l;
        EXPECT_EQ(lane.row, one.row) << l;
        EXPECT_GT(f[size_t(one.row * nu + one.column)], 0.f) << l;
        const Distribution2D::Sample s = d.sample(u);
        EXPECT_EQ(s.uv.x, one.uv.x) << l;
        EXPECT_EQ(s.pdf, d.cellPdf(one.column, one.row)) << l;
        EXPECT_GT(s.pdf, 0.f) << l;
    }
}
