// Light sampling: pdfs integrate correctly, mesh lights pick triangles by
// area, power selection follows power, one-sided emission.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "core/multi_jitter.h"
#include "lights/area_light.h"
#include "lights/delta_lights.h"
#include "lights/light_set.h"

using namespace penumbra;

namespace {

Scene sceneWithEmitter(bool twoSided) {
    Scene s;
    Material m;
    m.kd = Rgb(0.f);
    m.ke = Rgb(2.f);
    m.twoSidedEmission = twoSided;
    s.materials.push_back(m);
    return s;
}

// Solid angle of an axis-aligned square [-h, h]^2 at height d seen from below its centre.
double squareSolidAngle(double h, double d) { return 4.0 * std::asin(h * h / (h * h + d * d)); }

}  // namespace

TEST(AreaLights, RectangleSolidAnglePdfIntegratesToTheSubtendedSolidAngle) {
    Scene s = sceneWithEmitter(false);
    s.rectangles.push_back(Rectangle{Vec3f{-0.5f, 1.f, -0.5f}, Vec3f{1, 0, 0}, Vec3f{0, 0, 1}, 0});  // faces -y
    ShapeAreaLight light(s, ShapeAreaLight::Kind::Rectangle, 0);
    const uint32_t n = 64 * 64;
    double sum = 0;
    for (uint32_t k = 0; k < n; ++k) {
        auto ls = light.sample(Vec3f{0, 0, 0}, multiJitter2D(k, n, 5));
        ASSERT_TRUE(ls.has_value());
        EXPECT_NEAR(length(ls->wi), 1.f, 1e-5f);
        EXPECT_EQ(ls->L.r, 2.f);
        sum += 1.0 / ls->pdf;  // E[1/p_w] = solid angle
    }
    EXPECT_NEAR(sum / n, squareSolidAngle(0.5, 1.0), 1e-4);
    // From above, a one-sided light facing down gives nothing.
    EXPECT_FALSE(light.sample(Vec3f{0, 2, 0}, Vec2f{0.5f, 0.5f}).has_value());
}

TEST(AreaLights, TwoSidedDiskEmitsOnBothSides) {
    Scene s = sceneWithEmitter(true);
    s.disks.push_back(Disk{Vec3f{0, 1, 0}, Vec3f{0, -1, 0}, 0.5f, 0});
    ShapeAreaLight light(s, ShapeAreaLight::Kind::Disk, 0);
    EXPECT_TRUE(light.sample(Vec3f{0, 0, 0}, Vec2f{0.3f, 0.6f}).has_value());
    EXPECT_TRUE(light.sample(Vec3f{0, 2, 0}, Vec2f{0.3f, 0.6f}).has_value());
    EXPECT_NEAR(light.area(), kPi * 0.25f, 1e-6f);
    EXPECT_NEAR(light.power(), 2.f * kPi * 0.25f * kPi * 2.f, 1e-4f);
}

TEST(AreaLights, SphereLightFromOutsideSeesOnlyItsNearSideAndPdfIntegrates) {
    Scene s = sceneWithEmitter(false);
    s.spheres.push_back(Sphere{Vec3f{0, 0, 0}, 1.f, 0});
    ShapeAreaLight light(s, ShapeAreaLight::Kind::Sphere, 0);
    const Vec3f p{0, 0, 3};
    const uint32_t n = 128 * 128;
    double sum = 0;
    int used = 0;
    for (uint32_t k = 0; k < n; ++k) {
        auto ls = light.sampleArea(p, multiJitter2D(k, n, 11));
        if (!ls) continue;
        ++used;
        EXPECT_GT(ls->point.z, 0.f) << "only the side facing p emits towards it";
        sum += 1.0 / ls->pdf;
    }
    // Visible cap solid angle: 2 pi (1 - sqrt(1 - (r/d)^2)); uniform area sampling
    // covers the whole sphere, so E[1/p_w * visible] = cap solid angle. About half the samples are used.
    const double cap = 2 * M_PI * (1 - std::sqrt(1 - 1.0 / 9.0));
    EXPECT_NEAR(sum / n, cap, 0.01 * cap);
    EXPECT_NEAR(double(used) / n, 1.0 / 3.0, 0.02);  // cap area fraction (1 - 1/3) / 2 = 1/3 of the sphere
    // Cone sampling uses every sample, each with pdf 1 / cap.
    for (uint32_t k = 0; k < 64; ++k) {
        auto ls = light.sample(p, multiJitter2D(k, 64, 11));
        ASSERT_TRUE(ls.has_value());
        EXPECT_NEAR(ls->pdf, 1.0 / cap, 1e-4 / cap);
        EXPECT_NEAR(length(ls->point), 1.f, 1e-5f);
        EXPECT_GT(ls->point.z, 0.f);
    }
}

TEST(AreaLights, MeshLightPicksTrianglesInProportionToArea) {
    Scene s = sceneWithEmitter(false);
    TriangleMesh m;
    // Two triangles facing +z: areas 0.5 and 1.5.
    for (Vec3f p : {Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 1, 0}, Vec3f{2, 0, 0}, Vec3f{5, 0, 0}, Vec3f{2, 1, 0}})
        m.positions.push_back(p);
    m.indices = {0, 1, 2, 3, 4, 5};
    s.meshes.push_back(m);
    MeshAreaLight light(s, 0, 0, {0, 1});
    EXPECT_NEAR(light.area(), 2.f, 1e-6f);
    const uint32_t n = 1000;
    int first = 0;
    for (uint32_t k = 0; k < n; ++k) {
        auto ls = light.sampleArea(Vec3f{1, 0.3f, 5}, multiJitter2D(k, n, 3));
        ASSERT_TRUE(ls.has_value());
        if (ls->point.x < 1.5f) ++first;
        // Area sampling: pdf is uniform over the light's whole area: p_A = 1/2.
        float cosL = -dot(Vec3f{0, 0, 1}, ls->wi);
        EXPECT_NEAR(ls->pdf, 0.5f * ls->distance * ls->distance / cosL, 1e-3f * ls->pdf);
    }
    EXPECT_NEAR(first / double(n), 0.25, 0.01);  // stratified: very close to 0.5 / 2.0
}

TEST(LightSet, BuildsOneLightPerEmitterAndSelectsByPower) {
    Scene s;
    Material dim, bright, plain;
    dim.ke = Rgb(1.f);
    bright.ke = Rgb(3.f);
    s.materials = {dim, bright, plain};
    s.rectangles.push_back(Rectangle{Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 0, 1}, 0});
    s.rectangles.push_back(Rectangle{Vec3f{0, 1, 0}, Vec3f{1, 0, 0}, Vec3f{0, 0, 1}, 1});
    s.spheres.push_back(Sphere{Vec3f{5, 0, 0}, 1.f, 2});  // not emissive
    TriangleMesh m;
    for (Vec3f p : {Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 1, 0}, Vec3f{0, 0, 1}}) m.positions.push_back(p);
    m.indices = {0, 1, 2, 0, 2, 3, 0, 3, 1};
    m.faceMaterials = {0, 1, 2};
    s.meshes.push_back(m);
    s.pointLights.push_back(PointLight{Vec3f{0, 5, 0}, Rgb(1.f)});
    LightSet lights(s);
    EXPECT_EQ(lights.areaLightCount(), 4u);  // 2 rectangles + 2 (mesh, material) groups
    EXPECT_EQ(lights.size(), 5u);
    EXPECT_NEAR(lights.totalEmitterArea(), 2.f + 0.5f + 0.5f, 1e-5f);
    // Power of rectangle 1 is 3x that of rectangle 0.
    auto p0 = lights.powerPicker().pick(0.0f, Vec3f{}, Vec3f{});
    EXPECT_EQ(p0.index, 0u);
    double total = 0;
    for (size_t i = 0; i < lights.size(); ++i) total += lights[i].power();
    EXPECT_NEAR(p0.probability, lights[0].power() / total, 1e-5);
    EXPECT_NEAR(lights[1].power() / lights[0].power(), 3.0, 1e-5);
}

TEST(LightSet, SolidAngleBoundOverLanesIsThePointwiseOne) {
    // A unit square lamp (bounding sphere radius sqrt(2)/2) and a point light:
    // lane l's answer against its own omega is mayExceedSolidAngle's, the
    // points from inside the sphere to far away, omegas from 0.01 sr to 2 pi.
    Scene s = sceneWithEmitter(false);
    s.rectangles.push_back(Rectangle{Vec3f{-0.5f, 2.f, -0.5f}, Vec3f{1, 0, 0}, Vec3f{0, 0, 1}, 0});
    s.pointLights.push_back(PointLight{Vec3f{0, 5, 0}, Rgb(1.f)});
    const LightSet lights(s);
    ASSERT_EQ(lights.size(), 2u);
    constexpr int W = LanePoints::kWidth;
    int exceeded = 0, notExceeded = 0;
    for (int round = 0; round < 8; ++round) {
        LanePoints at;
        float omega[W];
        for (int l = 0; l < W; ++l) {
            const Vec2f u = multiJitter2D(uint32_t(round * W + l), 8 * W, 9);
            const float height = 2.f - 6.f * u.x;  // from the lamp's plane to 4 below it
            at.set(l, Vec3f{0.3f * u.y, height, 0.1f}, Vec3f{0, 1, 0});
            omega[l] = 0.01f * std::pow(628.f, u.y);  // 0.01 to 2 pi sr
        }
        const int n = W - round;  // fewer lanes than the width too
        int32_t exceed[W];
        const bool any = lights.mayExceedSolidAngleLanes(0, at, omega, n, exceed);
        bool wantAny = false;
        for (int l = 0; l < n; ++l) {
            const bool want = lights.mayExceedSolidAngle(0, at.p(l), omega[l]);
            EXPECT_EQ(exceed[l], want ? 1 : 0) << "round " << round << " lane " << l;
            wantAny |= want;
            (want ? exceeded : notExceeded) += 1;
        }
        EXPECT_EQ(any, wantAny) << "round " << round;
        // A point light subtends nothing: no lane exceeds anything.
        EXPECT_FALSE(lights.mayExceedSolidAngleLanes(1, at, omega, n, exceed));
    }
    EXPECT_GT(exceeded, 10);
    EXPECT_GT(notExceeded, 10);
}

TEST(DeltaLights, PointLightFallsOffWithInverseSquare) {
    PointLightSource l(PointLight{Vec3f{0, 2, 0}, Rgb(8.f)});
    auto s = l.sample(Vec3f{0, 0, 0}, Vec2f{});
    ASSERT_TRUE(s.has_value());
    EXPECT_FLOAT_EQ(s->L.r, 2.f);
    EXPECT_FLOAT_EQ(s->distance, 2.f);
    EXPECT_TRUE(s->delta);
    DirectionalLightSource d(DirectionalLight{Vec3f{0, -1, 0}, Rgb(3.f)}, 1.f);
    auto ds = d.sample(Vec3f{4, 0, 1}, Vec2f{});
    ASSERT_TRUE(ds.has_value());
    EXPECT_EQ(ds->wi, (Vec3f{0, 1, 0}));
    EXPECT_TRUE(std::isinf(ds->distance));
    EXPECT_EQ(ds->L.g, 3.f);
}

// Light::mayReach is a bound taken before sampling: where it says no, every
// sample from p is discarded by the integrators (wi . n <= 0, or none at all);
// where a sample would count, it must say yes.
TEST(AreaLights, MayReachIsFalseOnlyWhereEverySampleIsDiscarded) {
    Scene s = sceneWithEmitter(false);
    s.rectangles.push_back(Rectangle{Vec3f{-0.5f, 1.f, -0.5f}, Vec3f{1, 0, 0}, Vec3f{0, 0, 1}, 0});  // faces -y
    s.rectangles.push_back(Rectangle{Vec3f{0.2f, 0.3f, -0.4f}, Vec3f{0.8f, 0, 0}, Vec3f{0.3f, 0.6f, 0.2f}, 0});
    s.disks.push_back(Disk{Vec3f{0.3f, 1.2f, 0.1f}, normalize(Vec3f{0.2f, -1.f, 0.3f}), 0.7f, 0});
    s.spheres.push_back(Sphere{Vec3f{-0.4f, 0.9f, 0.5f}, 0.6f, 0});
    TriangleMesh m;  // two one-sided triangles facing -y, tilted
    for (Vec3f v : {Vec3f{-0.6f, 1.1f, -0.2f}, Vec3f{0.4f, 1.3f, -0.2f}, Vec3f{-0.6f, 1.1f, 0.8f}, Vec3f{0.4f, 1.3f, 0.8f}})
        m.positions.push_back(v);
    m.indices = {0, 2, 1, 1, 2, 3};
    s.meshes.push_back(m);
    std::vector<std::unique_ptr<Light>> lights;
    lights.push_back(std::make_unique<ShapeAreaLight>(s, ShapeAreaLight::Kind::Rectangle, 0));
    lights.push_back(std::make_unique<ShapeAreaLight>(s, ShapeAreaLight::Kind::Rectangle, 1));
    lights.push_back(std::make_unique<ShapeAreaLight>(s, ShapeAreaLight::Kind::Disk, 0));
    lights.push_back(std::make_unique<ShapeAreaLight>(s, ShapeAreaLight::Kind::Sphere, 0));
    lights.push_back(std::make_unique<MeshAreaLight>(s, 0, 0, std::vector<uint32_t>{0, 1}));
    size_t said[2] = {0, 0};
    for (uint32_t i = 0; i < 400; ++i) {
        // Points around the lights, normals in every direction.
        const Vec2f a = multiJitter2D(i, 400, 3), b = multiJitter2D(i, 400, 4);
        const Vec3f p{3.f * a.x - 1.5f, 2.5f * b.x - 0.5f, 3.f * a.y - 1.5f};
        const float z = 2.f * b.y - 1.f, phi = 2.f * kPi * a.x * 7.f;
        const float r = std::sqrt(std::max(0.f, 1.f - z * z));
        const Vec3f n{r * std::cos(phi), z, r * std::sin(phi)};
        for (size_t l = 0; l < lights.size(); ++l) {
            const bool may = lights[l]->mayReach(p, n);
            ++said[may ? 1 : 0];
            bool counts = false;
            for (uint32_t k = 0; k < 256 && !counts; ++k) {
                const auto ls = lights[l]->sample(p, multiJitter2D(k, 256, 11 + uint32_t(l)));
                counts = ls && dot(ls->wi, n) > 0.f;
            }
            if (counts) {
                EXPECT_TRUE(may) << "light " << l << " point " << i;
            }
        }
    }
    // Both answers occur, so the test exercises the bound both ways.
    EXPECT_GT(said[0], 100u);
    EXPECT_GT(said[1], 100u);
}
