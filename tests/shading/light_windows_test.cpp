// LightWindows, which drops a direct-light BRDF sample before its direction
// is made where it can meet no light: it must never drop one whose ray the
// exact test meets a light with, and it must drop most of the rest under small
// lights. PhongSampler::polar, which it reads, must describe the direction
// that direction() then makes.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <vector>

#include "core/multi_jitter.h"
#include "core/ray.h"
#include "core/sampling.h"
#include "core/shapes.h"
#include "lights/light_set.h"
#include "shading/light_windows.h"
#include "shading/bsdf/phong_sampling.h"

using namespace penumbra;

namespace {

// Deterministic uniform floats in [0, 1).
struct Rng {
    uint64_t state;
    float next() {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return float(state >> 40) * 0x1p-24f;
    }
    Vec2f next2() { return {next(), next()}; }
};

Material material(float kd, float ks, float exponent, PhongModel model) {
    Material m;
    m.kd = Rgb(kd);
    m.ks = Rgb(ks);
    m.exponent = exponent;
    m.model = model;
    return m;
}

// A scene whose material 0 is plain and material 1 a lamp (ke = 1).
Scene plainAndLamp() {
    Scene s;
    Material plain, lamp;
    lamp.ke = Rgb(1.f);
    s.materials = {plain, lamp};
    return s;
}

}  // namespace

TEST(PhongSampling, PolarCoordinatesDescribeTheDirectionMade) {
    // s: the sine of the angle from n (diffuse) or 1 - cos^(e+1) of the angle
    // from the mirror direction; azimuth: the direction's, in eighths of a turn.
    const Vec3f n = normalize(Vec3f{0.3f, 0.8f, -0.2f}), wo = normalize(Vec3f{-0.4f, 0.7f, 0.5f});
    int diffuse = 0, lobe = 0;
    for (const float e : {1.f, 40.f, 2000.f}) {
        const Material m = material(0.5f, 0.3f, e, PhongModel::Classic);
        const PhongSampler sampler(m, m.kd, n, wo);
        for (uint32_t k = 0; k < 4096; ++k) {
            const Vec2f u = multiJitter2D(k, 4096, 7);
            const PhongSampler::Polar c = sampler.polar(u);
            const std::optional<Vec3f> wi = sampler.direction(u);
            if (!wi) continue;
            const Frame& f = sampler.lobeFrame(c.diffuse);
            const Vec3f local = f.toLocal(*wi);
            const double angle = std::acos(std::min(1.0, double(local.z)));
            const double s = c.diffuse ? std::sin(angle) : 1.0 - std::pow(double(local.z), double(e) + 1.0);
            (c.diffuse ? diffuse : lobe) += 1;
            EXPECT_NEAR(c.s, s, 2e-3) << "e " << e << " sample " << k;
            if (angle < 0.01) continue;  // the azimuth is ill-conditioned next to the axis
            const double azimuth = std::atan2(double(local.y), double(local.x)) / (kPi / 4.0);
            const double turn = std::remainder(double(c.azimuth) - azimuth, 8.0);
            EXPECT_NEAR(turn, 0.0, 1e-3) << "e " << e << " sample " << k;
            EXPECT_GE(c.azimuth, -1.f);
            EXPECT_LT(c.azimuth, 8.f);
        }
    }
    EXPECT_GT(diffuse, 3000);
    EXPECT_GT(lobe, 1500);
}

TEST(LightWindows, NeverDropASampleThatMeetsALightAndDropMostOthers) {
    // Small lights of every kind, seen from points all around them with
    // Phong materials from nearly diffuse to sharply glossy. A dropped sample
    // must be one whose ray (spawnRay, as the integrator's) meets no light
    // in the exact test; a sphere light's bounding sphere is the light
    // itself, so rays grazing it check the cone's width.
    Scene s = plainAndLamp();
    s.rectangles.push_back(Rectangle{Vec3f{-0.6f, 0.9f, -0.3f}, Vec3f{0.5f, 0, 0}, Vec3f{0, 0, 0.4f}, 1});
    s.spheres.push_back(Sphere{Vec3f{0.8f, 0.f, 0.1f}, 0.3f, 1});
    s.disks.push_back(Disk{Vec3f{0, -0.8f, 0}, normalize(Vec3f{0.2f, 1, 0.1f}), 0.25f, 1});
    TriangleMesh mesh;
    for (Vec3f p : {Vec3f{-1, -0.2f, 0.6f}, Vec3f{-0.6f, -0.2f, 0.7f}, Vec3f{-0.8f, 0.2f, 0.6f}}) mesh.positions.push_back(p);
    mesh.indices = {0, 1, 2};
    mesh.faceMaterials = {1};
    s.meshes.push_back(mesh);
    const LightSet lights(s);
    ASSERT_TRUE(lights.emittersTestable());
    ASSERT_EQ(lights.areaLightCount(), 4u);

    const std::vector<Material> materials = {
        material(0.8f, 0.f, 1.f, PhongModel::Classic),         material(0.5f, 0.2f, 10.f, PhongModel::Classic),
        material(0.14f, 0.191f, 40.f, PhongModel::Classic),   material(0.2f, 0.5f, 300.f, PhongModel::Normalized),
        material(0.f, 0.9f, 5000.f, PhongModel::Normalized), material(0.f, 0.7f, 2.f, PhongModel::Classic)};
    Rng rng{12345};
    long dropped = 0, kept = 0, meeting = 0, meetingNearTheEdge = 0;
    for (int point = 0; point < 240; ++point) {
        // A point 1.5 to 4 from the centre, a normal facing roughly back to the lights, wo above it.
        const Vec3f out = squareToUniformSphere(rng.next2());
        const Vec3f p = (1.5f + 2.5f * rng.next()) * out;
        const Vec3f ng = normalize(-out + 0.9f * squareToUniformSphere(rng.next2()));
        Vec3f wo = squareToUniformSphere(rng.next2());
        if (dot(wo, ng) < 0.f) wo = -wo;
        const Material& m = materials[size_t(point) % materials.size()];
        const PhongSampler sampler(m, m.kd, ng, wo);
        const LightWindows windows(sampler, lights, p);
        for (int k = 0; k < 8192; ++k) {
            const Vec2f u = rng.next2();
            const bool may = windows.mayReachALight(u);
            const std::optional<Vec3f> wi = sampler.direction(u);
            if (!wi || dot(*wi, ng) <= 0.f) continue;  // the integrator drops these anyway
            const Ray ray = spawnRay(p, ng, *wi);
            const std::optional<LightSet::EmitterHit> e = lights.firstEmitterHit(ray);
            if (e) {
                ++meeting;
                // Within 1% of the sphere light's radius of its silhouette.
                const Sphere& b = s.spheres[0];
                const Vec3f oc = b.center - ray.o;
                const float miss = std::sqrt(std::max(0.f, dot(oc, oc) - dot(oc, ray.d) * dot(oc, ray.d)));
                meetingNearTheEdge += e->ref.kind == ShapeKind::Sphere && miss > 0.99f * b.radius;
            }
            ASSERT_TRUE(may || !e) << "point " << point << ", sample " << k << " meets light " << e->light
                                   << " but was dropped";
            (may ? kept : dropped) += 1;
        }
        // The lanes' answers are the scalar ones, and so are their polar coordinates.
        for (int k = 0; k < 64; ++k) {
            alignas(64) float x[16], y[16], s[16], azimuth[16];
            alignas(64) int32_t may[16], diffuse[16];
            for (int c = 0; c < 16; ++c) {
                const Vec2f u = rng.next2();
                x[c] = u.x;
                y[c] = u.y;
            }
            windows.mayReachLanes(x, y, may);
            sampler.polarLanes(x, y, diffuse, s, azimuth);
            for (int c = 0; c < 16; ++c) {
                ASSERT_EQ(may[c] != 0, windows.mayReachALight({x[c], y[c]})) << point << " " << k << " " << c;
                const PhongSampler::Polar p1 = sampler.polar({x[c], y[c]});
                ASSERT_EQ(diffuse[c] != 0, p1.diffuse);
                ASSERT_EQ(std::bit_cast<uint32_t>(s[c]), std::bit_cast<uint32_t>(p1.s));
                ASSERT_EQ(std::bit_cast<uint32_t>(azimuth[c]), std::bit_cast<uint32_t>(p1.azimuth));
            }
        }
    }
    EXPECT_GT(meeting, 20000);
    EXPECT_GT(meetingNearTheEdge, 100);  // rays that graze the sphere light were checked
    // Most samples are dropped: the lights fill a small share of the directions.
    EXPECT_GT(double(dropped), 3.0 * double(kept)) << dropped << " dropped, " << kept << " kept";
}

TEST(LightWindows, KeepEverySampleWhereThePointIsInsideALightsBounds) {
    // A point inside a light's bounding sphere (here on the light itself) may
    // see it in any direction: nothing is dropped.
    Scene s = plainAndLamp();
    s.rectangles.push_back(Rectangle{Vec3f{-1, 0, -1}, Vec3f{2, 0, 0}, Vec3f{0, 0, 2}, 1});
    const LightSet lights(s);
    const Material m = material(0.f, 0.9f, 5000.f, PhongModel::Normalized);
    const PhongSampler sampler(m, m.kd, Vec3f{0, 1, 0}, normalize(Vec3f{1, 1, 0}));
    const LightWindows windows(sampler, lights, Vec3f{0.5f, 0.f, 0.2f});
    for (uint32_t k = 0; k < 1024; ++k) EXPECT_TRUE(windows.mayReachALight(multiJitter2D(k, 1024, 3)));
}

TEST(PhongSampling, PolarRangeOfAnglesGivenByCosineAndSine) {
    // The range must hold the exact coordinates of both ends (rounded
    // outwards, by at most a few floats), be empty past a quarter turn and
    // open-ended at the axis and at a quarter turn.
    const Vec3f n{0, 0, 1}, wo = normalize(Vec3f{0.3f, 0.1f, 1.f});
    const auto at = [](double a) { return PhongSampler::Angle{std::cos(a), std::sin(a)}; };
    Rng rng{99};
    for (const float e : {1.f, 40.f, 5000.f}) {
        const Material m = material(0.5f, 0.3f, e, PhongModel::Classic);
        const PhongSampler sampler(m, m.kd, n, wo);
        for (const bool diffuse : {false, true}) {
            const auto exact = [&](double a) {
                return diffuse ? std::sin(a) : 1.0 - std::pow(std::cos(a), double(e) + 1.0);
            };
            for (int k = 0; k < 2000; ++k) {
                const double lo = 1.5 * double(rng.next()), hi = lo + 0.06 * double(rng.next());
                const auto [l, h] = sampler.polarRange(diffuse, at(lo), at(hi));
                ASSERT_LE(double(l), exact(lo)) << e << " " << lo;
                EXPECT_NEAR(double(l), exact(lo), 1e-6);
                if (hi >= kPi / 2.0) {
                    EXPECT_EQ(h, std::numeric_limits<float>::infinity());
                } else {
                    ASSERT_GE(double(h), exact(hi)) << e << " " << hi;
                    EXPECT_NEAR(double(h), exact(hi), 1e-6);
                }
            }
            const auto [l0, h0] = sampler.polarRange(diffuse, at(-0.2), at(0.3));  // the axis inside
            EXPECT_EQ(l0, -std::numeric_limits<float>::infinity());
            EXPECT_NEAR(double(h0), exact(0.3), 1e-6);
            const auto [l1, h1] = sampler.polarRange(diffuse, at(1.2), at(2.0));  // past a quarter turn
            EXPECT_NEAR(double(l1), exact(1.2), 1e-6);
            EXPECT_EQ(h1, std::numeric_limits<float>::infinity());
            const auto [l2, h2] = sampler.polarRange(diffuse, at(1.7), at(2.5));  // beyond the lobe
            EXPECT_GT(l2, h2);
        }
    }
}
