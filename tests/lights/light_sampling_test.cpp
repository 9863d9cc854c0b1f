// Solid-angle light sampling: chi-square fits of every sampling routine
// (cone, spherical rectangle, spherical triangle, area fallbacks) against
// Light::pdf, pdf() agreeing with the pdf of each sample, the emitter-hit
// lookup, and closed-form solid angles.
#include <gtest/gtest.h>

#include <cmath>

#include "core/multi_jitter.h"
#include "core/shapes.h"
#include "lights/area_light.h"
#include "lights/light_lanes.h"
#include "lights/light_set.h"
#include "lights/spherical_cap.h"
#include "lights/spherical_rectangle.h"
#include "lights/spherical_triangle.h"
#include "support/chi_square.h"

using namespace penumbra;
using penumbra::test::chiSquareDirections;

namespace {

Scene emitterScene(bool twoSided) {
    Scene s;
    Material m;
    m.kd = Rgb(0.f);
    m.ke = Rgb(2.f);
    m.twoSidedEmission = twoSided;
    s.materials.push_back(m);
    return s;
}

// The closest emitter hit along a ray (a brute-force loop over the shapes a
// LightSet turns into lights), completed as the accelerators complete hits.
std::optional<Hit> firstHit(const Scene& s, const Ray& ray) {
    std::optional<Hit> best;
    float tBest = kInfinity;
    auto consider = [&](std::optional<PrimHit> h, PrimRef ref) {
        if (h && h->t < tBest) {
            tBest = h->t;
            best = s.completeHit(ray, ref, h->t, h->u, h->v);
        }
    };
    for (uint32_t i = 0; i < s.rectangles.size(); ++i)
        consider(intersect(s.rectangles[i], ray), PrimRef{ShapeKind::Rectangle, i, 0});
    for (uint32_t i = 0; i < s.disks.size(); ++i) consider(intersect(s.disks[i], ray), PrimRef{ShapeKind::Disk, i, 0});
    for (uint32_t i = 0; i < s.spheres.size(); ++i)
        consider(intersect(s.spheres[i], ray), PrimRef{ShapeKind::Sphere, i, 0});
    for (uint32_t m = 0; m < s.meshes.size(); ++m)
        for (uint32_t t = 0; t < s.meshes[m].triangleCount(); ++t) {
            Vec3f p0, p1, p2;
            s.meshes[m].vertices(t, p0, p1, p2);
            consider(intersectTriangle(p0, p1, p2, ray), PrimRef{ShapeKind::Mesh, m, t});
        }
    return best;
}

// Chi-square test of light.sample (or sampleArea) from p against light.pdf,
// and each sample's pdf against light.pdf at the point it chose.
void expectLightFits(const Scene& scene, const Light& light, const Vec3f& p, bool area = false) {
    const uint32_t n = 200000;
    int mismatches = 0;
    const auto sample = [&](uint32_t i) -> std::optional<Vec3f> {
        const Vec2f u = multiJitter2D(i, n, 77);
        const auto ls = area ? light.sampleArea(p, u) : light.sample(p, u);
        if (!ls) return std::nullopt;
        if (!area && i % 97 == 0) {
            const auto h = firstHit(scene, Ray{p, ls->wi});
            if (!h || std::fabs(light.pdf(p, *h) - ls->pdf) > 2e-3f * ls->pdf) {
                if (mismatches++ < 3)
                    ADD_FAILURE() << "sample " << i << ": pdf " << ls->pdf << ", Light::pdf at its hit "
                                  << (h ? light.pdf(p, *h) : -1.f) << ", prim " << (h ? h->ref.prim : 0u)
                                  << ", point " << ls->point.x << " " << ls->point.y << " " << ls->point.z;
            }
        }
        return ls->wi;
    };
    const auto pdf = [&](const Vec3f& w) -> double {
        const auto h = firstHit(scene, Ray{p, w});
        return h ? light.pdf(p, *h) : 0.0;
    };
    const auto r = chiSquareDirections(sample, pdf);
    EXPECT_TRUE(r.passed) << r.message;
    EXPECT_EQ(mismatches, 0) << "Light::pdf disagrees with the pdf of sampled directions";
    // All of the light's solid angle is reachable: the pdf integrates to 1.
    EXPECT_NEAR(r.pdfIntegral, 1.0, 0.01) << r.message;
}

}  // namespace

TEST(LightSampling, SphereConeFitsItsPdf) {
    Scene s = emitterScene(false);
    s.spheres.push_back(Sphere{Vec3f{1.2f, 0.7f, 0.9f}, 0.9f, 0});
    ShapeAreaLight light(s, ShapeAreaLight::Kind::Sphere, 0);
    expectLightFits(s, light, Vec3f{0, 0, 0});
}

TEST(LightSampling, SmallFarSphereConeFitsItsPdf) {
    Scene s = emitterScene(false);
    s.spheres.push_back(Sphere{Vec3f{20.f, 10.f, 14.f}, 2.f, 0});
    ShapeAreaLight light(s, ShapeAreaLight::Kind::Sphere, 0);
    expectLightFits(s, light, Vec3f{0, 0, 0});
}

TEST(LightSampling, InsideATwoSidedSphereSamplesByArea) {
    Scene s = emitterScene(true);
    s.spheres.push_back(Sphere{Vec3f{0.2f, -0.1f, 0.3f}, 2.f, 0});
    ShapeAreaLight light(s, ShapeAreaLight::Kind::Sphere, 0);
    expectLightFits(s, light, Vec3f{0, 0, 0});
}

TEST(LightSampling, SphericalRectangleFitsItsPdf) {
    Scene s = emitterScene(false);
    // Faces the origin (cross(a, b) points to -x), off-centre.
    s.rectangles.push_back(Rectangle{Vec3f{1.f, -0.4f, 0.2f}, Vec3f{0, 0, 1.1f}, Vec3f{0, 1.5f, 0}, 0});
    ShapeAreaLight light(s, ShapeAreaLight::Kind::Rectangle, 0);
    expectLightFits(s, light, Vec3f{0, 0, 0});
}

TEST(LightSampling, TwoSidedRectangleFromBehindAndNearFitsItsPdf) {
    Scene s = emitterScene(true);
    s.rectangles.push_back(Rectangle{Vec3f{-1.f, -0.7f, 0.25f}, Vec3f{2.f, 0, 0}, Vec3f{0, 1.5f, 0}, 0});
    ShapeAreaLight light(s, ShapeAreaLight::Kind::Rectangle, 0);
    expectLightFits(s, light, Vec3f{0.1f, 0.2f, 0.f});
}

TEST(LightSampling, ParallelogramSamplesByArea) {
    Scene s = emitterScene(false);
    s.rectangles.push_back(Rectangle{Vec3f{1.f, -0.4f, 0.2f}, Vec3f{0, 0, 1.1f}, Vec3f{0.f, 1.2f, 0.6f}, 0});
    if (dot(rectangleNormal(s.rectangles[0]), Vec3f{-1, 0, 0}) < 0) std::swap(s.rectangles[0].a, s.rectangles[0].b);
    ShapeAreaLight light(s, ShapeAreaLight::Kind::Rectangle, 0);
    expectLightFits(s, light, Vec3f{0, 0, 0});
}

TEST(LightSampling, DiskSamplesByArea) {
    Scene s = emitterScene(false);
    s.disks.push_back(Disk{Vec3f{1.f, 0.5f, 0.6f}, normalize(Vec3f{-1.f, -0.2f, -0.3f}), 0.8f, 0});
    ShapeAreaLight light(s, ShapeAreaLight::Kind::Disk, 0);
    expectLightFits(s, light, Vec3f{0, 0, 0});
}

TEST(LightSampling, MeshLightMixesSphericalAndAreaTrianglesAndFitsItsPdf) {
    Scene s = emitterScene(false);
    TriangleMesh m;
    // Two large triangles close to the origin (spherical triangle sampling),
    // one tiny far one (area sampling), all facing the origin.
    for (Vec3f p : {Vec3f{1, -1, -0.5f}, Vec3f{1, 1, -0.5f}, Vec3f{1, 0, 1.2f}, Vec3f{-0.5f, 1, -0.6f},
                    Vec3f{-0.8f, 1, 0.9f}, Vec3f{0.9f, 1.1f, 0.4f}, Vec3f{5, -30, -8}, Vec3f{6, -30, -8},
                    Vec3f{5, -30, -9}})
        m.positions.push_back(p);
    m.indices = {0, 2, 1, 3, 5, 4, 6, 7, 8};
    s.meshes.push_back(m);
    MeshAreaLight light(s, 0, 0, {0, 1, 2});
    // The triangles face the origin (one-sided emission).
    for (uint32_t t = 0; t < 3; ++t) {
        Vec3f p0, p1, p2;
        s.meshes[0].vertices(t, p0, p1, p2);
        ASSERT_LT(dot(cross(p1 - p0, p2 - p0), p0), 0.f) << "triangle " << t;
    }
    expectLightFits(s, light, Vec3f{0, 0, 0});
}

TEST(LightSampling, LargeMeshLightPicksByAreaAndFitsItsPdf) {
    // 4 x 3 quads = 24 triangles (more than kSolidAnglePickMax) facing the
    // origin from z = 1, plus a far small one sampled by area.
    Scene s = emitterScene(false);
    TriangleMesh m;
    for (int j = 0; j <= 3; ++j)
        for (int i = 0; i <= 4; ++i) m.positions.push_back(Vec3f{-0.8f + 0.5f * i, -0.5f + 0.45f * j, 1.f});
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i) {
            const uint32_t a = uint32_t(j * 5 + i), b = a + 1, c = a + 5, d = a + 6;
            for (uint32_t v : {a, c, b, b, c, d}) m.indices.push_back(v);  // normals -z: towards the origin
        }
    const uint32_t base = uint32_t(m.positions.size());
    for (Vec3f p : {Vec3f{5, -30, -8}, Vec3f{6, -30, -8}, Vec3f{5, -30, -9}}) m.positions.push_back(p);
    for (uint32_t v : {base, base + 1, base + 2}) m.indices.push_back(v);
    s.meshes.push_back(m);
    std::vector<uint32_t> tris(m.triangleCount());
    for (uint32_t t = 0; t < tris.size(); ++t) tris[t] = t;
    ASSERT_GT(tris.size(), MeshAreaLight::kSolidAnglePickMax);
    MeshAreaLight light(s, 0, 0, tris);
    expectLightFits(s, light, Vec3f{0.1f, 0.05f, 0});
    // Without the far triangle and seen from afar, the whole light is sampled by area.
    Scene t = emitterScene(false);
    m.positions.resize(base);
    m.indices.resize(m.indices.size() - 3);
    t.meshes.push_back(m);
    tris.pop_back();
    MeshAreaLight farLight(t, 0, 0, tris);
    expectLightFits(t, farLight, Vec3f{0.3f, 0.2f, -5.f});
}

TEST(LightSampling, FarRectangleSamplesByAreaAndFarSmallMeshLightFitsItsPdf) {
    // The rectangle's and the small mesh light's bounding spheres subtend
    // less than kSolidAngleSamplingMinBound: both sample by area.
    Scene s = emitterScene(false);
    s.rectangles.push_back(Rectangle{Vec3f{3.f, -0.4f, 0.2f}, Vec3f{0, 0, 1.f}, Vec3f{0, 1.f, 0}, 0});
    ShapeAreaLight rect(s, ShapeAreaLight::Kind::Rectangle, 0);
    ASSERT_FALSE(subtendsAtLeast(Vec3f{3.f, 0.1f, 0.7f}, 0.5f, Vec3f{0, 0, 0}, kSolidAngleSamplingMinBound));
    expectLightFits(s, rect, Vec3f{0, 0, 0});
    Scene t = emitterScene(false);
    TriangleMesh m;
    for (Vec3f p : {Vec3f{-3, 1, -0.5f}, Vec3f{-3, 1, 0.5f}, Vec3f{-3, 2, 0.5f}, Vec3f{-3, 2, -0.5f}})
        m.positions.push_back(p);
    m.indices = {0, 2, 1, 0, 3, 2};  // normals +x: towards the origin
    t.meshes.push_back(m);
    MeshAreaLight mesh(t, 0, 0, {0, 1});
    expectLightFits(t, mesh, Vec3f{0, 0, 0});
}

TEST(LightSampling, SubtendsAtLeastAgreesWithTheCapsSolidAngle) {
    // A unit sphere seen from distance d subtends 2 pi (1 - sqrt(1 - 1/d^2)).
    for (float d : {1.01f, 1.2f, 1.5f, 2.f, 3.f, 10.f}) {
        const double cap = 2.0 * 3.14159265358979 * (1.0 - std::sqrt(1.0 - 1.0 / (double(d) * d)));
        for (float omega : {0.1f, 0.5f, 1.f, 3.f, 6.f}) {
            if (std::fabs(cap - omega) < 1e-4 * omega) continue;  // too close to call in float
            EXPECT_EQ(subtendsAtLeast(Vec3f{0, 0, 0}, 1.f, Vec3f{d, 0, 0}, omega), cap >= omega) << d << " " << omega;
        }
    }
    EXPECT_TRUE(subtendsAtLeast(Vec3f{0, 0, 0}, 1.f, Vec3f{0.5f, 0, 0}, 12.f));  // inside: everything
    EXPECT_FALSE(subtendsAtLeast(Vec3f{0, 0, 0}, 1.f, Vec3f{1.001f, 0, 0}, 7.f));  // outside: at most 2 pi
}

TEST(LightSampling, SampleManyGivesWhatSampleGivesPointByPoint) {
    // A near rectangle (its spherical set-up shared by the points) and a far one (by area).
    Scene s = emitterScene(false);
    s.rectangles.push_back(Rectangle{Vec3f{1.f, -0.4f, 0.2f}, Vec3f{0, 0, 1.1f}, Vec3f{0, 1.5f, 0}, 0});
    ShapeAreaLight light(s, ShapeAreaLight::Kind::Rectangle, 0);
    for (const Vec3f p : {Vec3f{0, 0, 0}, Vec3f{-6, 0.1f, 0.3f}, Vec3f{2, 0, 0} /* behind: nothing */}) {
        Vec2f u[7];
        std::optional<LightSample> many[7];
        for (uint32_t k = 0; k < 7; ++k) u[k] = multiJitter2D(k, 7, 5);
        light.sampleMany(p, u, many);
        for (uint32_t k = 0; k < 7; ++k) {
            const auto one = light.sample(p, u[k]);
            ASSERT_EQ(one.has_value(), many[k].has_value());
            if (!one) continue;
            EXPECT_EQ(one->point.x, many[k]->point.x);
            EXPECT_EQ(one->point.y, many[k]->point.y);
            EXPECT_EQ(one->point.z, many[k]->point.z);
            EXPECT_EQ(one->pdf, many[k]->pdf);
            EXPECT_EQ(one->L.r, many[k]->L.r);
        }
    }
}

// A lane's sample is the scalar one, bit for bit.
static void expectSameSample(const LightSample& one, const LightSample& lane) {
    EXPECT_EQ(one.wi, lane.wi);
    EXPECT_EQ(one.point, lane.point);
    EXPECT_EQ(one.distance, lane.distance);
    EXPECT_EQ(one.pdf, lane.pdf);
    EXPECT_EQ(one.L, lane.L);
    EXPECT_EQ(one.delta, lane.delta);
}

// Lane by lane what mayReach and sample give, bit for bit, for points all
// around a light: in front and behind, near (spherical rectangles) and far
// (by area), 16 lanes at a time and a partial batch at the end.
static void expectLanesMatchSample(const Light& light, uint64_t seed) {
    constexpr int W = LanePoints::kWidth;
    constexpr int kPoints = 16 * 12 + 7;
    int sampled = 0;
    for (int b = 0; b < kPoints; b += W) {
        const int n = std::min(W, kPoints - b);
        LanePoints at;
        alignas(64) float ux[W], uy[W];
        for (int l = 0; l < n; ++l) {
            const uint32_t i = uint32_t(b + l);
            const Vec2f a = multiJitter2D(i, kPoints, seed), c = multiJitter2D(i, kPoints, seed + 1);
            const float radius = i % 3 == 0 ? 1.5f : 12.f;  // near and far
            const Vec3f p = radius * Vec3f{2.f * a.x - 1.f, 2.f * a.y - 1.f, 2.f * c.x - 1.f};
            const Vec3f n = normalize(Vec3f{c.y - 0.5f, 0.7f - a.x, a.y - 0.3f});
            at.set(l, p, n);
            const Vec2f u = multiJitter2D(i, kPoints, seed + 2);
            ux[l] = u.x;
            uy[l] = u.y;
        }
        alignas(64) int32_t reach[W];
        light.mayReachLanes(at, n, reach);
        LightLanes out;
        light.sampleLanes(at, ux, uy, reach, n, out);
        for (int l = 0; l < n; ++l) {
            ASSERT_EQ(reach[l] != 0, light.mayReach(at.p(l), at.n(l))) << "lane " << l << " of batch " << b;
            const auto one = reach[l] ? light.sample(at.p(l), Vec2f{ux[l], uy[l]}) : std::nullopt;
            ASSERT_EQ(one.has_value(), out.ok[l] != 0) << "lane " << l << " of batch " << b;
            if (!one) continue;
            ++sampled;
            expectSameSample(*one, out.get(l));
        }
    }
    EXPECT_GT(sampled, kPoints / 5);
}

TEST(LightSampling, SampleLanesGiveWhatSampleGivesLaneByLane) {
    for (const bool twoSided : {false, true}) {
        Scene s = emitterScene(twoSided);
        s.rectangles.push_back(Rectangle{Vec3f{-1.f, 0.5f, -1.f}, Vec3f{2.f, 0, 0}, Vec3f{0, 0.3f, 2.f}, 0});
        // The second one is a parallelogram.
        s.rectangles.push_back(Rectangle{Vec3f{-1.f, 0.5f, -1.f}, Vec3f{2.f, 0, 0.4f}, Vec3f{0.3f, 0, 2.f}, 0});
        s.disks.push_back(Disk{Vec3f{0, 1, 0}, normalize(Vec3f{0.2f, -1, 0.1f}), 0.8f, 0});
        s.spheres.push_back(Sphere{Vec3f{0.5f, 0, 0}, 0.6f, 0});
        SCOPED_TRACE(twoSided ? "two-sided" : "one-sided");
        expectLanesMatchSample(ShapeAreaLight(s, ShapeAreaLight::Kind::Rectangle, 0), 11);
        expectLanesMatchSample(ShapeAreaLight(s, ShapeAreaLight::Kind::Rectangle, 1), 12);
        expectLanesMatchSample(ShapeAreaLight(s, ShapeAreaLight::Kind::Disk, 0), 13);
        expectLanesMatchSample(ShapeAreaLight(s, ShapeAreaLight::Kind::Sphere, 0), 14);
    }
}

TEST(LightSampling, MeshLightSampleLanesGiveWhatSampleGivesLaneByLane) {
    // A quad of two triangles of unequal area, a box of 12 (both picked by
    // triangle in the lanes) and a grid of 40 (more than kSolidAnglePickMax:
    // the default, lane by lane); one- and two-sided.
    for (const bool twoSided : {false, true}) {
        Scene s = emitterScene(twoSided);
        TriangleMesh quad;
        for (const Vec3f v : {Vec3f{-1, 0.5f, -1}, Vec3f{1, 0.5f, -0.8f}, Vec3f{1.2f, 0.6f, 1}, Vec3f{-1, 0.5f, 0.2f}})
            quad.positions.push_back(v);
        quad.indices = {0, 1, 2, 0, 2, 3};
        s.meshes.push_back(quad);
        TriangleMesh box;
        for (int v = 0; v < 8; ++v)
            box.positions.push_back(Vec3f{v & 1 ? 0.9f : -0.4f, v & 2 ? 0.8f : -0.3f, v & 4 ? 0.5f : -1.1f});
        box.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                       2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
        s.meshes.push_back(box);
        TriangleMesh grid;
        constexpr int kCols = 5, kRows = 4;
        for (int r = 0; r <= kRows; ++r)
            for (int c = 0; c <= kCols; ++c)
                grid.positions.push_back(
                    Vec3f{-1.f + 0.4f * float(c), 0.7f + 0.05f * float(r * c), -1.f + 0.5f * float(r)});
        for (uint32_t r = 0; r < kRows; ++r)
            for (uint32_t c = 0; c < kCols; ++c) {
                const uint32_t a = r * (kCols + 1) + c, b = a + 1, d = a + kCols + 1, e = d + 1;
                for (const uint32_t i : {a, d, b, b, d, e}) grid.indices.push_back(i);
            }
        s.meshes.push_back(grid);
        SCOPED_TRACE(twoSided ? "two-sided" : "one-sided");
        for (uint32_t mesh = 0; mesh < 3; ++mesh) {
            std::vector<uint32_t> tris(s.meshes[mesh].triangleCount());
            for (uint32_t t = 0; t < tris.size(); ++t) tris[t] = t;
            SCOPED_TRACE(testing::Message() << tris.size() << " triangles");
            expectLanesMatchSample(MeshAreaLight(s, mesh, 0, tris), 21 + mesh);
        }
    }
}

TEST(LightSampling, SampleManyLanesGiveWhatSampleGivesPointByPoint) {
    // One shading point's samples as lanes: near (spherical rectangle), far (by area), behind
    // (nothing); a parallelogram, a disk and a mesh light (the default, through sampleMany).
    Scene s = emitterScene(false);
    s.rectangles.push_back(Rectangle{Vec3f{1.f, -0.4f, 0.2f}, Vec3f{0, 0, 1.1f}, Vec3f{0, 1.5f, 0}, 0});
    s.rectangles.push_back(Rectangle{Vec3f{1.f, -0.4f, 0.2f}, Vec3f{0, 0.3f, 1.1f}, Vec3f{0, 1.5f, 0}, 0});
    s.disks.push_back(Disk{Vec3f{1, 0, 0}, Vec3f{-1, 0, 0}, 0.8f, 0});
    TriangleMesh mesh;
    for (const Vec3f v : {Vec3f{1, -1, -1}, Vec3f{1, 1, -1}, Vec3f{1, 0, 1}, Vec3f{1.5f, -1, 1}})
        mesh.positions.push_back(v);
    mesh.indices = {0, 1, 2, 0, 2, 3};
    s.meshes.push_back(mesh);
    s.finalize(Logger([](LogLevel, std::string_view) {}));
    const LightSet lights(s);
    ASSERT_EQ(lights.size(), 4u);
    for (size_t j = 0; j < lights.size(); ++j) {
        for (const Vec3f p : {Vec3f{0, 0, 0}, Vec3f{-6, 0.1f, 0.3f}, Vec3f{2, 0, 0}}) {
            float ux[LightLanes::kWidth], uy[LightLanes::kWidth];
            for (int l = 0; l < LightLanes::kWidth; ++l) {
                const Vec2f u = multiJitter2D(uint32_t(l), LightLanes::kWidth, 9);
                ux[l] = u.x;
                uy[l] = u.y;
            }
            for (const int n : {LightLanes::kWidth, 5}) {
                LightLanes out;
                lights[j].sampleManyLanes(p, ux, uy, n, out);
                for (int l = 0; l < n; ++l) {
                    const auto one = lights[j].sample(p, Vec2f{ux[l], uy[l]});
                    ASSERT_EQ(one.has_value(), out.ok[l] != 0) << "light " << j << " lane " << l;
                    if (!one) continue;
                    expectSameSample(*one, out.get(l));
                }
            }
        }
    }
}

TEST(LightSampling, SampleLanesLeaveLanesNotAskedForEmpty) {
    Scene s = emitterScene(false);
    s.rectangles.push_back(Rectangle{Vec3f{-1.f, 2.f, -1.f}, Vec3f{2.f, 0, 0}, Vec3f{0, 0, 2.f}, 0});  // faces down
    const ShapeAreaLight light(s, ShapeAreaLight::Kind::Rectangle, 0);
    LanePoints at;
    alignas(64) float ux[3] = {0.2f, 0.5f, 0.9f}, uy[3] = {0.3f, 0.5f, 0.1f};
    for (int l = 0; l < 3; ++l) at.set(l, Vec3f{0.1f * float(l), 0, 0}, Vec3f{0, 1, 0});
    const int32_t want[3] = {1, 0, 1};
    LightLanes out;
    light.sampleLanes(at, ux, uy, want, 3, out);
    EXPECT_EQ(out.ok[0], 1);
    EXPECT_EQ(out.ok[1], 0);
    EXPECT_EQ(out.ok[2], 1);
    EXPECT_EQ(out.get(0).wi, light.sample(at.p(0), Vec2f{0.2f, 0.3f})->wi);
}

TEST(LightSampling, AreaSamplingStillFitsItsPdf) {
    // sampleArea (the uniform-area baseline) against the area pdf converted to solid angle.
    Scene s = emitterScene(false);
    s.rectangles.push_back(Rectangle{Vec3f{1.f, -0.4f, 0.2f}, Vec3f{0, 0, 1.1f}, Vec3f{0, 1.5f, 0}, 0});
    ShapeAreaLight light(s, ShapeAreaLight::Kind::Rectangle, 0);
    const Vec3f p{0, 0, 0};
    const auto r = chiSquareDirections(
        [&](uint32_t i) -> std::optional<Vec3f> {
            auto ls = light.sampleArea(p, multiJitter2D(i, 200000, 5));
            return ls ? std::optional<Vec3f>(ls->wi) : std::nullopt;
        },
        [&](const Vec3f& w) -> double {
            const auto h = firstHit(s, Ray{p, w});
            return h ? areaPdfToSolidAngle(p, h->p, h->ng, 1.f / light.area(), false) : 0.0;
        });
    EXPECT_TRUE(r.passed) << r.message;
}

TEST(LightSampling, SolidAnglesHaveTheirClosedForms) {
    // A square [-h, h]^2 at distance d: 4 asin(h^2 / (h^2 + d^2)).
    const float h = 0.5f, d = 1.f;
    const SphericalRectangle sr(Vec3f{0, 0, 0}, Vec3f{-h, -h, d}, Vec3f{2 * h, 0, 0}, Vec3f{0, 2 * h, 0});
    EXPECT_NEAR(sr.solidAngle(), 4.0 * std::asin(h * h / (h * h + d * d)), 1e-6);
    // Its two halves as triangles.
    const float half = triangleSolidAngle(Vec3f{0, 0, 0}, Vec3f{-h, -h, d}, Vec3f{h, -h, d}, Vec3f{h, h, d});
    EXPECT_NEAR(2.0 * half, sr.solidAngle(), 1e-6);
    // An octant triangle subtends pi/2 from the origin.
    EXPECT_NEAR(triangleSolidAngle(Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 1, 0}, Vec3f{0, 0, 1}), kPi / 2, 1e-6);
    // Sphere cap: 2 pi (1 - sqrt(1 - (r/d)^2)).
    EXPECT_NEAR(1.0 / sphereConePdf(Vec3f{0, 0, 0}, Vec3f{0, 0, 3}, 1.f), 2 * M_PI * (1 - std::sqrt(8.0 / 9.0)), 1e-6);
    EXPECT_EQ(sphereConePdf(Vec3f{0, 0, 0}, Vec3f{0, 0, 0.5f}, 1.f), 0.f);  // inside
    // A tiny, far sphere keeps its precision (no 1 - cos cancellation).
    const double capSmall = 1.0 / sphereConePdf(Vec3f{0, 0, 0}, Vec3f{0, 0, 1000}, 0.01f);
    EXPECT_NEAR(capSmall / (M_PI * 1e-10), 1.0, 1e-4);
    // Samples land on the shapes.
    for (uint32_t k = 0; k < 64; ++k) {
        const Vec3f q = sr.sample(multiJitter2D(k, 64, 1));
        EXPECT_NEAR(q.z, d, 1e-5f);
        EXPECT_LE(std::fabs(q.x), h + 1e-5f);
        EXPECT_LE(std::fabs(q.y), h + 1e-5f);
    }
}

TEST(LightSet, FindsTheLightOfAnEmitterHit) {
    Scene s;
    Material plain, a, b;
    a.ke = Rgb(1.f);
    b.ke = Rgb(3.f);
    s.materials = {plain, a, b};
    s.rectangles.push_back(Rectangle{Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 0, 1}, 0});  // not a light
    s.rectangles.push_back(Rectangle{Vec3f{0, 1, 0}, Vec3f{1, 0, 0}, Vec3f{0, 0, 1}, 1});
    s.spheres.push_back(Sphere{Vec3f{5, 0, 0}, 1.f, 2});
    s.disks.push_back(Disk{Vec3f{0, 4, 0}, Vec3f{0, -1, 0}, 1.f, 1});
    TriangleMesh m;
    for (Vec3f p : {Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 1, 0}, Vec3f{0, 0, 1}}) m.positions.push_back(p);
    m.indices = {0, 1, 2, 0, 2, 3, 0, 3, 1};
    m.faceMaterials = {2, 0, 1};
    s.meshes.push_back(m);
    LightSet lights(s);
    ASSERT_EQ(lights.size(), 5u);  // rectangle 1, disk, sphere, two mesh groups
    const auto lightOf = [&](ShapeKind kind, uint32_t object, uint32_t prim, uint32_t material) {
        Hit h;
        h.ref = PrimRef{kind, object, prim};
        h.material = material;
        return lights.lightOf(h);
    };
    EXPECT_FALSE(lightOf(ShapeKind::Rectangle, 0, 0, 0).has_value());
    EXPECT_EQ(lightOf(ShapeKind::Rectangle, 1, 0, 1), std::optional<size_t>(0));
    EXPECT_EQ(lightOf(ShapeKind::Disk, 0, 0, 1), std::optional<size_t>(1));
    EXPECT_EQ(lightOf(ShapeKind::Sphere, 0, 0, 2), std::optional<size_t>(2));
    const auto m1 = lightOf(ShapeKind::Mesh, 0, 2, 1), m2 = lightOf(ShapeKind::Mesh, 0, 0, 2);
    ASSERT_TRUE(m1 && m2);
    EXPECT_NE(*m1, *m2);
    EXPECT_FALSE(lightOf(ShapeKind::Mesh, 0, 1, 0).has_value());
    EXPECT_FALSE(lightOf(ShapeKind::Plane, 0, 0, 1).has_value());
    // The power probabilities sum to 1 and match its picks.
    double sum = 0;
    for (size_t i = 0; i < lights.size(); ++i) sum += lights.powerPicker().probability(i, Vec3f{}, Vec3f{});
    EXPECT_NEAR(sum, 1.0, 1e-6);
    const PowerLightPicker& power = lights.powerPicker();
    EXPECT_FLOAT_EQ(power.pick(0.f, Vec3f{}, Vec3f{}).probability, power.probability(0, Vec3f{}, Vec3f{}));
}
