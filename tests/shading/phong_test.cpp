// The Phong BRDF in both models against hand-computed values.
#include "shading/bsdf/phong.h"

#include <gtest/gtest.h>


using namespace penumbra;

namespace {
Material makeMaterial(PhongModel model) {
    Material m;
    m.kd = Rgb(0.5f);
    m.ks = Rgb(0.3f);
    m.exponent = 10.f;
    m.model = model;
    return m;
}
}  // namespace

TEST(Phong, ClassicDeltaLightReproducesTheLectureFormula) {
    // n = +y; light direction s at 60 degrees from the normal in the xy-plane;
    // viewer v exactly along the mirror direction rotated by 10 degrees.
    Material m = makeMaterial(PhongModel::Classic);
    const float ts = 60.f * kPi / 180.f;
    Vec3f n{0, 1, 0}, s{-std::sin(ts), std::cos(ts), 0};
    const float tv = 50.f * kPi / 180.f;  // r is at +60 deg; v at +50 deg: angle(v, r) = 10 deg
    Vec3f v{std::sin(tv), std::cos(tv), 0};
    Rgb resp = phongResponse(m, m.kd, n, v, s, true);
    // kd (n.s) + ks (v.r)^n = 0.5 * 0.5 + 0.3 * cos(10 deg)^10
    const float expected = 0.5f * 0.5f + 0.3f * std::pow(std::cos(10.f * kPi / 180.f), 10.f);
    EXPECT_NEAR(resp.r, expected, 1e-6f);
    EXPECT_NEAR(resp.r, 0.25f + 0.3f * 0.858054f, 1e-5f);  // the number written out
}

TEST(Phong, NormalizedModelIsKdOverPiPlusNormalizedLobeTimesCosine) {
    Material m = makeMaterial(PhongModel::Normalized);
    Vec3f n{0, 0, 1}, wi = normalize(Vec3f{0.3f, 0, 1}), wo = normalize(Vec3f{-0.3f, 0, 1});  // wo = mirror of wi
    Rgb resp = phongResponse(m, m.kd, n, wo, wi, false);
    const float cosTheta = wi.z;
    const float expected = (0.5f / kPi + 0.3f * 12.f / (2.f * kPi) * 1.f) * cosTheta;
    EXPECT_NEAR(resp.g, expected, 1e-5f);
}

TEST(Phong, LightBelowTheSurfaceContributesNothing) {
    Material m = makeMaterial(PhongModel::Normalized);
    Rgb resp = phongResponse(m, m.kd, Vec3f{0, 0, 1}, Vec3f{0, 0, 1}, Vec3f{0, 0.2f, -1.f}, false);
    EXPECT_TRUE(resp.isBlack());
}

TEST(Phong, NormalizedLambertianAlbedoIntegratesToKd) {
    // Directional albedo of the diffuse part, int f cos dw over the hemisphere
    // (midpoint rule in (cos theta, phi), uniform pdf 1/(2 pi)), equals kd.
    Material m = makeMaterial(PhongModel::Normalized);
    m.ks = Rgb(0.f);
    const Vec3f wo = normalize(Vec3f{0.5f, 0, 1});
    double sum = 0;
    const int n = 200;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            float ct = (i + 0.5f) / n, phi = 2 * kPi * (j + 0.5f) / n;
            float st = std::sqrt(1 - ct * ct);
            Vec3f wi{st * std::cos(phi), st * std::sin(phi), ct};
            sum += phongResponse(m, m.kd, Vec3f{0, 0, 1}, wo, wi, false).r * 2 * M_PI;
        }
    EXPECT_NEAR(sum / (double(n) * n), 0.5, 1e-4);
}

TEST(Phong, NormalizedSpecularLobeConservesEnergyAtNormalIncidence) {
    // With wo = n, int ks (n+2)/(2pi) cos^n(alpha) cos(theta) dw = ks (alpha = theta here).
    Material m = makeMaterial(PhongModel::Normalized);
    m.kd = Rgb(0.f);
    m.ks = Rgb(1.f);
    m.exponent = 20.f;
    double sum = 0;
    const int n = 400;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            // Uniform hemisphere by (cos theta, phi) grid: pdf 1/(2pi).
            float ct = (i + 0.5f) / n, phi = 2 * kPi * (j + 0.5f) / n;
            float st = std::sqrt(1 - ct * ct);
            Vec3f wi{st * std::cos(phi), st * std::sin(phi), ct};
            sum += phongResponse(m, m.kd, Vec3f{0, 0, 1}, Vec3f{0, 0, 1}, wi, false).r * 2 * M_PI;
        }
    EXPECT_NEAR(sum / (double(n) * n), 1.0, 2e-3);
}
