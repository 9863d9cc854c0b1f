// Smooth dielectrics: Fresnel against closed forms, Snell's law, total
// internal reflection, and the path integrator's reflect/refract choice
// against the Fresnel probabilities (a chi-square test of the two outcomes).
#include "shading/bsdf/dielectric.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/hash.h"

using namespace penumbra;

namespace {

Vec3f fromAngle(float thetaDeg) {
    const float t = thetaDeg * kPi / 180.f;
    return {std::sin(t), std::cos(t), 0.f};
}

const Vec3f kUp{0.f, 1.f, 0.f};

}  // namespace

TEST(Dielectric, NormalIncidenceReflectance) {
    for (float n : {1.33f, 1.5f, 2.5f}) {
        const float R = ((n - 1.f) / (n + 1.f)) * ((n - 1.f) / (n + 1.f));
        EXPECT_NEAR(fresnelDielectric(1.f, n), R, 1e-6f) << n;
        EXPECT_NEAR(fresnelDielectric(1.f, 1.f / n), R, 1e-6f) << n;  // the same from inside
    }
    EXPECT_NEAR(fresnelDielectric(0.3f, 1.f), 0.f, 1e-7f);  // no interface
}

TEST(Dielectric, BrewsterAngleHasNoParallelReflection) {
    // At tan(theta_B) = eta the parallel part vanishes: F = rPerp^2 / 2 with
    // rPerp = cos(theta_i + theta_t) / cos(theta_i - theta_t) * -1 (Hecht), theta_t = 90 - theta_B.
    const float eta = 1.5f;
    const float thetaB = std::atan(eta);
    const float thetaT = 0.5f * kPi - thetaB;
    const float rPerp = -std::sin(thetaB - thetaT) / std::sin(thetaB + thetaT);
    EXPECT_NEAR(fresnelDielectric(std::cos(thetaB), eta), 0.5f * rPerp * rPerp, 1e-6f);
}

TEST(Dielectric, ReciprocityAcrossTheInterface) {
    // F is the same for a ray and its reversed refracted ray (Stokes relations).
    const float eta = 1.5f;
    for (float deg = 0.f; deg < 89.f; deg += 7.f) {
        const Vec3f wo = fromAngle(deg);
        const auto t = refract(wo, kUp, eta);
        ASSERT_TRUE(t);
        const float cosT = -t->y;
        EXPECT_NEAR(fresnelDielectric(wo.y, eta), fresnelDielectric(cosT, 1.f / eta), 2e-5f) << deg;
    }
}

TEST(Dielectric, RefractionFollowsSnellsLaw) {
    const float eta = 1.33f;
    for (float deg = 0.f; deg < 89.f; deg += 11.f) {
        const Vec3f wo = fromAngle(deg);
        const auto t = refract(wo, kUp, eta);
        ASSERT_TRUE(t);
        EXPECT_NEAR(length(*t), 1.f, 1e-6f);
        EXPECT_LT(t->y, 0.f);                                 // through the surface
        EXPECT_NEAR(-t->x * eta, wo.x, 1e-5f) << deg;          // sin(theta_i) = eta sin(theta_t), tangent reversed
        EXPECT_NEAR(t->z, 0.f, 1e-6f);                        // in the plane of incidence
    }
}

TEST(Dielectric, TotalInternalReflectionBeyondTheCriticalAngle) {
    const float eta = 1.f / 1.5f;  // from glass into air
    const float critical = std::asin(eta) * 180.f / kPi;  // 41.8 degrees
    EXPECT_TRUE(refract(fromAngle(critical - 0.5f), kUp, eta));
    EXPECT_FALSE(refract(fromAngle(critical + 0.5f), kUp, eta));
    EXPECT_EQ(fresnelDielectric(std::cos((critical + 0.5f) * kPi / 180.f), eta), 1.f);
    const DielectricSplit s = splitDielectric(fromAngle(60.f), kUp, kUp, eta, Rgb(1.f));
    EXPECT_FALSE(s.transmitted);
    EXPECT_EQ(s.reflectedWeight, Rgb(1.f));
    EXPECT_NEAR(s.reflected.x, -fromAngle(60.f).x, 1e-6f);
    EXPECT_NEAR(s.reflected.y, fromAngle(60.f).y, 1e-6f);
    for (float u : {0.f, 0.5f, 0.999f}) EXPECT_FALSE(sampleDielectric(fromAngle(60.f), kUp, kUp, eta, Rgb(1.f), u).transmitted);
}

TEST(Dielectric, SplitWeightsConserveEnergyThroughAClosedObject) {
    // Entering scales radiance by 1/eta^2 and leaving by eta^2: a clear slab seen
    // at normal incidence passes (1 - R)^2 of the light in one straight pass.
    const float n = 1.5f, R = 0.04f;
    const DielectricSplit in = splitDielectric(kUp, kUp, kUp, n, Rgb(1.f));
    const DielectricSplit out = splitDielectric(kUp, kUp, kUp, 1.f / n, Rgb(1.f));
    ASSERT_TRUE(in.transmitted && out.transmitted);
    EXPECT_NEAR(in.reflectedWeight.g, R, 1e-6f);
    EXPECT_NEAR((in.transmittedWeight * out.transmittedWeight).g, (1.f - R) * (1.f - R), 1e-6f);
    const DielectricSplit tinted = splitDielectric(kUp, kUp, kUp, n, Rgb(0.5f, 1.f, 0.25f));
    EXPECT_NEAR(tinted.transmittedWeight.r, 0.5f * (1.f - R) / (n * n), 1e-6f);
    EXPECT_NEAR(tinted.transmittedWeight.b, 0.25f * (1.f - R) / (n * n), 1e-6f);
}

TEST(Dielectric, SmoothNormalsThatFlipADirectionFallBackToTheGeometricNormal) {
    // A shading normal tilted so far that the mirror direction would go below the surface.
    const Vec3f ng = kUp;
    const Vec3f ns = normalize(Vec3f{0.9f, 0.3f, 0.f});
    const Vec3f wo = fromAngle(-70.f);
    const DielectricSplit s = splitDielectric(wo, ns, ng, 1.5f, Rgb(1.f));
    EXPECT_GT(dot(s.reflected, ng), 0.f);
    ASSERT_TRUE(s.transmitted);
    EXPECT_LT(dot(*s.transmitted, ng), 0.f);
}

TEST(Dielectric, SampledBranchFrequenciesMatchFresnel) {
    // The sampled branch is a two-outcome distribution: reflect with probability F.
    // Pearson's chi-square summed over the incidence angles without total
    // internal reflection (one degree of freedom each: an angle's two counts add
    // to N) against the p = 0.001 critical value (Wilson-Hilferty); and the
    // sampled weights times their probabilities reproduce the split's weights.
    const int kN = 20000;
    double chi2 = 0.0;
    int angles = 0, dof = 0;
    for (float eta : {1.5f, 1.f / 1.5f}) {
        for (float deg : {0.f, 15.f, 30.f, 40.f, 60.f, 80.f}) {
            const Vec3f wo = fromAngle(deg);
            const DielectricSplit split = splitDielectric(wo, kUp, kUp, eta, Rgb(0.8f));
            const float F = split.reflectedWeight.r;
            int reflected = 0;
            for (int i = 0; i < kN; ++i) {
                const float u = toUnitFloat(mix64(uint64_t(i) * 0x9e3779b97f4a7c15ULL + uint64_t(angles)));
                const DielectricSample s = sampleDielectric(wo, kUp, kUp, eta, Rgb(0.8f), u);
                if (!s.transmitted) {
                    ++reflected;
                    EXPECT_NEAR(s.probability, split.transmitted ? F : 1.f, 1e-6f);
                    EXPECT_NEAR((s.weight * s.probability).r, F, 1e-6f);
                } else {
                    EXPECT_NEAR(s.probability, 1.f - F, 1e-6f);
                    EXPECT_NEAR((s.weight * s.probability).r, split.transmittedWeight.r, 1e-6f);
                }
            }
            ++angles;
            if (F >= 1.f) {
                EXPECT_EQ(reflected, kN);  // total internal reflection
                continue;
            }
            const double eR = double(kN) * F, eT = double(kN) * (1.0 - F);
            const double r = reflected, t = kN - reflected;
            ++dof;
            chi2 += (r - eR) * (r - eR) / eR + (t - eT) * (t - eT) / eT;
        }
    }
    ASSERT_EQ(dof, 10);  // 60 and 80 degrees from inside the glass are totally reflected
    const double k = dof, z = 3.0902;  // the standard normal's 0.999 quantile
    const double critical = k * std::pow(1.0 - 2.0 / (9.0 * k) + z * std::sqrt(2.0 / (9.0 * k)), 3.0);  // 29.6
    EXPECT_LT(chi2, critical) << "chi-square of the reflect/refract frequencies against Fresnel";
}
