// Analytic shape and triangle tests: known hit distances, normals (through
// Scene::completeHit, the one place normals are computed) and surface
// coordinates; misses, grazing rays, the (tnear, tfar] interval, degenerate
// inputs, and uniform area sampling.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <utility>

#include "core/scene.h"
#include "core/shapes.h"
#include "core/transform.h"

namespace penumbra {
namespace {

constexpr float kEps = 1e-5f;

// A scene whose material 0 has a texture: Scene::completeHit computes the uv
// of a sphere, plane or box hit only for such a material.
Scene texturedScene() {
    Scene scene;
    scene.materials.resize(1);
    scene.materials[0].textureIndex = 0;
    return scene;
}

void expectVecNear(const Vec3f& a, const Vec3f& b, float eps = kEps) {
    EXPECT_NEAR(a.x, b.x, eps);
    EXPECT_NEAR(a.y, b.y, eps);
    EXPECT_NEAR(a.z, b.z, eps);
}

Ray makeRay(Vec3f o, Vec3f d, float tnear = 0.f, float tfar = kInfinity) { return Ray{o, d, tnear, tfar}; }

// A miss must not smuggle NaN into anything; a hit must be finite.
void expectFiniteOrMiss(const std::optional<PrimHit>& h) {
    if (!h) return;
    EXPECT_TRUE(std::isfinite(h->t));
    EXPECT_TRUE(std::isfinite(h->u));
    EXPECT_TRUE(std::isfinite(h->v));
}

// ---------------------------------------------------------------- sphere

TEST(SphereTest, HitFromOutsideGivesNearSideWithOutwardNormal) {
    Scene scene = texturedScene();
    scene.spheres.push_back(Sphere{{0.f, 0.f, 0.f}, 1.f, 0});
    Ray r = makeRay({0.f, 0.f, -5.f}, {0.f, 0.f, 1.f});
    auto h = intersect(scene.spheres[0], r);
    ASSERT_TRUE(h);
    EXPECT_FLOAT_EQ(h->t, 4.f);
    Hit hit = scene.completeHit(r, PrimRef{ShapeKind::Sphere, 0, 0}, h->t, h->u, h->v);
    expectVecNear(hit.p, {0.f, 0.f, -1.f});
    expectVecNear(hit.ng, {0.f, 0.f, -1.f});
    expectVecNear(hit.ns, {0.f, 0.f, -1.f});
    // u = atan2(z, x) / 2pi + 1/2 = 1/4, v = acos(y) / pi = 1/2.
    EXPECT_NEAR(hit.uv.x, 0.25f, kEps);
    EXPECT_NEAR(hit.uv.y, 0.5f, kEps);
}

TEST(SphereTest, HitFromInsideGivesFarSideAndNormalStaysOutward) {
    Scene scene = texturedScene();
    scene.spheres.push_back(Sphere{{1.f, 2.f, 3.f}, 2.f, 0});
    Ray r = makeRay({1.f, 2.f, 3.f}, {0.f, 1.f, 0.f});
    auto h = intersect(scene.spheres[0], r);
    ASSERT_TRUE(h);
    EXPECT_FLOAT_EQ(h->t, 2.f);
    Hit hit = scene.completeHit(r, PrimRef{ShapeKind::Sphere, 0, 0}, h->t, h->u, h->v);
    expectVecNear(hit.p, {1.f, 4.f, 3.f});
    expectVecNear(hit.ng, {0.f, 1.f, 0.f});  // front side, not flipped towards the ray
    EXPECT_NEAR(hit.uv.y, 0.f, kEps);        // the north pole
}

TEST(SphereTest, NonUnitDirectionScalesT) {
    Sphere s{{0.f, 0.f, 0.f}, 1.f, 0};
    auto h = intersect(s, makeRay({0.f, 0.f, -5.f}, {0.f, 0.f, 2.f}));
    ASSERT_TRUE(h);
    EXPECT_FLOAT_EQ(h->t, 2.f);
}

TEST(SphereTest, MissesAndGrazing) {
    Sphere s{{0.f, 0.f, 0.f}, 1.f, 0};
    EXPECT_FALSE(intersect(s, makeRay({0.f, 2.f, -5.f}, {0.f, 0.f, 1.f})));
    EXPECT_FALSE(intersect(s, makeRay({0.f, 0.f, -5.f}, {0.f, 0.f, -1.f})));  // sphere behind the ray
    EXPECT_FALSE(intersect(s, makeRay({0.f, 1.0001f, -5.f}, {0.f, 0.f, 1.f})));
    // Exactly tangent: one touching point at t = 5, normal along +y.
    Scene scene;
    scene.spheres.push_back(s);
    Ray r = makeRay({0.f, 1.f, -5.f}, {0.f, 0.f, 1.f});
    auto h = intersect(s, r);
    ASSERT_TRUE(h);
    EXPECT_NEAR(h->t, 5.f, 1e-4f);
    Hit hit = scene.completeHit(r, PrimRef{ShapeKind::Sphere, 0, 0}, h->t, h->u, h->v);
    expectVecNear(hit.ng, {0.f, 1.f, 0.f}, 1e-3f);
}

TEST(SphereTest, IntervalLimits) {
    Sphere s{{0.f, 0.f, 0.f}, 1.f, 0};
    const Vec3f o{0.f, 0.f, -5.f}, d{0.f, 0.f, 1.f};
    // Hits at t = 4 and t = 6. tfar is inclusive, tnear exclusive.
    auto atTfar = intersect(s, makeRay(o, d, 0.f, 4.f));
    ASSERT_TRUE(atTfar);
    EXPECT_FLOAT_EQ(atTfar->t, 4.f);
    EXPECT_FALSE(intersect(s, makeRay(o, d, 0.f, std::nextafter(4.f, 0.f))));
    EXPECT_FALSE(intersect(s, makeRay(o, d, 0.f, 3.f)));
    auto pastNear = intersect(s, makeRay(o, d, 4.f, kInfinity));
    ASSERT_TRUE(pastNear);
    EXPECT_FLOAT_EQ(pastNear->t, 6.f);
    auto between = intersect(s, makeRay(o, d, 4.5f, 10.f));
    ASSERT_TRUE(between);
    EXPECT_FLOAT_EQ(between->t, 6.f);
    EXPECT_FALSE(intersect(s, makeRay(o, d, 6.f, 10.f)));
    EXPECT_FALSE(intersect(s, makeRay(o, d, 4.5f, 5.5f)));
}

TEST(SphereTest, ZeroRadiusNeverHits) {
    Sphere s{{0.f, 0.f, 0.f}, 0.f, 0};
    auto h = intersect(s, makeRay({0.f, 0.f, -5.f}, {0.f, 0.f, 1.f}));
    EXPECT_FALSE(h);
    expectFiniteOrMiss(h);
    EXPECT_FALSE(intersect(Sphere{{0.f, 0.f, 0.f}, -1.f, 0}, makeRay({0.f, 0.f, -5.f}, {0.f, 0.f, 1.f})));
}

TEST(SphereTest, SmallFarSphereIsAccurate) {
    // The geometric discriminant keeps a small sphere far away accurate.
    Sphere s{{0.f, 0.f, 1e4f}, 0.01f, 0};
    auto h = intersect(s, makeRay({0.f, 0.f, 0.f}, {0.f, 0.f, 1.f}));
    ASSERT_TRUE(h);
    EXPECT_NEAR(h->t, 1e4f - 0.01f, 2e-3f);
}

// ---------------------------------------------------------------- plane

TEST(PlaneTest, HitFromFrontAndBackWhenTwoSided) {
    Scene scene = texturedScene();
    scene.planes.push_back(Plane{{0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, true, 0});
    Ray down = makeRay({1.f, 2.f, 3.f}, {0.f, -1.f, 0.f});
    auto h = intersect(scene.planes[0], down);
    ASSERT_TRUE(h);
    EXPECT_FLOAT_EQ(h->t, 2.f);
    Hit hit = scene.completeHit(down, PrimRef{ShapeKind::Plane, 0, 0}, h->t, h->u, h->v);
    expectVecNear(hit.p, {1.f, 0.f, 3.f});
    expectVecNear(hit.ng, {0.f, 1.f, 0.f});
    // Frame::fromNormal(+y) has s = +x and t = -z.
    EXPECT_NEAR(hit.uv.x, 1.f, kEps);
    EXPECT_NEAR(hit.uv.y, -3.f, kEps);

    Ray up = makeRay({0.f, -2.f, 0.f}, {0.f, 1.f, 0.f});
    auto back = intersect(scene.planes[0], up);
    ASSERT_TRUE(back);
    EXPECT_FLOAT_EQ(back->t, 2.f);
    Hit backHit = scene.completeHit(up, PrimRef{ShapeKind::Plane, 0, 0}, back->t, back->u, back->v);
    expectVecNear(backHit.ng, {0.f, 1.f, 0.f});  // the front normal, not flipped
}

TEST(PlaneTest, OneSidedIsInvisibleFromBehind) {
    Plane p{{0.f, 1.f, 0.f}, {0.f, 1.f, 0.f}, false, 0};
    EXPECT_FALSE(intersect(p, makeRay({0.f, -2.f, 0.f}, {0.f, 1.f, 0.f})));
    auto front = intersect(p, makeRay({0.f, 4.f, 0.f}, {0.f, -1.f, 0.f}));
    ASSERT_TRUE(front);
    EXPECT_FLOAT_EQ(front->t, 3.f);
}

TEST(PlaneTest, ParallelAndAwayRaysMiss) {
    Plane p{{0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, true, 0};
    EXPECT_FALSE(intersect(p, makeRay({0.f, 1.f, 0.f}, {1.f, 0.f, 0.f})));
    auto inPlane = intersect(p, makeRay({0.f, 0.f, 0.f}, {1.f, 0.f, 0.f}));  // grazing: inside the plane
    EXPECT_FALSE(inPlane);
    expectFiniteOrMiss(inPlane);
    EXPECT_FALSE(intersect(p, makeRay({0.f, 1.f, 0.f}, {0.f, 1.f, 0.f})));
}

TEST(PlaneTest, IntervalLimits) {
    Plane p{{0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, true, 0};
    const Vec3f o{0.f, 2.f, 0.f}, d{0.f, -1.f, 0.f};
    EXPECT_TRUE(intersect(p, makeRay(o, d, 0.f, 2.f)));
    EXPECT_FALSE(intersect(p, makeRay(o, d, 0.f, std::nextafter(2.f, 0.f))));
    EXPECT_FALSE(intersect(p, makeRay(o, d, 2.f, 10.f)));
}

// ---------------------------------------------------------------- box

TEST(BoxTest, AxisAlignedHitsFromOutsideAndInside) {
    Scene scene = texturedScene();
    scene.boxes.push_back(makeBox({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f}));
    Ray r = makeRay({0.5f, -0.5f, -5.f}, {0.f, 0.f, 1.f});
    auto h = intersect(scene.boxes[0], r);
    ASSERT_TRUE(h);
    EXPECT_FLOAT_EQ(h->t, 4.f);
    Hit hit = scene.completeHit(r, PrimRef{ShapeKind::Box, 0, 0}, h->t, h->u, h->v);
    expectVecNear(hit.p, {0.5f, -0.5f, -1.f});
    expectVecNear(hit.ng, {0.f, 0.f, -1.f});
    // Face -z: uv along x and y, relative to the box size.
    EXPECT_NEAR(hit.uv.x, 0.75f, kEps);
    EXPECT_NEAR(hit.uv.y, 0.25f, kEps);

    Ray inside = makeRay({0.f, 0.f, 0.f}, {0.f, 0.f, 1.f});
    auto hi = intersect(scene.boxes[0], inside);
    ASSERT_TRUE(hi);
    EXPECT_FLOAT_EQ(hi->t, 1.f);
    Hit hitIn = scene.completeHit(inside, PrimRef{ShapeKind::Box, 0, 0}, hi->t, hi->u, hi->v);
    expectVecNear(hitIn.ng, {0.f, 0.f, 1.f});

    Ray side = makeRay({-4.f, 0.25f, 0.1f}, {1.f, 0.f, 0.f});
    auto hs = intersect(scene.boxes[0], side);
    ASSERT_TRUE(hs);
    EXPECT_FLOAT_EQ(hs->t, 3.f);
    expectVecNear(scene.completeHit(side, PrimRef{ShapeKind::Box, 0, 0}, hs->t, 0.f, 0.f).ng, {-1.f, 0.f, 0.f});
}

TEST(BoxTest, MissesGrazingAndLimits) {
    Box b = makeBox({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f});
    EXPECT_FALSE(intersect(b, makeRay({0.f, 2.f, -5.f}, {0.f, 0.f, 1.f})));
    EXPECT_FALSE(intersect(b, makeRay({0.f, 0.f, -5.f}, {0.f, 0.f, -1.f})));
    EXPECT_FALSE(intersect(b, makeRay({-5.f, 0.f, -5.f}, {1.f, 0.f, 0.1f})));
    // A ray sliding along the top face touches the closed slab.
    auto graze = intersect(b, makeRay({-5.f, 1.f, 0.f}, {1.f, 0.f, 0.f}));
    ASSERT_TRUE(graze);
    EXPECT_FLOAT_EQ(graze->t, 4.f);
    EXPECT_FALSE(intersect(b, makeRay({-5.f, 1.001f, 0.f}, {1.f, 0.f, 0.f})));
    // Hits at 4 and 6.
    const Vec3f o{0.f, 0.f, -5.f}, d{0.f, 0.f, 1.f};
    EXPECT_TRUE(intersect(b, makeRay(o, d, 0.f, 4.f)));
    EXPECT_FALSE(intersect(b, makeRay(o, d, 0.f, std::nextafter(4.f, 0.f))));
    auto far = intersect(b, makeRay(o, d, 4.f, 100.f));
    ASSERT_TRUE(far);
    EXPECT_FLOAT_EQ(far->t, 6.f);
}

TEST(BoxTest, OrientedBoxViaRotation) {
    Scene scene;
    const Transform rot = Transform::rotate(30.f, {0.f, 1.f, 0.f});
    scene.boxes.push_back(makeBox({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f}, Transform::translate({2.f, 0.f, 0.f}) * rot));
    // Along +x the ray meets the face whose normal is the rotated -x axis; its
    // plane lies 1 unit from the centre, so t = (5 + 2) - 1 / cos 30.
    Ray r = makeRay({-5.f, 0.f, 0.f}, {1.f, 0.f, 0.f});
    auto h = intersect(scene.boxes[0], r);
    ASSERT_TRUE(h);
    EXPECT_NEAR(h->t, 7.f - 1.f / std::cos(30.f * kPi / 180.f), 1e-5f);
    Hit hit = scene.completeHit(r, PrimRef{ShapeKind::Box, 0, 0}, h->t, h->u, h->v);
    expectVecNear(hit.ng, normalize(rot.applyVector({-1.f, 0.f, 0.f})));
    EXPECT_NEAR(std::fabs(hit.ng.x), std::cos(30.f * kPi / 180.f), 1e-5f);
    expectVecNear(hit.p, r.o + h->t * r.d, 1e-5f);
    // The world-space corner region the axis-aligned box would cover is empty now.
    EXPECT_FALSE(intersect(scene.boxes[0], makeRay({2.95f, 5.f, 0.95f}, {0.f, -1.f, 0.f}, 0.f, kInfinity)));
}

TEST(BoxTest, SingularTransformNeverHits) {
    Box b = makeBox({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f}, Transform::scale({1.f, 0.f, 1.f}));
    for (Vec3f d : {Vec3f{0.f, -1.f, 0.f}, Vec3f{0.f, 0.f, 1.f}, Vec3f{0.3f, -0.5f, 0.8f}}) {
        auto h = intersect(b, makeRay(Vec3f{0.f, 0.f, 0.f} - 5.f * d, d));
        EXPECT_FALSE(h);
        expectFiniteOrMiss(h);
    }
    EXPECT_TRUE(bounds(b).empty());
}

// The slab test as it was written with branches (a reference for the
// branch-free boxHitDistance the packet loops run): the same t, bit for bit.
std::optional<float> branchySlabTest(const Box& b, const Ray& r) {
    const Vec3f o = b.objectFromWorld.applyPoint(r.o), d = b.objectFromWorld.applyVector(r.d);
    float enter = -kInfinity, exit = kInfinity;
    for (int i = 0; i < 3; ++i) {
        if (b.lo[i] > b.hi[i]) return std::nullopt;
        if (d[i] == 0.f) {
            if (o[i] < b.lo[i] || o[i] > b.hi[i]) return std::nullopt;
            continue;
        }
        const float inv = 1.f / d[i];
        float tn = (b.lo[i] - o[i]) * inv, tf = (b.hi[i] - o[i]) * inv;
        if (tn > tf) std::swap(tn, tf);
        enter = std::max(enter, tn);
        exit = std::min(exit, tf);
    }
    if (enter > exit) return std::nullopt;
    if (enter > r.tnear && enter <= r.tfar) return enter;
    if (exit > r.tnear && exit <= r.tfar) return exit;
    return std::nullopt;
}

TEST(BoxTest, RaysParallelToAFaceHitFromWithinItsSlabOnly) {
    const Box b = makeBox({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f});
    for (const float zero : {0.f, -0.f}) {
        // Within the y slab (its bounds included) the ray meets the x faces; outside it, nothing.
        for (const float y : {-1.f, -0.5f, 0.f, 1.f}) {
            const auto h = intersect(b, makeRay({-5.f, y, 0.f}, {1.f, zero, zero}));
            ASSERT_TRUE(h) << y;
            EXPECT_EQ(h->t, 4.f);
        }
        for (const float y : {std::nextafter(1.f, 2.f), -1.5f, 7.f})
            EXPECT_FALSE(intersect(b, makeRay({-5.f, y, 0.f}, {1.f, zero, zero}))) << y;
        // From inside, along an axis: the far face.
        const auto inside = intersect(b, makeRay({0.25f, 0.f, 0.f}, {zero, zero, -1.f}));
        ASSERT_TRUE(inside);
        EXPECT_EQ(inside->t, 1.f);
    }
}

TEST(BoxTest, BranchFreeTestGivesTheBranchyTestsAnswersBitForBit) {
    const Box boxes[] = {makeBox({-1.f, -2.f, -0.5f}, {2.f, 1.f, 0.5f}),
                         makeBox({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f},
                                 Transform::translate({0.5f, 0.f, -1.f}) * Transform::rotate(35.f, normalize(Vec3f{1.f, 2.f, 3.f}))),
                         makeBox({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f}, Transform::scale({1.f, 0.f, 1.f}))};
    uint32_t state = 12345u;
    const auto uniform = [&] {
        state = state * 1664525u + 1013904223u;
        return float(state >> 8) * 0x1p-24f;
    };
    int hits = 0, compared = 0;
    for (const Box& b : boxes)
        for (int k = 0; k < 20000; ++k) {
            Vec3f o{8.f * uniform() - 4.f, 8.f * uniform() - 4.f, 8.f * uniform() - 4.f};
            Vec3f d{2.f * uniform() - 1.f, 2.f * uniform() - 1.f, 2.f * uniform() - 1.f};
            // Every fourth ray runs along an axis plane or an axis, some from a slab's very bound.
            if (k % 4 == 1) d.y = 0.f;
            if (k % 4 == 2) d = Vec3f{0.f, 0.f, d.z < 0.f ? -1.f : 1.f};
            if (k % 8 == 3) o.x = b.lo.x;
            const float tnear = k % 3 == 0 ? 0.f : uniform(), tfar = k % 5 == 0 ? 2.f + uniform() : kInfinity;
            const Ray r = makeRay(o, d, tnear, tfar);
            const std::optional<float> want = branchySlabTest(b, r);
            const std::optional<PrimHit> got = intersect(b, r);
            ASSERT_EQ(got.has_value(), want.has_value()) << "box " << &b - boxes << " ray " << k;
            if (want) {
                EXPECT_EQ(got->t, *want) << "box " << &b - boxes << " ray " << k;
            }
            hits += want ? 1 : 0;
            ++compared;
        }
    EXPECT_GT(hits, compared / 40);  // about 4%: random rays through a cube of side 8
}

// ------------------------------------------------- triangle hits over lanes

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// completeTriangleHitLanes gives each lane what completeTriangleHit gives it,
// bit for bit: with and without vertex normals and uvs, for 1 to 16 lanes, on
// triangles whose vertex normals cancel and on degenerate ones.
TEST(HitCompletionTest, TriangleHitsOverTheLanesEqualTheScalarOnes) {
    uint32_t state = 777u;
    const auto uniform = [&] {
        state = state * 1664525u + 1013904223u;
        return float(state >> 8) * 0x1p-24f;
    };
    const auto point = [&] { return Vec3f{8.f * uniform() - 4.f, 8.f * uniform() - 4.f, 8.f * uniform() - 4.f}; };
    for (int variant = 0; variant < 4; ++variant) {
        const bool normals = variant & 1, uvs = variant & 2;
        TriangleMesh m;
        m.material = 3;
        for (int i = 0; i < 60; ++i) {
            m.positions.push_back(point());
            if (normals) m.normals.push_back(normalize(point()));
            if (uvs) m.uvs.push_back(Vec2f{uniform(), uniform()});
        }
        for (uint32_t t = 0; t < 40; ++t)
            for (uint32_t k = 0; k < 3; ++k) m.indices.push_back((t * 7 + k * 13) % 60);
        // Triangle 40: its corners' normals cancel at the centre; 41: all three corners on one line.
        m.positions.push_back({0.f, 0.f, 0.f});
        m.positions.push_back({1.f, 0.f, 0.f});
        m.positions.push_back({0.f, 1.f, 0.f});
        m.positions.push_back({2.f, 2.f, 2.f});
        if (normals) {
            m.normals.push_back({0.f, 0.f, 1.f});
            m.normals.push_back({0.f, 0.f, 1.f});
            m.normals.push_back({0.f, 0.f, -1.f});  // half of 61's and half of this one: zero
            m.normals.push_back({0.f, 1.f, 0.f});
        }
        if (uvs) m.uvs.insert(m.uvs.end(), 4, Vec2f{0.5f, 0.5f});
        m.indices.insert(m.indices.end(), {60, 61, 62, 60, 61, 63});
        m.positions[63] = {3.f, 0.f, 0.f};  // on the line through 60 and 61
        m.faceMaterials.assign(42, 0);
        for (uint32_t t = 0; t < 42; ++t) m.faceMaterials[t] = t % 5;
        for (int n = 1; n <= 16; ++n) {
            uint32_t tri[16];
            float u[16], v[16];
            Hit lanes[16];
            Hit* out[16];
            for (int l = 0; l < n; ++l) {
                tri[l] = l % 7 == 3 ? 40 : l % 7 == 5 ? 41 : uint32_t(uniform() * 40.f) % 40;
                u[l] = tri[l] == 40 ? 0.5f : uniform();
                v[l] = tri[l] == 40 ? 0.5f : (1.f - u[l]) * uniform();
                out[l] = &lanes[l];
            }
            completeTriangleHitLanes(m, n, tri, u, v, out);
            for (int l = 0; l < n; ++l) {
                Hit want;
                completeTriangleHit(m, tri[l], u[l], v[l], want);
                const Hit& got = lanes[l];
                const float a[] = {got.p.x, got.p.y, got.p.z, got.ng.x, got.ng.y, got.ng.z, got.ns.x, got.ns.y,
                                   got.ns.z, got.uv.x, got.uv.y};
                const float b[] = {want.p.x, want.p.y, want.p.z, want.ng.x, want.ng.y, want.ng.z, want.ns.x, want.ns.y,
                                   want.ns.z, want.uv.x, want.uv.y};
                for (int f = 0; f < 11; ++f) {
                    ASSERT_TRUE(sameBits(a[f], b[f]))
                        << "variant " << variant << ", " << n << " lanes, lane " << l << ", field " << f << ": " << a[f]
                        << " against " << b[f];
                }
                EXPECT_EQ(got.material, want.material);
            }
        }
        // The cancelling normals leave the geometric one; the degenerate triangle's normal is zero.
        Hit h;
        completeTriangleHit(m, 40, 0.5f, 0.5f, h);
        EXPECT_EQ(h.ns, h.ng);
        EXPECT_EQ(h.ng, (Vec3f{0.f, 0.f, 1.f}));
        completeTriangleHit(m, 41, 0.25f, 0.25f, h);
        EXPECT_EQ(h.ng, Vec3f{});
    }
}

// ------------------------------------------------- uv only where textured

// A sphere's, a plane's or a box's hit takes its uv only where its material
// has a texture (the only reader); every other field is the same bit for bit.
TEST(HitCompletionTest, UvOnlyForTexturedMaterialsAndNothingElseChanges) {
    Scene plain;
    plain.materials.resize(1);  // no texture
    Scene textured = texturedScene();
    for (Scene* s : {&plain, &textured}) {
        s->spheres.push_back(Sphere{{0.3f, -0.2f, 0.1f}, 1.5f, 0});
        s->planes.push_back(Plane{{0.f, -1.f, 0.f}, normalize(Vec3f{0.2f, 1.f, -0.1f}), true, 0});
        s->boxes.push_back(makeBox({-1.f, -2.f, -0.5f}, {2.f, 1.f, 0.5f}));
        s->boxes.push_back(makeBox({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f}, Transform::rotate(40.f, Vec3f{0.f, 1.f, 0.f})));
    }
    const PrimRef refs[] = {{ShapeKind::Sphere, 0, 0}, {ShapeKind::Plane, 0, 0}, {ShapeKind::Box, 0, 0},
                            {ShapeKind::Box, 1, 0}};
    int hits = 0, nonZeroUv = 0;
    for (const PrimRef& ref : refs) {
        for (int k = 0; k < 16; ++k) {
            const float a = 0.39f * float(k);
            const Ray r = makeRay({6.f * std::cos(a), 3.f - 0.3f * float(k), 6.f * std::sin(a)},
                                  normalize(Vec3f{-std::cos(a), -0.4f, -std::sin(a)}));
            std::optional<PrimHit> h;
            switch (ref.kind) {
                case ShapeKind::Sphere: h = intersect(plain.spheres[0], r); break;
                case ShapeKind::Plane: h = intersect(plain.planes[0], r); break;
                default: h = intersect(plain.boxes[ref.object], r); break;
            }
            if (!h) continue;
            ++hits;
            const Hit p = plain.completeHit(r, ref, h->t, h->u, h->v);
            const Hit t = textured.completeHit(r, ref, h->t, h->u, h->v);
            EXPECT_EQ(p.t, t.t);
            EXPECT_EQ(p.p, t.p);
            EXPECT_EQ(p.ng, t.ng);
            EXPECT_EQ(p.ns, t.ns);
            EXPECT_EQ(p.material, t.material);
            EXPECT_EQ(p.ref, t.ref);
            EXPECT_EQ(p.uv.x, 0.f);
            EXPECT_EQ(p.uv.y, 0.f);
            // The textured scene's uv is the shape's own, as the free function computes it.
            Hit own;
            switch (ref.kind) {
                case ShapeKind::Sphere: completeHit(plain.spheres[0], r, h->t, own); break;
                case ShapeKind::Plane: completeHit(plain.planes[0], r, h->t, own); break;
                default: completeHit(plain.boxes[ref.object], r, h->t, own); break;
            }
            EXPECT_EQ(t.uv.x, own.uv.x);
            EXPECT_EQ(t.uv.y, own.uv.y);
            nonZeroUv += (t.uv.x != 0.f || t.uv.y != 0.f) ? 1 : 0;
        }
    }
    EXPECT_GT(hits, 30);
    EXPECT_GT(nonZeroUv, 30);  // the comparison above compares real coordinates
}

// ---------------------------------------------------------------- rectangle

TEST(RectangleTest, HitGivesParametersAndFrontNormal) {
    Scene scene;
    // cross(a, b) = cross(2x, 2z) = -4y: the front faces down.
    scene.rectangles.push_back(Rectangle{{-1.f, 0.f, -1.f}, {2.f, 0.f, 0.f}, {0.f, 0.f, 2.f}, 0});
    Ray r = makeRay({0.5f, 3.f, -0.5f}, {0.f, -1.f, 0.f});
    auto h = intersect(scene.rectangles[0], r);
    ASSERT_TRUE(h);
    EXPECT_FLOAT_EQ(h->t, 3.f);
    EXPECT_NEAR(h->u, 0.75f, kEps);
    EXPECT_NEAR(h->v, 0.25f, kEps);
    Hit hit = scene.completeHit(r, PrimRef{ShapeKind::Rectangle, 0, 0}, h->t, h->u, h->v);
    expectVecNear(hit.p, {0.5f, 0.f, -0.5f});
    expectVecNear(hit.ng, {0.f, -1.f, 0.f});
    EXPECT_NEAR(hit.uv.x, 0.75f, kEps);
    EXPECT_NEAR(hit.uv.y, 0.25f, kEps);
    // Two-sided: also hit from below.
    EXPECT_TRUE(intersect(scene.rectangles[0], makeRay({0.f, -1.f, 0.f}, {0.f, 1.f, 0.f})));
}

TEST(RectangleTest, ParallelogramCoordinates) {
    // a and b not perpendicular: (u, v) are coordinates in the (a, b) basis.
    Rectangle q{{0.f, 0.f, 0.f}, {2.f, 0.f, 0.f}, {1.f, 1.f, 0.f}, 0};
    Vec3f target = q.p0 + 0.25f * q.a + 0.5f * q.b;
    auto h = intersect(q, makeRay(target + Vec3f{0.f, 0.f, 2.f}, {0.f, 0.f, -1.f}));
    ASSERT_TRUE(h);
    EXPECT_FLOAT_EQ(h->t, 2.f);
    EXPECT_NEAR(h->u, 0.25f, kEps);
    EXPECT_NEAR(h->v, 0.5f, kEps);
}

TEST(RectangleTest, MissesEdgesLimitsAndDegenerate) {
    Rectangle q{{-1.f, 0.f, -1.f}, {2.f, 0.f, 0.f}, {0.f, 0.f, 2.f}, 0};
    EXPECT_FALSE(intersect(q, makeRay({1.5f, 3.f, 0.f}, {0.f, -1.f, 0.f})));
    EXPECT_FALSE(intersect(q, makeRay({0.f, 3.f, 0.f}, {0.f, 1.f, 0.f})));
    EXPECT_FALSE(intersect(q, makeRay({-5.f, 0.f, 0.f}, {1.f, 0.f, 0.f})));  // grazing, in its plane
    auto edge = intersect(q, makeRay({1.f, 3.f, 0.f}, {0.f, -1.f, 0.f}));   // on the closed edge s = 1
    ASSERT_TRUE(edge);
    EXPECT_FLOAT_EQ(edge->u, 1.f);
    EXPECT_FALSE(intersect(q, makeRay({0.f, 3.f, 0.f}, {0.f, -1.f, 0.f}, 0.f, 2.999f)));
    EXPECT_FALSE(intersect(q, makeRay({0.f, 3.f, 0.f}, {0.f, -1.f, 0.f}, 3.f, 10.f)));

    for (const Rectangle& bad : {Rectangle{{0.f, 0.f, 0.f}, {0.f, 0.f, 0.f}, {0.f, 0.f, 1.f}, 0},
                                 Rectangle{{0.f, 0.f, 0.f}, {1.f, 0.f, 0.f}, {2.f, 0.f, 0.f}, 0}}) {
        for (Vec3f d : {Vec3f{0.f, -1.f, 0.f}, Vec3f{0.f, 0.f, -1.f}, Vec3f{1.f, 0.f, 0.f}}) {
            auto h = intersect(bad, makeRay(Vec3f{0.2f, 0.f, 0.f} - 3.f * d, d));
            EXPECT_FALSE(h);
            expectFiniteOrMiss(h);
        }
        EXPECT_EQ(area(bad), 0.f);
    }
}

// ---------------------------------------------------------------- disk

TEST(DiskTest, HitGivesFrameCoordinates) {
    Scene scene;
    scene.disks.push_back(Disk{{0.f, 0.f, 0.f}, {0.f, 0.f, 1.f}, 2.f, 0});
    Ray r = makeRay({1.f, 0.f, 5.f}, {0.f, 0.f, -1.f});
    auto h = intersect(scene.disks[0], r);
    ASSERT_TRUE(h);
    EXPECT_FLOAT_EQ(h->t, 5.f);
    // Frame::fromNormal(+z) is s = +x, t = +y: (u, v) = (1, 0) / radius.
    EXPECT_NEAR(h->u, 0.5f, kEps);
    EXPECT_NEAR(h->v, 0.f, kEps);
    Hit hit = scene.completeHit(r, PrimRef{ShapeKind::Disk, 0, 0}, h->t, h->u, h->v);
    expectVecNear(hit.p, {1.f, 0.f, 0.f});
    expectVecNear(hit.ng, {0.f, 0.f, 1.f});
    EXPECT_NEAR(hit.uv.x, 0.75f, kEps);
    EXPECT_NEAR(hit.uv.y, 0.5f, kEps);
    // From behind (two-sided), the normal stays the front one.
    Ray back = makeRay({0.f, 1.f, -3.f}, {0.f, 0.f, 1.f});
    auto hb = intersect(scene.disks[0], back);
    ASSERT_TRUE(hb);
    EXPECT_FLOAT_EQ(hb->t, 3.f);
    expectVecNear(scene.completeHit(back, PrimRef{ShapeKind::Disk, 0, 0}, hb->t, hb->u, hb->v).ng, {0.f, 0.f, 1.f});
}

TEST(DiskTest, MissesLimitsAndDegenerate) {
    Disk k{{0.f, 0.f, 0.f}, {0.f, 0.f, 1.f}, 2.f, 0};
    EXPECT_FALSE(intersect(k, makeRay({2.1f, 0.f, 5.f}, {0.f, 0.f, -1.f})));
    EXPECT_FALSE(intersect(k, makeRay({1.5f, 1.5f, 5.f}, {0.f, 0.f, -1.f})));  // inside the square, outside the disk
    EXPECT_TRUE(intersect(k, makeRay({2.f, 0.f, 5.f}, {0.f, 0.f, -1.f})));     // on the rim
    EXPECT_FALSE(intersect(k, makeRay({-5.f, 0.f, 0.f}, {1.f, 0.f, 0.f})));    // grazing, in its plane
    EXPECT_FALSE(intersect(k, makeRay({0.f, 0.f, 5.f}, {0.f, 0.f, -1.f}, 0.f, 4.99f)));
    EXPECT_TRUE(intersect(k, makeRay({0.f, 0.f, 5.f}, {0.f, 0.f, -1.f}, 0.f, 5.f)));
    EXPECT_FALSE(intersect(k, makeRay({0.f, 0.f, 5.f}, {0.f, 0.f, -1.f}, 5.f, 10.f)));
    auto h = intersect(Disk{{0.f, 0.f, 0.f}, {0.f, 0.f, 1.f}, 0.f, 0}, makeRay({0.f, 0.f, 5.f}, {0.f, 0.f, -1.f}));
    EXPECT_FALSE(h);
    expectFiniteOrMiss(h);
}

// ---------------------------------------------------------------- triangle

TEST(TriangleTest, HitGivesBarycentricsAndMeshNormal) {
    Scene scene;
    TriangleMesh m;
    m.positions.push_back({0.f, 0.f, 0.f});
    m.positions.push_back({1.f, 0.f, 0.f});
    m.positions.push_back({0.f, 1.f, 0.f});
    m.indices = {0, 1, 2};
    scene.meshes.push_back(m);
    Ray r = makeRay({0.25f, 0.5f, 1.f}, {0.f, 0.f, -1.f});
    auto h = intersectTriangle(m.positions[0], m.positions[1], m.positions[2], r);
    ASSERT_TRUE(h);
    EXPECT_FLOAT_EQ(h->t, 1.f);
    EXPECT_NEAR(h->u, 0.25f, kEps);  // weight of p1
    EXPECT_NEAR(h->v, 0.5f, kEps);   // weight of p2
    Hit hit = scene.completeHit(r, PrimRef{ShapeKind::Mesh, 0, 0}, h->t, h->u, h->v);
    expectVecNear(hit.p, {0.25f, 0.5f, 0.f});
    expectVecNear(hit.ng, {0.f, 0.f, 1.f});
    EXPECT_NEAR(hit.uv.x, 0.25f, kEps);
    EXPECT_NEAR(hit.uv.y, 0.5f, kEps);
    // Two-sided, and the same parameters from behind.
    auto back = intersectTriangle(m.positions[0], m.positions[1], m.positions[2],
                                  makeRay({0.25f, 0.5f, -2.f}, {0.f, 0.f, 1.f}));
    ASSERT_TRUE(back);
    EXPECT_FLOAT_EQ(back->t, 2.f);
    EXPECT_NEAR(back->u, 0.25f, kEps);
}

TEST(TriangleTest, MissesGrazingLimitsAndDegenerate) {
    const Vec3f p0{0.f, 0.f, 0.f}, p1{1.f, 0.f, 0.f}, p2{0.f, 1.f, 0.f};
    EXPECT_FALSE(intersectTriangle(p0, p1, p2, makeRay({0.6f, 0.6f, 1.f}, {0.f, 0.f, -1.f})));
    EXPECT_FALSE(intersectTriangle(p0, p1, p2, makeRay({0.2f, 0.2f, 1.f}, {0.f, 0.f, 1.f})));
    auto graze = intersectTriangle(p0, p1, p2, makeRay({-1.f, 0.2f, 0.f}, {1.f, 0.f, 0.f}));  // in its plane
    EXPECT_FALSE(graze);
    expectFiniteOrMiss(graze);
    EXPECT_TRUE(intersectTriangle(p0, p1, p2, makeRay({0.2f, 0.2f, 1.f}, {0.f, 0.f, -1.f}, 0.f, 1.f)));
    EXPECT_FALSE(intersectTriangle(p0, p1, p2, makeRay({0.2f, 0.2f, 1.f}, {0.f, 0.f, -1.f}, 0.f, 0.999f)));
    EXPECT_FALSE(intersectTriangle(p0, p1, p2, makeRay({0.2f, 0.2f, 1.f}, {0.f, 0.f, -1.f}, 1.f, 5.f)));

    // Zero area: collinear and coincident vertices.
    for (Vec3f q : {Vec3f{2.f, 0.f, 0.f}, Vec3f{1.f, 0.f, 0.f}, Vec3f{0.f, 0.f, 0.f}}) {
        for (Vec3f d : {Vec3f{0.f, 0.f, -1.f}, Vec3f{0.f, -1.f, 0.f}, Vec3f{-1.f, 0.f, 0.f}}) {
            auto h = intersectTriangle(p0, p1, q, makeRay(Vec3f{0.5f, 0.f, 0.f} - 2.f * d, d));
            EXPECT_FALSE(h);
            expectFiniteOrMiss(h);
        }
        EXPECT_EQ(triangleArea(p0, p1, q), 0.f);
    }
}

TEST(TriangleTest, SharedEdgeAndVertexAreWatertight) {
    // Two triangles of a quad share the diagonal p1-p2; rays exactly through
    // the diagonal and the shared vertices must hit at least one of them.
    const Vec3f p0{0.f, 0.f, 0.f}, p1{1.f, 0.f, 0.f}, p2{0.f, 1.f, 0.f}, p3{1.f, 1.f, 0.f};
    int misses = 0;
    for (int i = 0; i <= 16; ++i) {
        float s = i / 16.f;
        Vec3f target{1.f - s, s, 0.f};
        for (Vec3f d : {Vec3f{0.f, 0.f, -1.f}, Vec3f{0.3f, -0.2f, -1.f}, Vec3f{-0.7f, 0.1f, -0.5f}}) {
            Ray r = makeRay(target - 3.f * d, d);
            bool a = intersectTriangle(p0, p1, p2, r).has_value();
            bool b = intersectTriangle(p1, p3, p2, r).has_value();
            if (!a && !b) ++misses;
        }
    }
    EXPECT_EQ(misses, 0);
}

// ---------------------------------------------------------------- bounds, area, sampling

TEST(ShapeBoundsTest, ContainTheShape) {
    Bounds3f bs = bounds(Sphere{{1.f, 2.f, 3.f}, 0.5f, 0});
    expectVecNear(bs.lo, {0.5f, 1.5f, 2.5f});
    expectVecNear(bs.hi, {1.5f, 2.5f, 3.5f});
    Bounds3f bd = bounds(Disk{{0.f, 0.f, 0.f}, {0.f, 0.f, 1.f}, 2.f, 0});
    expectVecNear(bd.lo, {-2.f, -2.f, 0.f});
    expectVecNear(bd.hi, {2.f, 2.f, 0.f});
    Bounds3f bq = bounds(Rectangle{{-1.f, 0.f, -1.f}, {2.f, 0.f, 0.f}, {0.f, 0.f, 2.f}, 0});
    expectVecNear(bq.lo, {-1.f, 0.f, -1.f});
    expectVecNear(bq.hi, {1.f, 0.f, 1.f});
    Bounds3f bb = bounds(makeBox({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f}, Transform::rotate(45.f, {0.f, 0.f, 1.f})));
    EXPECT_NEAR(bb.hi.x, std::sqrt(2.f), 1e-5f);
    EXPECT_NEAR(bb.hi.z, 1.f, 1e-5f);
}

TEST(ShapeSamplingTest, SpherePointsLieOnTheSurfaceWithPdfOneOverArea) {
    Sphere s{{1.f, -2.f, 0.5f}, 1.5f, 0};
    EXPECT_NEAR(area(s), 4.f * kPi * 2.25f, 1e-4f);
    for (int i = 0; i < 64; ++i) {
        Vec2f u{(i % 8 + 0.5f) / 8.f, (i / 8 + 0.5f) / 8.f};
        SurfaceSample ss = sampleUniform(s, u);
        EXPECT_NEAR(length(ss.p - s.center), s.radius, 1e-5f);
        expectVecNear(ss.n, (ss.p - s.center) / s.radius, 1e-5f);
        EXPECT_NEAR(ss.pdfArea, 1.f / area(s), 1e-7f);
    }
}

TEST(ShapeSamplingTest, RectanglePointsLieOnTheSurfaceWithPdfOneOverArea) {
    Rectangle q{{-1.f, 2.f, -1.f}, {2.f, 0.f, 0.f}, {0.f, 0.f, 3.f}, 0};
    EXPECT_FLOAT_EQ(area(q), 6.f);
    for (int i = 0; i < 64; ++i) {
        Vec2f u{(i % 8 + 0.5f) / 8.f, (i / 8 + 0.5f) / 8.f};
        SurfaceSample ss = sampleUniform(q, u);
        EXPECT_FLOAT_EQ(ss.p.y, 2.f);
        EXPECT_GE(ss.p.x, -1.f);
        EXPECT_LE(ss.p.x, 1.f);
        EXPECT_GE(ss.p.z, -1.f);
        EXPECT_LE(ss.p.z, 2.f);
        expectVecNear(ss.n, {0.f, -1.f, 0.f});
        EXPECT_FLOAT_EQ(ss.pdfArea, 1.f / 6.f);
    }
}

TEST(ShapeSamplingTest, DiskPointsLieOnTheSurfaceWithPdfOneOverArea) {
    Disk k{{0.f, 1.f, 0.f}, normalize(Vec3f{1.f, 1.f, 0.f}), 0.5f, 0};
    EXPECT_NEAR(area(k), kPi * 0.25f, 1e-6f);
    float maxR = 0.f;
    for (int i = 0; i < 64; ++i) {
        Vec2f u{(i % 8 + 0.5f) / 8.f, (i / 8 + 0.5f) / 8.f};
        SurfaceSample ss = sampleUniform(k, u);
        EXPECT_NEAR(dot(ss.p - k.center, k.normal), 0.f, 1e-6f);
        EXPECT_LE(length(ss.p - k.center), k.radius + 1e-6f);
        maxR = std::max(maxR, length(ss.p - k.center));
        expectVecNear(ss.n, k.normal);
        EXPECT_NEAR(ss.pdfArea, 1.f / area(k), 1e-6f);
    }
    EXPECT_GT(maxR, 0.4f);  // the samples spread over the disk
}

TEST(ShapeSamplingTest, TrianglePointsLieOnTheSurfaceWithPdfOneOverArea) {
    const Vec3f p0{0.f, 0.f, 0.f}, p1{2.f, 0.f, 0.f}, p2{0.f, 0.f, -2.f};
    EXPECT_FLOAT_EQ(triangleArea(p0, p1, p2), 2.f);
    for (int i = 0; i < 64; ++i) {
        Vec2f u{(i % 8 + 0.5f) / 8.f, (i / 8 + 0.5f) / 8.f};
        SurfaceSample ss = sampleTriangle(p0, p1, p2, u);
        EXPECT_FLOAT_EQ(ss.p.y, 0.f);
        EXPECT_GE(ss.p.x, 0.f);
        EXPECT_LE(ss.p.z, 0.f);
        EXPECT_LE(ss.p.x - ss.p.z, 2.f + 1e-5f);  // inside the hypotenuse
        expectVecNear(ss.n, normalize(cross(p1 - p0, p2 - p0)));
        EXPECT_FLOAT_EQ(ss.pdfArea, 0.5f);
    }
}

}  // namespace
}  // namespace penumbra
