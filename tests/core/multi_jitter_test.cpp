// The multi-jittered sampler: stratification in 2D and in both 1D
// projections, purity, and faster convergence than independent samples.
#include "core/multi_jitter.h"
#include "core/multi_jitter_lanes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <vector>

#include "core/hash.h"

using namespace penumbra;

TEST(MultiJitter, PermutationIsABijection) {
    for (uint32_t n : {1u, 2u, 3u, 7u, 16u, 100u, 1000u}) {
        for (uint32_t p : {0u, 1u, 12345u}) {
            std::set<uint32_t> seen;
            for (uint32_t i = 0; i < n; ++i) seen.insert(permuteIndex(i, n, p));
            EXPECT_EQ(seen.size(), n);
            EXPECT_LT(*seen.rbegin(), n);
        }
    }
}

TEST(MultiJitter, SquareSetsAreStratifiedIn2DAndBothProjections) {
    for (uint32_t k : {2u, 4u, 8u, 16u}) {
        const uint32_t n = k * k;
        for (uint32_t pattern : {1u, 77u, 0xdeadbeefu}) {
            std::set<uint32_t> cells, xs, ys;
            for (uint32_t s = 0; s < n; ++s) {
                Vec2f u = multiJitter2D(s, n, pattern);
                ASSERT_GE(u.x, 0.f);
                ASSERT_LT(u.x, 1.f);
                ASSERT_GE(u.y, 0.f);
                ASSERT_LT(u.y, 1.f);
                cells.insert(uint32_t(u.y * k) * k + uint32_t(u.x * k));
                xs.insert(uint32_t(u.x * n));
                ys.insert(uint32_t(u.y * n));
            }
            EXPECT_EQ(cells.size(), n) << "k=" << k << ": one sample per grid cell";
            EXPECT_EQ(xs.size(), n) << "k=" << k << ": n-rooks in x";
            EXPECT_EQ(ys.size(), n) << "k=" << k << ": n-rooks in y";
        }
    }
}

TEST(MultiJitter, NonSquareSetsUseDistinctCells) {
    for (uint32_t n : {2u, 3u, 5u, 10u, 24u}) {
        MjGrid g = mjGrid(n);
        std::set<uint32_t> cells;
        for (uint32_t s = 0; s < n; ++s) {
            Vec2f u = multiJitter2D(s, n, 99u);
            cells.insert(uint32_t(u.y * g.rows) * g.cols + uint32_t(u.x * g.cols));
        }
        EXPECT_EQ(cells.size(), n);
    }
}

TEST(MultiJitter, SamplesArePureFunctionsOfTheirInputs) {
    EXPECT_EQ(mjPattern(1, 2, 3, 4), mjPattern(1, 2, 3, 4));
    EXPECT_NE(mjPattern(1, 2, 3, 4), mjPattern(1, 2, 3, 5));
    EXPECT_NE(mjPattern(1, 2, 3, 4), mjPattern(2, 2, 3, 4));
    Vec2f a = multiJitter2D(5, 16, 42), b = multiJitter2D(5, 16, 42);
    EXPECT_EQ(a.x, b.x);
    EXPECT_EQ(a.y, b.y);
    Vec2f c = multiJitter2D(5, 16, 43);
    EXPECT_TRUE(a.x != c.x || a.y != c.y);
}

TEST(MultiJitter, ConvergesFasterThanIndependentSamples) {
    // A smooth integrand over [0,1]^2 with a known integral:
    // int int sin(pi x) * exp(y) dx dy = (2/pi) * (e - 1).
    const double exact = (2.0 / M_PI) * (std::exp(1.0) - 1.0);
    auto f = [](Vec2f u) { return std::sin(M_PI * u.x) * std::exp(double(u.y)); };
    const uint32_t n = 256;
    const int trials = 200;
    double errMj = 0, errRandom = 0;
    for (int t = 0; t < trials; ++t) {
        double sumMj = 0, sumRandom = 0;
        for (uint32_t s = 0; s < n; ++s) {
            sumMj += f(multiJitter2D(s, n, mjPattern(7, uint64_t(t), 0, 0)));
            uint64_t h = hashValues({uint64_t(t), s});
            sumRandom += f(Vec2f{toUnitFloat(h), toUnitFloat(mix64(h))});
        }
        errMj += std::pow(sumMj / n - exact, 2);
        errRandom += std::pow(sumRandom / n - exact, 2);
    }
    const double rmseMj = std::sqrt(errMj / trials), rmseRandom = std::sqrt(errRandom / trials);
    const double ratio = rmseMj / rmseRandom;
    std::cout << "[ measured ] RMSE multi-jittered " << rmseMj << ", independent " << rmseRandom << ", ratio " << ratio
              << " (n = 256)\n";
    RecordProperty("rmse_ratio", std::to_string(ratio));
    EXPECT_LT(ratio, 0.1);
}

TEST(MultiJitter, TabulatedSetsGiveTheSameSamples) {
    // The renderer tabulates its pixel sets' permutations; images must not
    // depend on it. Square and non-square sets, and grids past the table size
    // (which fall back to the permutations).
    for (uint32_t n : {1u, 2u, 8u, 16u, 100u, 4096u, 5000u}) {
        for (uint32_t p : {0u, 7u, 0xdeadbeefu}) {
            const MultiJitterSet direct(n, p), tabulated(n, p, true);
            for (uint32_t s = 0; s < n; ++s) {
                const Vec2f a = direct.sample(s), b = tabulated.sample(s);
                ASSERT_EQ(a.x, b.x) << "n " << n << " pattern " << p << " sample " << s;
                ASSERT_EQ(a.y, b.y) << "n " << n << " pattern " << p << " sample " << s;
            }
        }
    }
}

TEST(MultiJitter, LanesGiveEachLanesSetsSamples) {
    // The renderer draws a block's pixel sets as lanes where their grid holds
    // exactly n cells and fits the tables; every lane's points are its set's.
    EXPECT_FALSE(MultiJitterLanes::supports(0));
    EXPECT_FALSE(MultiJitterLanes::supports(5));     // 2 x 3 cells
    EXPECT_FALSE(MultiJitterLanes::supports(5000));  // 70 x 72 > the tables
    for (uint32_t n : {1u, 2u, 4u, 8u, 9u, 12u, 100u, 4096u}) {
        ASSERT_TRUE(MultiJitterLanes::supports(n)) << n;
        MultiJitterLanes lanes(n);
        uint32_t patterns[MultiJitterLanes::kLanes];
        for (int l = 0; l < MultiJitterLanes::kLanes; ++l) {
            patterns[l] = static_cast<uint32_t>(mix64(uint64_t(n) * 131 + uint64_t(l)));
            lanes.setLane(l, patterns[l]);
        }
        lanes.setLane(3, 0xdeadbeefu);  // a lane set again takes its new set
        patterns[3] = 0xdeadbeefu;
        // All lanes set at once (the renderer's way: their permutations'
        // walks as one loop over the lanes), and the first seven of them.
        MultiJitterLanes together(n), some(n);
        together.setLanes(patterns, MultiJitterLanes::kLanes);
        some.setLanes(patterns, 7);
        for (uint32_t s = 0; s < n; s += 1 + n / 64) {
            alignas(64) float x[MultiJitterLanes::kLanes], y[MultiJitterLanes::kLanes];
            alignas(64) float tx[MultiJitterLanes::kLanes], ty[MultiJitterLanes::kLanes];
            alignas(64) float sx[MultiJitterLanes::kLanes], sy[MultiJitterLanes::kLanes];
            lanes.sample(s, x, y);
            together.sample(s, tx, ty);
            some.sample(s, sx, sy);
            for (int l = 0; l < MultiJitterLanes::kLanes; ++l) {
                const Vec2f want = MultiJitterSet(n, patterns[l]).sample(s);
                ASSERT_EQ(x[l], want.x) << "n " << n << " lane " << l << " sample " << s;
                ASSERT_EQ(y[l], want.y) << "n " << n << " lane " << l << " sample " << s;
                ASSERT_EQ(tx[l], want.x) << "n " << n << " lane " << l << " sample " << s;
                ASSERT_EQ(ty[l], want.y) << "n " << n << " lane " << l << " sample " << s;
                if (l < 7) {
                    ASSERT_EQ(sx[l], want.x) << "n " << n << " lane " << l << " sample " << s;
                    ASSERT_EQ(sy[l], want.y) << "n " << n << " lane " << l << " sample " << s;
                }
            }
        }
    }
}
