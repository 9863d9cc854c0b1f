// ShadowLanes (one shadow ray per lane, as arrays) against the rule it
// vectorises: shadowSampleWeight, spawnRayTo and Accelerator::occluded lane
// by lane, bit for bit, for Lambertian, glossy and MIS lanes in both Phong
// models, samples behind the surface, occluded and unoccluded rays.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "accel/accelerator.h"
#include "core/multi_jitter.h"
#include "core/scene.h"
#include "lights/area_light.h"
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
            sp.material = &ms[i % ms.size()];
            sp.kd = sp.material->kd;
            sp.glossy = sp.material->isGlossy();  // as SurfaceShading::shade sets it
            sp.p = Vec3f{6.f * a.x - 3.f, 0.f, 6.f * a.y - 3.f};  // on the floor, some in the sphere's shadow
            sp.ng = Vec3f{0, 1, 0};
            sp.ns = normalize(Vec3f{0.3f * (u.y - 0.5f), 1.f, 0.2f});
            sp.wo = normalize(Vec3f{a.y - 0.5f, 0.8f, a.x - 0.2f});
            if (i % 7 == 5) sp.ng = Vec3f{0, -1, 0};  // facing away: every sample below the surface
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
                Rgb w;
                if (shadowSampleWeight(sp, ls, 1.f, ls.pdf, mis[c], 2.f, w)) {
                    const Ray ray =
                        std::isinf(ls.distance) ? spawnRay(sp.p, sp.ng, ls.wi) : spawnRayTo(sp.p, sp.ng, ls.point);
                    if (!accel->occluded(ray)) {
                        want = w;
                    } else {
                        ++shadowed;
                    }
                }
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
