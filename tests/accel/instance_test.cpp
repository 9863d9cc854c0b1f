// Instances in both accelerators: placements (translation, rotation,
// non-uniform scale, mirroring) hit where the transform puts the prototype,
// with normals transformed by the inverse transpose, the instance's material
// and the mesh of a group reported; an instance answers like a copy of its
// placed vertices; Scene::finalize's rules for instances (bad ones dropped,
// emissive ones expanded into meshes).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "accel/accelerator.h"
#include "core/scene.h"
#include "core/transform.h"
#include "support/both_accelerators.h"

namespace penumbra {
namespace {

class InstanceHits : public test::ForBothAccelerators {};

Logger quietLogger() {
    return Logger([](LogLevel, std::string_view) {});
}

// The square [-1, 1]^2 in the plane z = z0, front facing +z.
TriangleMesh square(float z0 = 0.f, uint32_t material = 0) {
    TriangleMesh m;
    m.name = "square";
    for (Vec3f p : {Vec3f{-1, -1, z0}, Vec3f{1, -1, z0}, Vec3f{1, 1, z0}, Vec3f{-1, 1, z0}}) m.positions.push_back(p);
    m.indices = {0, 1, 2, 0, 2, 3};
    m.material = material;
    return m;
}

// A square in the plane x + y = 0, front facing (1, 1, 0) / sqrt(2).
TriangleMesh tiltedSquare() {
    TriangleMesh m;
    m.name = "tilted";
    for (Vec3f p : {Vec3f{-1, 1, -1}, Vec3f{1, -1, -1}, Vec3f{1, -1, 1}, Vec3f{-1, 1, 1}}) m.positions.push_back(p);
    m.indices = {0, 2, 1, 0, 3, 2};
    return m;
}

void expectNear(const Vec3f& a, const Vec3f& b, float tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

uint32_t addPrototype(Scene& s, std::vector<TriangleMesh> meshes, const std::string& name = "p") {
    s.prototypes.push_back(Prototype{name, std::move(meshes)});
    return uint32_t(s.prototypes.size() - 1);
}

TEST_P(InstanceHits, TranslationRotationAndScaleHitWhereTheTransformPutsThePrototype) {
    Scene s;
    s.materials.resize(3);
    const uint32_t sq = addPrototype(s, {square()});
    const uint32_t tilt = addPrototype(s, {tiltedSquare()});
    s.instances.push_back(makeInstance(sq, Transform::translate({5, 0, 0})));
    // Rotating +z onto +x, then moving to x = -10.
    s.instances.push_back(makeInstance(sq, Transform::translate({-10, 0, 0}) * Transform::rotate(90.f, {0, 1, 0})));
    // Non-uniform scale: the plane x + y = 0 becomes x / 2 + 2 y = 0, whose
    // normal is (1/2, 2, 0) (the inverse transpose), not M n = (2, 1/2, 0).
    s.instances.push_back(makeInstance(tilt, Transform::translate({0, 0, 30}) * Transform::scale({2, 0.5f, 1}), 2));
    s.finalize(quietLogger());
    const auto acc = makeAccelerator(GetParam(), s);

    auto h = acc->intersect(Ray{{5.3f, 0.2f, 10.f}, {0, 0, -1}});
    ASSERT_TRUE(h);
    EXPECT_EQ(h->ref, (PrimRef{ShapeKind::Instance, 0, h->ref.prim, 0}));
    EXPECT_NEAR(h->t, 10.f, 1e-5f);
    expectNear(h->p, {5.3f, 0.2f, 0.f}, 1e-5f);
    expectNear(h->ng, {0, 0, 1}, 1e-6f);
    expectNear(h->ns, {0, 0, 1}, 1e-6f);
    EXPECT_EQ(h->material, 0u);

    h = acc->intersect(Ray{{-5.f, 0.3f, 0.4f}, {-1, 0, 0}});
    ASSERT_TRUE(h);
    EXPECT_EQ(h->ref.kind, ShapeKind::Instance);
    EXPECT_EQ(h->ref.object, 1u);
    EXPECT_NEAR(h->t, 5.f, 1e-5f);
    expectNear(h->p, {-10.f, 0.3f, 0.4f}, 1e-5f);
    expectNear(h->ng, {1, 0, 0}, 1e-6f);
    // Just beside the rotated square (it spans z in [-1, 1] now): a miss.
    EXPECT_FALSE(acc->intersect(Ray{{-5.f, 0.3f, 1.1f}, {-1, 0, 0}}));

    h = acc->intersect(Ray{{0.4f, 10.f, 30.2f}, {0, -1, 0}});
    ASSERT_TRUE(h);
    EXPECT_EQ(h->ref.object, 2u);
    EXPECT_NEAR(h->t, 10.1f, 1e-5f);
    expectNear(h->p, {0.4f, -0.1f, 30.2f}, 1e-5f);
    expectNear(h->ng, normalize(Vec3f{0.5f, 2.f, 0.f}), 1e-6f);
    EXPECT_EQ(h->material, 2u);  // the instance's override

    // Occlusion sees instances too, in the open interval (tnear, tfar).
    EXPECT_TRUE(acc->occluded(Ray{{5.3f, 0.2f, 10.f}, {0, 0, -1}, 0.f, 10.5f}));
    EXPECT_FALSE(acc->occluded(Ray{{5.3f, 0.2f, 10.f}, {0, 0, -1}, 0.f, 9.5f}));
    EXPECT_FALSE(acc->occluded(Ray{{-5.f, 0.3f, 1.1f}, {-1, 0, 0}}));
}

TEST_P(InstanceHits, AnInstanceAnswersLikeACopyOfItsPlacedVertices) {
    // Rotation, non-uniform scale, translation and a mirror (det < 0): the
    // mirror turns the triangles clockwise, so the front flips, as for a copy.
    const Transform placements[] = {
        Transform::translate({0.5f, -0.25f, 0.f}) * Transform::rotate(37.f, normalize(Vec3f{1, 2, 3})) *
            Transform::scale({1.5f, 0.7f, 1.2f}),
        Transform::translate({0.f, 0.3f, 0.f}) * Transform::scale({1.f, 1.f, -1.f}) *
            Transform::rotate(20.f, {1, 0, 0})};
    for (const Transform& place : placements) {
        Scene inst, copy;
        TriangleMesh proto = tiltedSquare();
        proto.normals = {normalize(Vec3f{1, 1, 0.3f}), normalize(Vec3f{1, 1, -0.3f}), normalize(Vec3f{1, 0.8f, 0}),
                         normalize(Vec3f{0.9f, 1, 0})};
        copy.meshes.push_back(placedCopy(proto, place));
        addPrototype(inst, {proto});
        inst.instances.push_back(makeInstance(0, place));
        inst.finalize(quietLogger());
        copy.finalize(quietLogger());
        const auto a = makeAccelerator(GetParam(), inst), b = makeAccelerator(GetParam(), copy);
        int hits = 0;
        for (int i = 0; i < 400; ++i) {
            const float x = -1.f + 2.f * float(i % 20) / 19.f, y = -1.f + 2.f * float(i / 20) / 19.f;
            const Ray r{{5.f, 5.f + y, x}, normalize(Vec3f{-1.f, -1.f, 0.f})};
            const auto hi = a->intersect(r), hc = b->intersect(r);
            ASSERT_EQ(hi.has_value(), hc.has_value()) << i;
            EXPECT_EQ(a->occluded(r), b->occluded(r)) << i;
            if (!hi) continue;
            ++hits;
            EXPECT_EQ(hi->ref.prim, hc->ref.prim);
            // t, u, v of the object-space test round differently (a few 1e-6
            // relative, more at grazing angles); the point moves along the ray with t.
            EXPECT_NEAR(hi->t, hc->t, 1e-5f * hc->t);
            expectNear(hi->p, hc->p, 1e-5f * hc->t);
            expectNear(hi->ng, hc->ng, 1e-5f);
            expectNear(hi->ns, hc->ns, 1e-5f);
        }
        EXPECT_GT(hits, 100);
    }
}

TEST_P(InstanceHits, GroupsReportTheirMeshAndMaterial) {
    Scene s;
    s.materials.resize(4);
    addPrototype(s, {square(0.f, 1), square(-2.f, 2)}, "pair");
    s.instances.push_back(makeInstance(0, Transform::translate({0, 0, -5})));
    s.instances.push_back(makeInstance(0, Transform::translate({3, 0, -5}), 3));
    s.finalize(quietLogger());
    const auto acc = makeAccelerator(GetParam(), s);
    auto h = acc->intersect(Ray{{0.5f, 0.5f, 0.f}, {0, 0, -1}});
    ASSERT_TRUE(h);
    EXPECT_EQ(h->ref.part, 0u);
    EXPECT_EQ(h->material, 1u);
    EXPECT_NEAR(h->t, 5.f, 1e-5f);
    // Through a hole-free square no ray reaches the second mesh from the
    // front; from behind it is the first one met.
    h = acc->intersect(Ray{{0.5f, 0.5f, -10.f}, {0, 0, 1}});
    ASSERT_TRUE(h);
    EXPECT_EQ(h->ref.part, 1u);
    EXPECT_EQ(h->material, 2u);
    EXPECT_NEAR(h->t, 3.f, 1e-5f);
    h = acc->intersect(Ray{{3.5f, 0.5f, -10.f}, {0, 0, 1}});
    ASSERT_TRUE(h);
    EXPECT_EQ(h->ref.object, 1u);
    EXPECT_EQ(h->material, 3u);
    EXPECT_EQ(s.triangleCount(), 8u);
}

TEST_P(InstanceHits, BatchedQueriesSeeInstances) {
    Scene s;
    addPrototype(s, {square()});
    for (int i = 0; i < 6; ++i)
        s.instances.push_back(makeInstance(0, Transform::translate({2.5f * float(i), 0, 0}) *
                                                  Transform::rotate(10.f * float(i), {0, 1, 0})));
    s.finalize(quietLogger());
    const auto acc = makeAccelerator(GetParam(), s);
    std::vector<Ray> rays;
    // Off the squares' outer edges, where packets and single rays may round either way.
    for (int i = 0; i < 37; ++i) rays.push_back(Ray{{0.4f * float(i) - 0.93f, 0.1f, 5.f}, {0, 0, -1}, 0.f, 6.f});
    std::vector<std::optional<Hit>> batch(rays.size());
    std::vector<uint8_t> occ(rays.size());
    acc->intersectBatch(rays, batch);
    acc->occludedBatch(rays, occ);
    int hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const auto single = acc->intersect(rays[i]);
        ASSERT_EQ(single.has_value(), batch[i].has_value()) << i;
        EXPECT_EQ(occ[i] != 0, acc->occluded(rays[i])) << i;
        EXPECT_EQ(occ[i] != 0, single.has_value()) << i;
        if (!single) continue;
        ++hits;
        EXPECT_EQ(single->ref, batch[i]->ref);
        EXPECT_NEAR(single->t, batch[i]->t, 1e-5f);
    }
    EXPECT_GT(hits, 20);
}

PENUMBRA_FOR_BOTH_ACCELERATORS(InstanceHits);

// What the texture filter measures a hit triangle on (shading/integrator.cpp).
TEST(InstanceFinalize, MeshOfNamesThePrototypesMeshAndThePlacement) {
    Scene s;
    s.meshes.push_back(square());
    addPrototype(s, {square(0.f), square(1.f)}, "pair");
    s.instances.push_back(makeInstance(0, Transform::translate({0, 0, 3})));
    s.spheres.push_back(Sphere{{0, 0, 9}, 1.f, 0});
    s.finalize(quietLogger());
    Transform place = Transform::scale({2, 2, 2});
    EXPECT_EQ(s.meshOf(PrimRef{ShapeKind::Mesh, 0, 1}, &place), &s.meshes[0]);
    EXPECT_TRUE(place.isIdentity());
    EXPECT_EQ(s.meshOf(PrimRef{ShapeKind::Instance, 0, 1, 1}, &place), &s.prototypes[0].meshes[1]);
    EXPECT_EQ(place.applyPoint({0, 0, 1}), (Vec3f{0, 0, 4}));
    EXPECT_EQ(s.meshOf(PrimRef{ShapeKind::Sphere, 0, 0}, &place), nullptr);
}

TEST(InstanceFinalize, DropsInstancesNoAcceleratorCanPlace) {
    Scene s;
    addPrototype(s, {square()});
    addPrototype(s, {}, "empty");
    s.instances.push_back(makeInstance(0, Transform()));
    s.instances.push_back(makeInstance(7, Transform()));                    // unknown prototype
    s.instances.push_back(makeInstance(1, Transform()));                    // empty prototype
    s.instances.push_back(makeInstance(0, Transform::scale({1, 0, 1})));    // singular
    s.instances.push_back(makeInstance(0, Transform::translate({2e18f, 0, 0})));  // beyond the range
    Instance nan = makeInstance(0, Transform());
    nan.worldFromObject = Transform::translate({std::nanf(""), 0, 0});
    s.instances.push_back(nan);
    std::vector<std::string> warnings;
    const SceneFixups fix = s.finalize(Logger([&](LogLevel l, std::string_view m) {
        if (l == LogLevel::Warning) warnings.emplace_back(m);
    }));
    EXPECT_EQ(fix.droppedInstances, 5u);
    ASSERT_EQ(s.instances.size(), 1u);
    EXPECT_EQ(s.instances[0].prototype, 0u);
    ASSERT_EQ(warnings.size(), 2u);  // the bad ones, and the one beyond the range
    EXPECT_NE(warnings[0].find("dropped 1 instance(s) reaching beyond"), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[1].find("dropped 4 instance(s) with an unknown or empty prototype"), std::string::npos)
        << warnings[1];
    EXPECT_EQ(s.finalize(quietLogger()).droppedInstances, 0u);  // idempotent
}

TEST(InstanceFinalize, EmissiveInstancesBecomeMeshesSoEachIsALight) {
    Scene s;
    Material plain, lamp;
    lamp.ke = Rgb(5.f);
    s.materials = {plain, lamp};
    addPrototype(s, {square(0.f, 0)}, "plain");
    addPrototype(s, {square(0.f, 0), square(1.f, 1)}, "lamp");
    s.instances.push_back(makeInstance(0, Transform::translate({1, 0, 0})));
    s.instances.push_back(makeInstance(1, Transform::translate({0, 5, 0})));     // emissive prototype
    s.instances.push_back(makeInstance(0, Transform::translate({0, 9, 0}), 1));  // emissive override
    s.instances.push_back(makeInstance(1, Transform::translate({0, 7, 0}), 0));  // override makes it plain
    s.finalize(quietLogger());
    ASSERT_EQ(s.instances.size(), 2u);
    EXPECT_EQ(s.instances[0].prototype, 0u);
    EXPECT_EQ(s.instances[1].prototype, 1u);
    EXPECT_EQ(s.instances[1].material, 0u);
    // The lamp's two meshes placed at y = 5, then the overridden square at y = 9.
    ASSERT_EQ(s.meshes.size(), 3u);
    EXPECT_EQ(s.meshes[0].positions[0].y, 4.f);
    EXPECT_EQ(s.meshes[1].material, 1u);
    EXPECT_EQ(s.meshes[1].positions[0].z, 1.f);
    EXPECT_EQ(s.meshes[2].material, 1u);
    EXPECT_EQ(s.meshes[2].positions[0].y, 8.f);
    EXPECT_EQ(s.triangleCount(), 2u * 3u + 2u + 4u);
    const size_t before = s.meshes.size();
    s.finalize(quietLogger());
    EXPECT_EQ(s.meshes.size(), before);  // idempotent
}

}  // namespace
}  // namespace penumbra
