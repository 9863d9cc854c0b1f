// Warping functions: their samples follow the densities they claim.
#include "core/sampling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/multi_jitter.h"

using namespace penumbra;

TEST(Sampling, ConcentricDiskIsUniform) {
    // Uniform on the unit disk: E[r^2] = 1/2, and each quadrant gets a quarter.
    const uint32_t n = 64 * 64;
    double r2 = 0;
    int quadrant[4] = {0, 0, 0, 0};
    for (uint32_t s = 0; s < n; ++s) {
        Vec2f d = squareToConcentricDisk(multiJitter2D(s, n, 9));
        ASSERT_LE(d.x * d.x + d.y * d.y, 1.f + 1e-6f);
        r2 += d.x * d.x + d.y * d.y;
        ++quadrant[(d.x < 0) + 2 * (d.y < 0)];
    }
    EXPECT_NEAR(r2 / n, 0.5, 1e-3);
    for (int q : quadrant) EXPECT_NEAR(double(q) / n, 0.25, 0.01);
}

TEST(Sampling, ConcentricDiskIsShirleyChiusMap) {
    // The polynomial sine and cosine give the trigonometric map's points
    // within float rounding: r (cos phi, sin phi), phi = pi/4 y/x where |x| >
    // |y|, else pi/2 - pi/4 x/y, on a grid over the square and its corners.
    double worst = 0.0;
    const int n = 601;
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            const Vec2f u{float(i) / (n - 1) * 0x1.fffffep-1f, float(j) / (n - 1) * 0x1.fffffep-1f};
            const Vec2f d = squareToConcentricDisk(u);
            const double x = 2.0 * u.x - 1.0, y = 2.0 * u.y - 1.0;
            double r = 0.0, phi = 0.0;
            if (std::fabs(x) > std::fabs(y)) {
                r = x, phi = kPi / 4.0 * (y / x);
            } else if (y != 0.0) {
                r = y, phi = kPi / 2.0 - kPi / 4.0 * (x / y);
            }
            worst = std::max(worst, std::hypot(d.x - r * std::cos(phi), d.y - r * std::sin(phi)));
        }
    }
    EXPECT_LT(worst, 3e-7);
    EXPECT_EQ(squareToConcentricDisk(Vec2f{0.5f, 0.5f}).x, 0.f);
    EXPECT_EQ(squareToConcentricDisk(Vec2f{0.5f, 0.5f}).y, 0.f);
}

TEST(Sampling, SinCosOctantIsSinAndCos) {
    for (int i = -1000; i <= 1000; ++i) {
        const float a = float(i) / 1000.f * (kPi / 4.f);
        const SinCos sc = sinCosOctant(a);
        EXPECT_NEAR(sc.sin, std::sin(double(a)), 1.5e-7) << a;
        EXPECT_NEAR(sc.cos, std::cos(double(a)), 1.5e-7) << a;
    }
}

TEST(Sampling, CosineHemisphereHasPdfCosOverPi) {
    // Under p = cos/pi: E[cos] = 2/3, and the cap theta < 60 degrees holds
    // sin^2(60 degrees) = 3/4 of the samples.
    const uint32_t n = 64 * 64;
    double meanCos = 0, inCap = 0;
    for (uint32_t s = 0; s < n; ++s) {
        Vec3f w = squareToCosineHemisphere(multiJitter2D(s, n, 4));
        ASSERT_NEAR(length(w), 1.f, 1e-5f);
        ASSERT_GE(w.z, 0.f);
        meanCos += w.z;
        inCap += w.z > 0.5f ? 1 : 0;
    }
    EXPECT_NEAR(meanCos / n, 2.0 / 3.0, 2e-3);
    EXPECT_NEAR(inCap / n, 0.75, 2e-3);
}

TEST(Sampling, UniformSphereAndTriangleAreUniform) {
    const uint32_t n = 64 * 64;
    double z = 0, z2 = 0, b1 = 0, b2 = 0;
    for (uint32_t s = 0; s < n; ++s) {
        Vec2f u = multiJitter2D(s, n, 21);
        Vec3f w = squareToUniformSphere(u);
        ASSERT_NEAR(length(w), 1.f, 1e-5f);
        z += w.z;
        z2 += w.z * w.z;
        Vec2f b = squareToTriangle(u);
        ASSERT_GE(b.x, 0.f);
        ASSERT_GE(b.y, 0.f);
        ASSERT_LE(b.x + b.y, 1.f + 1e-6f);
        b1 += b.x;
        b2 += b.y;
    }
    EXPECT_NEAR(z / n, 0.0, 1e-3);        // symmetric
    EXPECT_NEAR(z2 / n, 1.0 / 3.0, 1e-3);  // E[z^2] on the sphere
    EXPECT_NEAR(b1 / n, 1.0 / 3.0, 1e-3);  // the centroid
    EXPECT_NEAR(b2 / n, 1.0 / 3.0, 1e-3);
}
