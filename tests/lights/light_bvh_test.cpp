// The light hierarchy: cones that hold what they unite, the orientation
// measure's closed forms, pick probabilities that sum to 1 over the lights
// and equal probability() for every pick, picks that follow probability()
// (chi-square), importance that is 0 exactly where no light can reach, lights
// at infinity beside the tree, and degenerate inputs (one light, no power,
// lights at one point, overflowing powers, a deep tree).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "lights/bvh_light_picker.h"
#include "lights/light_bounds.h"
#include "lights/light_bvh.h"
#include "support/chi_square.h"

using namespace penumbra;

namespace {

Vec3f randomUnit(std::mt19937& rng) {
    std::normal_distribution<float> g;
    for (;;) {
        const Vec3f v{g(rng), g(rng), g(rng)};
        if (lengthSquared(v) > 1e-6f) return normalize(v);
    }
}

// A quad-like light: a small box at `at` facing `axis` (one- or two-sided),
// or, with cosThetaO = -1, a light shining every way (a sphere or a point).
LightBounds quad(const Vec3f& at, const Vec3f& axis, float size, bool twoSided = false) {
    LightBounds b;
    b.box.extend(at - Vec3f(size));
    b.box.extend(at + Vec3f(size));
    b.axis = axis;
    b.cosThetaO = 1.f;
    b.twoSided = twoSided;
    return b;
}

LightBounds point(const Vec3f& at) {
    LightBounds b;
    b.box.extend(at);
    return b;
}

// Lights of every kind scattered in a 20-unit cube, powers over 4 orders of magnitude.
struct RandomLights {
    std::vector<std::optional<LightBounds>> bounds;
    std::vector<double> powers;
};
RandomLights randomLights(size_t n, uint32_t seed, size_t infinite = 0) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-10.f, 10.f), s(0.01f, 0.5f), e(0.f, 4.f);
    RandomLights r;
    for (size_t i = 0; i < n; ++i) {
        const Vec3f at{u(rng), u(rng), u(rng)};
        switch (i % 4) {
            case 0: r.bounds.push_back(quad(at, randomUnit(rng), s(rng))); break;
            case 1: r.bounds.push_back(quad(at, randomUnit(rng), s(rng), true)); break;
            case 2: r.bounds.push_back(point(at)); break;
            default: {
                LightBounds b = quad(at, randomUnit(rng), s(rng));
                b.cosThetaO = -1.f;  // a sphere
                r.bounds.push_back(b);
            }
        }
        r.powers.push_back(std::pow(10.0, double(e(rng))));
    }
    for (size_t i = 0; i < infinite; ++i) {
        r.bounds.push_back(std::nullopt);
        r.powers.push_back(std::pow(10.0, double(e(rng))) * 100.0);
    }
    return r;
}

// Angle between unit vectors (accurate where they nearly coincide, unlike acos of the dot product).
float angle(const Vec3f& a, const Vec3f& b) { return 2.f * std::atan2(length(a - b), length(a + b)); }

// The share of picks at (p, n) that find no light: where the descent reaches
// a node whose children's bounds both rule the point out (stratified u).
double missedShare(const LightBVH& tree, const Vec3f& p, const Vec3f& n, int picks) {
    int missed = 0;
    for (int i = 0; i < picks; ++i) missed += tree.pick((float(i) + 0.5f) / float(picks), p, n).probability == 0.f;
    return double(missed) / picks;
}

}  // namespace

TEST(LightBounds, UnitedConeHoldsBothCones) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> half(0.f, 1.5f);
    for (int i = 0; i < 2000; ++i) {
        const DirectionCone a{randomUnit(rng), std::cos(half(rng))}, b{randomUnit(rng), std::cos(half(rng))};
        const DirectionCone c = unite(a, b);
        if (c.cosTheta <= -1.f) {
            // Every direction: only where no narrower cone about the plane of the axes holds both.
            EXPECT_GE(angle(a.axis, b.axis) + std::acos(a.cosTheta) + std::acos(b.cosTheta), 2.f * kPi - 1e-3f);
            continue;
        }
        const float theta = std::acos(c.cosTheta);
        EXPECT_NEAR(length(c.axis), 1.f, 1e-5f);
        EXPECT_LE(angle(c.axis, a.axis) + std::acos(a.cosTheta), theta + 1e-5f) << i;
        EXPECT_LE(angle(c.axis, b.axis) + std::acos(b.cosTheta), theta + 1e-5f) << i;
    }
    // One inside the other, and opposite narrow cones (a half-turn apart: the union is a half-space-and-more).
    const DirectionCone wide{{0, 1, 0}, std::cos(1.f)}, narrow{normalize(Vec3f{0.2f, 1, 0}), std::cos(0.1f)};
    EXPECT_EQ(unite(wide, narrow).cosTheta, wide.cosTheta);
    EXPECT_EQ(unite(narrow, wide).cosTheta, wide.cosTheta);
    const DirectionCone up{{0, 1, 0}, 1.f}, down{{0, -1, 0}, 1.f};
    const DirectionCone both = unite(up, down);
    EXPECT_NEAR(both.cosTheta, 0.f, 2e-3f);
    EXPECT_NEAR(dot(both.axis, Vec3f{0, 1, 0}), 0.f, 2e-3f);
}

TEST(LightBounds, OrientationMeasureClosedForms) {
    // A flat Lambertian emitter: the cosine-weighted hemisphere, pi.
    EXPECT_NEAR(orientationMeasure(1.f, 0.f), kPi, 1e-5f);
    // Normals every way: the whole sphere, 4 pi.
    EXPECT_NEAR(orientationMeasure(-1.f, 0.f), 4.f * kPi, 1e-4f);
    // A hemisphere of normals: 2 pi, plus 2 pi int_{pi/2}^{pi} sin^2 = pi^2 / 2 for the band behind it.
    EXPECT_NEAR(orientationMeasure(0.f, 0.f), 2.f * kPi + 0.5f * kPi * kPi, 1e-4f);
    // It grows with the cone.
    EXPECT_LT(orientationMeasure(0.9f, 0.f), orientationMeasure(0.5f, 0.f));
}

TEST(LightBVH, ProbabilitiesSumToOneAndMatchEveryPick) {
    // Lights of every kind and orientation: the probabilities and the share of
    // picks that find no light (a node whose children both rule the point out)
    // add up to 1, and every pick's probability is probability()'s, bit for bit.
    for (const size_t n : {1u, 2u, 3u, 7u, 64u, 300u}) {
        const RandomLights lights = randomLights(n, uint32_t(n));
        const LightBVH tree(lights.bounds, lights.powers);
        std::mt19937 rng(11);
        std::uniform_real_distribution<float> u01(0.f, 1.f), u(-12.f, 12.f);
        int reached = 0;
        for (int k = 0; k < 200; ++k) {
            const Vec3f p{u(rng), u(rng), u(rng)};
            const Vec3f nrm = k % 5 == 0 ? Vec3f{} : randomUnit(rng);
            double sum = 0;
            for (size_t j = 0; j < n; ++j) {
                const float pj = tree.probability(j, p, nrm);
                ASSERT_TRUE(pj >= 0.f && pj <= 1.f) << pj;
                sum += pj;
            }
            reached += sum > 0;
            EXPECT_NEAR(sum + missedShare(tree, p, nrm, 4000), 1.0, 2e-3) << n << " lights, point " << k;
            for (int i = 0; i < 20; ++i) {
                const LightPicker::Pick pick = tree.pick(u01(rng), p, nrm);
                EXPECT_GE(pick.u, 0.f);
                EXPECT_LT(pick.u, 1.f);
                if (pick.probability == 0.f) continue;
                EXPECT_EQ(pick.probability, tree.probability(pick.index, p, nrm)) << "bit for bit";
            }
        }
        EXPECT_GT(reached, 60) << n;
    }
}

TEST(LightBVH, UnderCeilingLightsEveryPickFindsOne) {
    // A 16 x 16 grid of downward quads at y = 6 and points on the floor below
    // facing up (the many-lights benchmark's shape): every light reaches every
    // point, no pick is lost and the probabilities sum to 1.
    std::vector<std::optional<LightBounds>> bounds;
    std::vector<double> powers;
    for (int i = 0; i < 16; ++i)
        for (int j = 0; j < 16; ++j) {
            bounds.push_back(quad({float(i) - 8, 6, float(j) - 8}, {0, -1, 0}, 0.125f));
            powers.push_back(std::pow(1000.0, double((i * 7 + j * 13) % 16) / 15.0));
        }
    const LightBVH tree(bounds, powers);
    EXPECT_LE(tree.depth(), 6u);  // 256 lights, 4 children a node: 4 levels when balanced
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> u(-12.f, 12.f);
    for (int k = 0; k < 100; ++k) {
        const Vec3f p{u(rng), 0, u(rng)};
        double sum = 0;
        for (size_t j = 0; j < bounds.size(); ++j) {
            const float pj = tree.probability(j, p, {0, 1, 0});
            EXPECT_GT(pj, 0.f);
            sum += pj;
        }
        EXPECT_NEAR(sum, 1.0, 1e-5) << k;
        EXPECT_EQ(missedShare(tree, p, {0, 1, 0}, 1000), 0.0);
    }
    // Under lights of equal power, the light straight above a point is likelier
    // than seen from beyond a corner, where the corner's light is the likeliest.
    const LightBVH even(bounds, std::vector<double>(bounds.size(), 1.0));
    const size_t above = 8 * 16 + 8;  // at (0, 6, 0)
    EXPECT_GT(even.probability(above, {0, 0, 0}, {0, 1, 0}), 2.f * even.probability(above, {-11, 0, -11}, {0, 1, 0}));
    for (size_t j = 1; j < bounds.size(); ++j)
        EXPECT_GT(even.probability(0, {-11, 0, -11}, {0, 1, 0}), even.probability(j, {-11, 0, -11}, {0, 1, 0})) << j;
}

TEST(LightBVH, PicksFollowProbabilities) {
    // Chi-square of 100,000 picks against probability() at a few points.
    const RandomLights lights = randomLights(40, 5);
    const LightBVH tree(lights.bounds, lights.powers);
    const Vec3f points[] = {{0, 0, 0}, {9, -9, 3}, {-3, 11, 0.5f}};
    const Vec3f normals[] = {{0, 1, 0}, normalize(Vec3f{-1, 1, 0}), {}};
    for (int k = 0; k < 3; ++k) {
        constexpr int kPicks = 100000;
        std::mt19937 rng{uint32_t(k)};
        std::uniform_real_distribution<float> u01(0.f, 1.f);
        std::vector<double> count(41, 0.0);  // the last: picks that found no light
        for (int i = 0; i < kPicks; ++i) {
            const LightPicker::Pick pick = tree.pick(u01(rng), points[k], normals[k]);
            count[pick.probability > 0.f ? pick.index : 40] += 1;
        }
        std::vector<double> probability(41, 0.0);
        double sum = 0;
        for (size_t j = 0; j < 40; ++j) sum += probability[j] = tree.probability(j, points[k], normals[k]);
        probability[40] = std::max(0.0, 1.0 - sum);
        double chi2 = 0, pooled = 0, pooledExpected = 0;
        int dof = -1;
        for (size_t j = 0; j < 41; ++j) {
            const double expected = kPicks * probability[j];
            if (expected < 1e-9) {
                EXPECT_EQ(count[j], 0) << "a light of probability 0 was picked";
                continue;
            }
            if (expected < 5) {
                pooled += count[j];
                pooledExpected += expected;
                continue;
            }
            chi2 += (count[j] - expected) * (count[j] - expected) / expected;
            ++dof;
        }
        if (pooledExpected > 0) {
            chi2 += (pooled - pooledExpected) * (pooled - pooledExpected) / pooledExpected;
            ++dof;
        }
        ASSERT_GT(dof, 3);
        EXPECT_GT(test::chiSquareSurvival(chi2, dof), 0.01) << "point " << k << ": chi2 " << chi2 << ", " << dof;
    }
}

TEST(LightBVH, ImportanceIsZeroOnlyWhereNoLightReaches) {
    // Two downward quads at y = 5 and one upward quad at y = -5, 10 apart.
    const std::vector<std::optional<LightBounds>> bounds = {
        quad({-5, 5, 0}, {0, -1, 0}, 0.25f), quad({5, 5, 0}, {0, -1, 0}, 0.25f), quad({0, -5, 0}, {0, 1, 0}, 0.25f)};
    const LightBVH tree(bounds, std::vector<double>{1.0, 2.0, 4.0});
    // Between them, facing up: only the ceiling quads; they split 1:2 at the midpoint below them.
    EXPECT_EQ(tree.probability(2, {0, 0, 0}, {0, 1, 0}), 0.f);
    EXPECT_NEAR(tree.probability(1, {0, 0, 0}, {0, 1, 0}) / tree.probability(0, {0, 0, 0}, {0, 1, 0}), 2.0, 0.01);
    // Facing down: only the floor quad (the ceiling pair's bounding sphere
    // holds the point, so the pair keeps a share its quads then both refuse).
    EXPECT_GT(tree.probability(2, {0, 0, 0}, {0, -1, 0}), 0.f);
    EXPECT_EQ(tree.probability(0, {0, 0, 0}, {0, -1, 0}), 0.f);
    EXPECT_EQ(tree.probability(1, {0, 0, 0}, {0, -1, 0}), 0.f);
    EXPECT_NEAR(tree.probability(2, {0, 0, 0}, {0, -1, 0}) + missedShare(tree, {0, 0, 0}, {0, -1, 0}, 10000), 1.0,
                1e-3);
    // No normal: all three, the nearer and stronger ones more.
    EXPECT_GT(tree.probability(2, {0, 0, 0}, {}), tree.probability(1, {0, 0, 0}, {}));
    EXPECT_GT(tree.probability(0, {0, 0, 0}, {}), 0.f);
    // Above the ceiling: the downward quads send nothing up; facing up, nothing at all.
    EXPECT_EQ(tree.probability(0, {0, 8, 0}, {}), 0.f);
    EXPECT_EQ(tree.probability(1, {0, 8, 0}, {}), 0.f);
    EXPECT_GT(tree.probability(2, {0, 8, 0}, {}), 0.f);
    EXPECT_EQ(tree.pick(0.5f, {0, 8, 0}, {0, 1, 0}).probability, 0.f);
    // Just below a quad's plane, off to the side, facing up: it still reaches (a grazing, tiny share).
    EXPECT_GT(tree.probability(0, {-3, 4.9f, 0}, {0, 1, 0}), 0.f);
}

TEST(LightBVH, DegenerateInputs) {
    const Vec3f p{0.3f, -2, 1}, n{0, 1, 0};
    {  // One light: probability 1 wherever it reaches.
        const std::vector<std::optional<LightBounds>> b = {point({0, 1, 0})};
        const LightBVH tree(b, std::vector<double>{5.0});
        EXPECT_EQ(tree.depth(), 1u);
        EXPECT_EQ(tree.probability(0, p, n), 1.f);
        const LightPicker::Pick pick = tree.pick(0.37f, p, n);
        EXPECT_EQ(pick.index, 0u);
        EXPECT_EQ(pick.probability, 1.f);
        EXPECT_EQ(pick.u, 0.37f);
        EXPECT_EQ(tree.probability(0, p, Vec3f{0, -1, 0}), 0.f);  // facing away
    }
    {  // Lights without power (zero, negative, NaN) are left out.
        const std::vector<std::optional<LightBounds>> b = {point({0, 1, 0}), point({1, 1, 0}), point({2, 1, 0}),
                                                           point({3, 1, 0})};
        const LightBVH tree(b, std::vector<double>{0.0, 3.0, -1.0, std::nan("")});
        EXPECT_FALSE(tree.holds(0));
        EXPECT_TRUE(tree.holds(1));
        EXPECT_EQ(tree.probability(0, p, n), 0.f);
        EXPECT_EQ(tree.probability(1, p, n), 1.f);
        for (float u : {0.f, 0.5f, 0.999f}) EXPECT_EQ(tree.pick(u, p, n).index, 1u);
        const LightBVH none(b, std::vector<double>{0.0, 0.0, 0.0, 0.0});
        EXPECT_TRUE(none.empty());
        EXPECT_EQ(none.pick(0.5f, p, n).probability, 0.f);
    }
    {  // Lights at one point: picked in proportion to power, bit-identical to probability().
        std::vector<std::optional<LightBounds>> b;
        std::vector<double> powers;
        for (int i = 0; i < 100; ++i) {
            b.push_back(quad({1, 1, 1}, {0, -1, 0}, 0.1f));
            powers.push_back(1.0 + i % 4);
        }
        const LightBVH tree(b, powers);
        EXPECT_LE(tree.depth(), 4u);  // halved by count: balanced, 4 children a node
        double sum = 0;
        for (int i = 0; i < 100; ++i) {
            const float pi = tree.probability(size_t(i), p, n);
            sum += pi;
            EXPECT_NEAR(pi, (1.0 + i % 4) / 250.0, 1e-6) << i;
        }
        EXPECT_NEAR(sum, 1.0, 1e-5);
    }
    {  // Powers that overflow a float and radiance of 3e38: no NaN, probabilities still sum to 1.
        const std::vector<std::optional<LightBounds>> b = {quad({0, 1, 0}, {0, -1, 0}, 0.1f), point({1, 1, 0}),
                                                           quad({-1, 1, 0}, {0, -1, 0}, 1e-30f), point({0, -1.99f, 1})};
        const double inf = std::numeric_limits<double>::infinity();
        const LightBVH tree(b, std::vector<double>{inf, 3e38 * 4, 1e-30, 3e38});
        double sum = 0;
        for (size_t j = 0; j < 4; ++j) {
            const float pj = tree.probability(j, p, n);
            EXPECT_TRUE(std::isfinite(pj));
            sum += pj;
        }
        EXPECT_NEAR(sum, 1.0, 1e-5);
        for (float u : {0.f, 0.3f, 0.7f, 0.9999f}) {
            const LightPicker::Pick pick = tree.pick(u, p, n);
            EXPECT_GT(pick.probability, 0.f);
            EXPECT_EQ(pick.probability, tree.probability(pick.index, p, n));
        }
        // At a light's own position (distance 0), and from the far end of the accelerators' range.
        for (const Vec3f& q : {Vec3f{1, 1, 0}, Vec3f{0, -1.8e18f, 0}}) {
            double s = 0;
            for (size_t j = 0; j < 4; ++j) s += tree.probability(j, q, Vec3f{});
            EXPECT_NEAR(s, 1.0, 1e-5) << q.y;
        }
    }
    {  // Lights spaced by powers of two along a line: a deep, thin tree, still no longer than 64 turns.
        std::vector<std::optional<LightBounds>> b;
        std::vector<double> powers;
        for (int i = 0; i < 120; ++i) {
            b.push_back(point({std::ldexp(1.f, i - 60), 0, 0}));
            powers.push_back(1.0);
        }
        const LightBVH tree(b, powers);
        EXPECT_LE(tree.depth(), 64u);
        double sum = 0;
        for (size_t j = 0; j < b.size(); ++j) sum += tree.probability(j, {0.5f, 1, 0}, Vec3f{});
        EXPECT_NEAR(sum, 1.0, 1e-5);
    }
}

TEST(BVHLightPicker, LightsAtInfinityBesideTheTree) {
    RandomLights lights = randomLights(30, 9, 3);
    const BVHLightPicker picker(lights.bounds, lights.powers);
    double treePower = 0, infinitePower = 0;
    for (size_t j = 0; j < lights.bounds.size(); ++j) (lights.bounds[j] ? treePower : infinitePower) += lights.powers[j];
    EXPECT_NEAR(picker.treeShare(), treePower / (treePower + infinitePower), 1e-6);
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> u01(0.f, 1.f), u(-8.f, 8.f);
    for (int k = 0; k < 100; ++k) {
        const Vec3f p{u(rng), u(rng), u(rng)}, n = randomUnit(rng);
        double sum = 0, infinite = 0;
        for (size_t j = 0; j < lights.bounds.size(); ++j) {
            const float pj = picker.probability(j, p, n);
            sum += pj;
            if (!lights.bounds[j]) {
                infinite += pj;
                EXPECT_NEAR(pj, (1 - picker.treeShare()) * lights.powers[j] / infinitePower, 1e-6);
            }
        }
        EXPECT_NEAR(infinite, 1.0 - picker.treeShare(), 1e-6);
        EXPECT_LE(sum, 1.0 + 1e-5);
        for (int i = 0; i < 10; ++i) {
            const LightPicker::Pick pick = picker.pick(u01(rng), p, n);
            if (pick.probability == 0.f) continue;  // the tree's share, where none of its lights reaches
            EXPECT_EQ(pick.probability, picker.probability(pick.index, p, n));
        }
    }
    // Only lights at infinity, or only bounded ones.
    const std::vector<std::optional<LightBounds>> sky = {std::nullopt, std::nullopt};
    const BVHLightPicker onlySky(sky, std::vector<double>{1.0, 3.0});
    EXPECT_EQ(onlySky.treeShare(), 0.f);
    EXPECT_FLOAT_EQ(onlySky.probability(1, {}, {}), 0.75f);
    EXPECT_EQ(onlySky.pick(0.9f, {}, {}).index, 1u);
    const std::vector<std::optional<LightBounds>> lamp = {point({0, 1, 0})};
    const BVHLightPicker onlyLamp(lamp, std::vector<double>{2.0});
    EXPECT_EQ(onlyLamp.treeShare(), 1.f);
    EXPECT_EQ(onlyLamp.probability(0, {}, {}), 1.f);
}
