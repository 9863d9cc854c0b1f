// ShadowLanes (one shadow ray per lane, as arrays) against the rule it
// vectorises: shadowSampleWeight, spawnRayTo and Accelerator::occluded lane
// by lane, bit for bit, for Lambertian, glossy and MIS lanes in both Phong
// models, samples behind the surface, occluded and unoccluded rays; under an
// area light and under point and directional lights (whose samples are exact).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "accel/accelerator.h"
#include "core/multi_jitter.h"
#include "core/scene.h"
#include "lights/area_light.h"
#include "lights/delta_lights.h"
#include "lights/light_lanes.h"
#include "shading/bsdf/phong.h"
#include "shading/shadow_lanes.h"

namespace penumbra {
namespace {

Logger quietLogger() {
    return Logger([](LogLevel, std::string_view) {});
}

// A floor, a sphere casting a shadow on part of it, and a rectangle light above.
Scene litScene() {
    Scene s;
    Material light;
    light.kd = Rgb(0.f);
    light.ke = Rgb(5.f, 4.f, 3.f);
    s.materials.push_back(light);
    s.rectangles.push_back(Rectangle{Vec3f{-1.f, 4.f, -1.f}, Vec3f{2.f, 0, 0}, Vec3f{0, 0, 2.f}, 0});  // faces down
    s.spheres.push_back(Sphere{Vec3f{0.f, 2.f, 0.f}, 0.7f, 0});
    s.planes.push_back(Plane{Vec3f{0, 0, 0}, Vec3f{0, 1, 0}, true, 0});
    s.finalize(quietLogger());
    return s;
}

std::vector<Material> materials() {
    std::vector<Material> ms;
    Material m;
    m.kd = Rgb(0.6f, 0.5f, 0.4f);
    m.ks = Rgb(0.f);
    m.model = PhongModel::Classic;
    ms.push_back(m);  // Lambertian, classic
    m.model = PhongModel::Normalized;
    ms.push_back(m);  // Lambertian, normalised
    m.ks = Rgb(0.3f);
    m.exponent = 20.f;
    ms.push_back(m);  // glossy, normalised
    m.model = PhongModel::Classic;
    ms.push_back(m);  // glossy, classic
    return ms;
}

// Point i of a test: on the floor (some in the sphere's shadow), its material
// one of ms in turn, its shading normal and wo from a and u; every seventh faces
// away (every sample below the surface).
ShadingPoint floorPoint(uint32_t i, Vec2f a, Vec2f u, const std::vector<Material>& ms) {
    ShadingPoint sp;
    sp.material = &ms[i % ms.size()];
    sp.kd = sp.material->kd;
    sp.glossy = sp.material->isGlossy();  // as SurfaceShading::shade sets it
    sp.p = Vec3f{6.f * a.x - 3.f, 0.f, 6.f * a.y - 3.f};
    sp.ng = i % 7 == 5 ? Vec3f{0, -1, 0} : Vec3f{0, 1, 0};
    sp.ns = normalize(Vec3f{0.3f * (u.y - 0.5f), 1.f, 0.2f});
    sp.wo = normalize(Vec3f{a.y - 0.5f, 0.8f, a.x - 0.2f});
    return sp;
}

// The scalar rule's answer for one sample: its weight (light pdf lightPdf) where
// shadowSampleWeight keeps it and its shadow ray (spawnRayTo, or spawnRay for a
// direction) meets nothing; Rgb{} otherwise, counting the occluded ones.
Rgb scalarAnswer(const ShadingPoint& sp, const LightSample& ls, float lightPdf, float mis, float nLight,
                 const Accelerator& accel, int& shadowed) {
    Rgb w;
    if (!shadowSampleWeight(sp, ls, 1.f, lightPdf, mis, nLight, w)) return {};
    const Ray ray = std::isinf(ls.distance) ? spawnRay(sp.p, sp.ng, ls.wi) : spawnRayTo(sp.p, sp.ng, ls.point);
    if (!accel.occluded(ray)) return w;
    ++shadowed;
    return {};
}

TEST(ShadowLanes, WeightsAndRaysAreThoseOfTheScalarRuleBitForBit) {
    const Scene scene = litScene();
    const auto accel = makeAccelerator(AcceleratorKind::Embree, scene);
    const ShapeAreaLight light(scene, ShapeAreaLight::Kind::Rectangle, 0);
    const std::vector<Material> ms = materials();
    constexpr int W = ShadowLanes::kWidth;
    constexpr int kPoints = 200;
    std::vector<ShadingPoint> sps(kPoints);
    int traced = 0, added = 0, shadowed = 0;
    for (int b = 0; b < kPoints; b += W) {
        const int n = std::min(W, kPoints - b);
        ShadowLanes lanes;
        LightLanes samples;
        float mis[W] = {};  // the MIS count: one BSDF sample per point where set
        for (int c = 0; c < n; ++c) {
            const uint32_t i = uint32_t(b + c);
            const Vec2f a = multiJitter2D(i, kPoints, 3), u = multiJitter2D(i, kPoints, 4);
            ShadingPoint& sp = sps[i];
            sp = floorPoint(i, a, u, ms);
            mis[c] = i % 3 == 1 ? 1.f : 0.f;
            lanes.setLane(c, sp, mis[c]);
            std::optional<LightSample> ls = light.sample(sp.p, u);
            if (ls && i % 11 == 4) ls->distance = kInfinity;  // a sample in a direction (as environments give)
            samples.set(c, ls);
        }
        Rgb got[W];
        traced += int(lanes.trace(samples, n, 2.f, *accel, got));
        for (int c = 0; c < n; ++c) {
            const ShadingPoint& sp = sps[size_t(b + c)];
            Rgb want;
            if (samples.ok[c]) {
                const LightSample ls = samples.get(c);
                want = scalarAnswer(sp, ls, ls.pdf, mis[c], 2.f, *accel, shadowed);
            }
            EXPECT_EQ(got[c], want) << "point " << b + c;
            added += got[c].isBlack() ? 0 : 1;
        }
    }
    // Every kind of lane was there: traced, unoccluded, in the shadow.
    EXPECT_GT(added, kPoints / 3);
    EXPECT_GT(shadowed, 5);
    EXPECT_GE(traced, added + shadowed);
}

TEST(ShadowLanes, DeltaLightWeightsAreThoseOfTheScalarRuleBitForBit) {
    // What DirectLight did lane by lane for a point or directional light: sample(p, {0.5, 0.5}),
    // shadowSampleWeight with light pdf 1 (no MIS: a delta light's samples ignore the count),
    // spawnRayTo (spawnRay for a direction) and occluded.
    const Scene scene = litScene();
    const auto accel = makeAccelerator(AcceleratorKind::Embree, scene);
    const PointLightSource point(PointLight{Vec3f{1.6f, 3.2f, -0.2f}, Rgb(40.f, 30.f, 20.f)});  // below the rectangle
    const DirectionalLightSource sun(DirectionalLight{normalize(Vec3f{0.2f, -1.f, 0.1f}), Rgb(2.f, 1.5f, 1.f)}, 10.f);
    const std::vector<Material> ms = materials();
    constexpr int W = ShadowLanes::kWidth;
    constexpr int kPoints = 200;
    for (const Light* light : {static_cast<const Light*>(&point), static_cast<const Light*>(&sun)}) {
        std::vector<ShadingPoint> sps(kPoints);
        int added = 0, shadowed = 0;
        for (int b = 0; b < kPoints; b += W) {
            const int n = std::min(W, kPoints - b);
            ShadowLanes lanes;
            float mis[W] = {};
            alignas(64) int32_t want[W];
            alignas(64) float half[W];
            for (int c = 0; c < n; ++c) {
                const uint32_t i = uint32_t(b + c);
                const Vec2f a = multiJitter2D(i, kPoints, 5), u = multiJitter2D(i, kPoints, 6);
                ShadingPoint& sp = sps[i];
                sp = floorPoint(i, a, u, ms);
                mis[c] = i % 3 == 1 ? 1.f : 0.f;
                lanes.setLane(c, sp, mis[c]);
                want[c] = 1;
                half[c] = 0.5f;
            }
            LightLanes samples;
            light->sampleLanes(lanes.points(), half, half, want, n, samples);
            ASSERT_TRUE(samples.delta);
            Rgb got[W];
            lanes.trace(samples, n, 4.f, *accel, got);
            for (int c = 0; c < n; ++c) {
                const ShadingPoint& sp = sps[size_t(b + c)];
                const std::optional<LightSample> ls = light->sample(sp.p, Vec2f{0.5f, 0.5f});
                ASSERT_TRUE(ls);
                ASSERT_EQ(samples.get(c).L, ls->L);
                ASSERT_EQ(samples.get(c).wi, ls->wi);
                EXPECT_EQ(got[c], scalarAnswer(sp, *ls, 1.f, 0.f, 4.f, *accel, shadowed)) << "point " << b + c;
                added += got[c].isBlack() ? 0 : 1;
            }
        }
        EXPECT_GT(added, kPoints / 3);
        EXPECT_GT(shadowed, 5);
    }
}

TEST(ShadowLanes, TheScalarRuleMatchesThePhongResponse) {
    // shadowSampleWeight without MIS is phongResponse * L / pdf, zero below the surface.
    const Material m = materials()[2];
    ShadingPoint sp;
    sp.material = &m;
    sp.kd = m.kd;
    sp.p = Vec3f{0, 0, 0};
    sp.ng = sp.ns = Vec3f{0, 1, 0};
    sp.wo = normalize(Vec3f{1, 1, 0});
    const LightSample ls{Rgb(2.f), normalize(Vec3f{-1, 1, 0}), Vec3f{-1, 1, 0}, std::sqrt(2.f), 0.5f, false};
    Rgb w;
    ASSERT_TRUE(shadowSampleWeight(sp, ls, 1.f, ls.pdf, 0.f, 1.f, w));
    const Rgb f = phongResponse(m, m.kd, sp.ns, sp.wo, ls.wi, false);
    EXPECT_EQ(w, f * ls.L * (1.f / 0.5f));
    LightSample below = ls;
    below.wi = normalize(Vec3f{-1, -1, 0});
    EXPECT_FALSE(shadowSampleWeight(sp, below, 1.f, below.pdf, 0.f, 1.f, w));
    // Under MIS the weight shrinks by the power heuristic against the BRDF's pdf.
    Rgb misW;
    ASSERT_TRUE(shadowSampleWeight(sp, ls, 1.f, ls.pdf, 1.f, 1.f, misW));
    EXPECT_LT(misW.r, w.r);
    EXPECT_GT(misW.r, 0.f);
}

}  // namespace
}  // namespace penumbra
