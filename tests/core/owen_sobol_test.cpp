// The integrators' sample sequence: aligned blocks are (0,k,2)-nets (what
// makes a shading point's samples and a pixel's samples stratified), every
// point is uniform over the scrambles (what keeps estimators unbiased), and
// stratified estimates converge faster than independent ones.
#include "core/owen_sobol.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/hash.h"

using namespace penumbra;

namespace {

// Whether points [first, first + 2^k) fall one into each cell of every
// 2^a x 2^(k-a) grid.
bool blockIsNet(const OwenSobol2D& seq, uint32_t first, uint32_t k) {
    const uint32_t n = 1u << k;
    for (uint32_t a = 0; a <= k; ++a) {
        const uint32_t cols = 1u << a, rows = 1u << (k - a);
        std::vector<int> count(n, 0);
        for (uint32_t i = first; i < first + n; ++i) {
            const Vec2f u = seq.point(i);
            if (!(u.x >= 0.f && u.x < 1.f && u.y >= 0.f && u.y < 1.f)) return false;
            ++count[uint32_t(u.y * float(rows)) * cols + uint32_t(u.x * float(cols))];
        }
        for (int c : count)
            if (c != 1) return false;
    }
    return true;
}

}  // namespace

TEST(OwenSobol, SobolSecondDimensionMatchesItsGeneratorMatrix) {
    // The first points of Sobol's second dimension in index (not Gray-code) order.
    const double expected[] = {0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875};
    for (uint32_t i = 0; i < 8; ++i) EXPECT_EQ(detail::sobolSecond(i) / 4294967296.0, expected[i]) << i;
    // High index bits use the other tables: bit j alone gives column j of the matrix.
    uint32_t v = 0x80000000u;
    for (uint32_t j = 0; j < 32; ++j, v ^= v >> 1) EXPECT_EQ(detail::sobolSecond(1u << j), v) << j;
}

TEST(OwenSobol, OwenScrambleIsABijectionThatKeepsIntervals) {
    // Values in one dyadic interval [m 2^-k, (m+1) 2^-k) stay together.
    for (uint32_t seed : {0u, 1u, 0xdeadbeefu}) {
        for (uint32_t k : {1u, 4u, 9u}) {
            const uint32_t shift = 32 - k;
            for (uint32_t m = 0; m < 8; ++m) {
                const uint32_t top = detail::owenScramble(m << shift, seed) >> shift;
                for (uint32_t low : {1u, 12345u, (1u << shift) - 1u})
                    EXPECT_EQ(detail::owenScramble((m << shift) | low, seed) >> shift, top);
            }
        }
        std::vector<bool> seen(1u << 12, false);
        for (uint32_t x = 0; x < (1u << 12); ++x) {
            const uint32_t y = detail::owenScramble(x << 20, seed) >> 20;
            EXPECT_FALSE(seen[y]);
            seen[y] = true;
        }
    }
}

TEST(OwenSobol, AlignedBlocksAreStratifiedInEveryElementaryInterval) {
    for (uint64_t key : {1ull, 42ull, 0x123456789abcdefull}) {
        const OwenSobol2D seq(key);
        // A shading point's 4 or 16 samples (camera sample s takes block s).
        for (uint32_t s = 0; s < 8; ++s) {
            EXPECT_TRUE(blockIsNet(seq, s * 4, 2)) << key << " block " << s;
            EXPECT_TRUE(blockIsNet(seq, s * 16, 4)) << key << " block " << s;
        }
        // A pixel's 16 camera samples x 16 light samples, and 1024 points.
        EXPECT_TRUE(blockIsNet(seq, 0, 8)) << key;
        EXPECT_TRUE(blockIsNet(seq, 0, 10)) << key;
        EXPECT_TRUE(blockIsNet(seq, 1024, 10)) << key;
    }
}

TEST(OwenSobol, EachPointIsUniformOverScrambles) {
    // Point i over 16,384 keys, in an 8 x 8 histogram: chi-square with 63
    // degrees of freedom stays far below its 0.1% quantile (103.4).
    for (uint32_t i : {0u, 1u, 5u, 1000u}) {
        const int cells = 64, n = 16384;
        std::vector<int> hist(cells, 0);
        for (int k = 0; k < n; ++k) {
            const Vec2f u = OwenSobol2D(mix64(uint64_t(k) + 7)).point(i);
            ++hist[int(u.y * 8.f) * 8 + int(u.x * 8.f)];
        }
        double chi2 = 0;
        const double e = double(n) / cells;
        for (int c : hist) chi2 += (c - e) * (c - e) / e;
        EXPECT_LT(chi2, 103.4) << "point " << i;
    }
}

TEST(OwenSobol, DifferentKeysGiveDifferentSequences) {
    const OwenSobol2D a(1), b(2);
    int same = 0;
    for (uint32_t i = 0; i < 64; ++i) same += a.point(i).x == b.point(i).x;
    EXPECT_LT(same, 4);
    // Pure: the same key and index give the same point.
    EXPECT_EQ(OwenSobol2D(9).point(33).x, OwenSobol2D(9).point(33).x);
    EXPECT_EQ(OwenSobol2D(9).point(33).y, OwenSobol2D(9).point(33).y);
}

TEST(OwenSobol, StratifiedEstimatesBeatIndependentOnes) {
    // The fraction of a disk in the unit square (an edge, like a shadow
    // boundary) from 64 points: the sequence's squared error, over 500 keys,
    // is several times smaller than that of independent points.
    const double truth = 3.14159265358979 * 0.16;  // r = 0.4
    auto inside = [](Vec2f u) { return (u.x - 0.5f) * (u.x - 0.5f) + (u.y - 0.5f) * (u.y - 0.5f) < 0.16f; };
    double errSeq = 0, errRandom = 0;
    for (uint64_t k = 0; k < 500; ++k) {
        const OwenSobol2D seq(k);
        int hitsSeq = 0, hitsRandom = 0;
        for (uint32_t i = 0; i < 64; ++i) {
            hitsSeq += inside(seq.point(i));
            const uint64_t h = mix64(k * 1000 + i);
            hitsRandom += inside(Vec2f{toUnitFloat(h), toUnitFloat(mix64(h))});
        }
        errSeq += std::pow(hitsSeq / 64.0 - truth, 2);
        errRandom += std::pow(hitsRandom / 64.0 - truth, 2);
    }
    EXPECT_LT(errSeq, 0.25 * errRandom) << errSeq << " vs " << errRandom;
}

TEST(OwenSobol, ReverseBitsReversesEveryBit) {
    for (uint32_t k = 0; k < 32; ++k) EXPECT_EQ(detail::reverseBits(1u << k), 1u << (31 - k));
    uint64_t state = 1;
    for (int i = 0; i < 10000; ++i) {
        state = mix64(state + 0x9e3779b97f4a7c15ULL);
        const uint32_t x = static_cast<uint32_t>(state);
        uint32_t naive = 0;
        for (uint32_t k = 0; k < 32; ++k) naive |= ((x >> k) & 1u) << (31 - k);
        ASSERT_EQ(detail::reverseBits(x), naive) << x;
        ASSERT_EQ(detail::reverseBits(detail::reverseBits(x)), x);
        ASSERT_EQ(detail::reverseBitsBySwaps(x), naive) << x;
    }
}

TEST(OwenSobol, SecondDimensionByShiftsIsTheTables) {
    // The generator matrix's columns v_0 = 2^31, v_{j+1} = v_j ^ (v_j >> 1), reversed.
    for (uint32_t j = 0; j < 32; ++j)
        EXPECT_EQ(detail::sobolSecondReversedByShifts(1u << j), detail::sobolSecondReversed(1u << j));
    uint64_t state = 7;
    for (int i = 0; i < 10000; ++i) {
        state = mix64(state + 0x9e3779b97f4a7c15ULL);
        const uint32_t x = static_cast<uint32_t>(state);
        ASSERT_EQ(detail::sobolSecondReversedByShifts(x), detail::sobolSecondReversed(x)) << x;
        ASSERT_EQ(detail::sobolSecondReversedByShifts(uint32_t(i)), detail::sobolSecondReversed(uint32_t(i))) << i;
    }
}

TEST(OwenSobol, PointLanesArePointsBitForBit) {
    // Each lane with its own key and index, as a batch's lanes have.
    for (const uint64_t salt : {1ULL, 2ULL, 3ULL}) {
        uint64_t keys[OwenSobol2D::kLanes];
        uint32_t indices[OwenSobol2D::kLanes];
        for (int l = 0; l < OwenSobol2D::kLanes; ++l) {
            keys[l] = mix64(uint64_t(l) * 977 + salt);
            indices[l] = l == 0 ? 0u : l == 1 ? ~0u : uint32_t(mix64(uint64_t(l) + salt) >> (8 * salt));
        }
        float x[OwenSobol2D::kLanes], y[OwenSobol2D::kLanes];
        const uint32_t first[OwenSobol2D::kLanes] = {};
        OwenSobol2D::pointLanes(keys, indices, 1, first, x, y);
        for (int l = 0; l < OwenSobol2D::kLanes; ++l) {
            const Vec2f p = OwenSobol2D(keys[l]).point(indices[l]);
            EXPECT_EQ(x[l], p.x) << "lane " << l;
            EXPECT_EQ(y[l], p.y) << "lane " << l;
        }
    }
}

TEST(OwenSobol, PointLanesOfSeveralSamplesAreSamplePointsBitForBit) {
    // Lanes as (shading point, sample) pairs: each its own key, camera sample
    // and sample of n, for powers of two (the block path) and other counts.
    for (const uint32_t n : {2u, 3u, 4u, 7u, 8u, 15u}) {
        uint64_t keys[OwenSobol2D::kLanes];
        uint32_t indices[OwenSobol2D::kLanes], ks[OwenSobol2D::kLanes];
        for (int l = 0; l < OwenSobol2D::kLanes; ++l) {
            keys[l] = mix64(uint64_t(l / 3) * 31 + n);
            indices[l] = l < 3 ? 0u : uint32_t(mix64(uint64_t(l / 3) + n) >> 40);
            ks[l] = uint32_t(l) % n;
        }
        float x[OwenSobol2D::kLanes], y[OwenSobol2D::kLanes];
        OwenSobol2D::pointLanes(keys, indices, n, ks, x, y);
        for (int l = 0; l < OwenSobol2D::kLanes; ++l) {
            Vec2f want;
            OwenSobol2D(keys[l]).samplePoints(indices[l], n, ks[l], 1, &want);
            EXPECT_EQ(x[l], want.x) << "n " << n << ", lane " << l;
            EXPECT_EQ(y[l], want.y) << "n " << n << ", lane " << l;
        }
    }
}

TEST(OwenSobol, SamplePointLanesAreSamplePointsBitForBit) {
    // Powers of two (the block path) and other counts, from several starting points.
    const OwenSobol2D seq(0x1234567ULL);
    for (const uint32_t n : {16u, 64u, 20u, 100u})
        for (const uint32_t index : {0u, 5u, 1000u})
            for (uint32_t first = 0; first < n; first += 16) {
                Vec2f want[OwenSobol2D::kLanes];
                const uint32_t count = std::min(n - first, 16u);
                seq.samplePoints(index, n, first, count, want);
                float x[OwenSobol2D::kLanes], y[OwenSobol2D::kLanes];
                seq.samplePointLanes(index, n, first, x, y);
                for (uint32_t k = 0; k < count; ++k) {
                    EXPECT_EQ(x[k], want[k].x) << n << " " << index << " " << first + k;
                    EXPECT_EQ(y[k], want[k].y) << n << " " << index << " " << first + k;
                }
            }
}

TEST(OwenSobol, BlockPointsAreTheBlocksPointsInAnotherOrder) {
    // The integrators draw a shading point's 2^m samples with blockPoints:
    // the estimator sums them, so they must be exactly point()'s for the
    // block, whatever the order and however the block is cut into chunks.
    for (uint64_t key : {1ULL, 0x9e3779b97f4a7c15ULL}) {
        const OwenSobol2D seq(key);
        for (uint32_t log2n : {0u, 1u, 4u, 6u, 8u}) {
            const uint32_t n = 1u << log2n;
            for (uint32_t block : {0u, 1u, 7u, 99u}) {
                std::vector<std::pair<float, float>> expected, got;
                for (uint32_t k = 0; k < n; ++k) {
                    const Vec2f p = seq.point(block * n + k);
                    expected.emplace_back(p.x, p.y);
                }
                std::vector<Vec2f> out(n);
                for (uint32_t k0 = 0; k0 < n; k0 += 16)  // in chunks, as the integrators draw them
                    seq.blockPoints(block, log2n, k0, std::min(16u, n - k0), out.data() + k0);
                for (const Vec2f& p : out) got.emplace_back(p.x, p.y);
                std::sort(expected.begin(), expected.end());
                std::sort(got.begin(), got.end());
                EXPECT_EQ(expected, got) << "key " << key << " block " << block << " n " << n;
            }
        }
    }
}
