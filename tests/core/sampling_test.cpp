// Warping functions: their samples follow the densities they claim.
#include "core/sampling.h"

#include <gtest/gtest.h>

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
