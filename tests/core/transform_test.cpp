// Affine transforms: composition, inverse, and normals under non-uniform scale and rotation.
#include "core/transform.h"

#include <gtest/gtest.h>

using namespace penumbra;

namespace {
void expectNear(const Vec3f& a, const Vec3f& b, float tol = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}
}  // namespace

TEST(Transform, RotationIsRightHanded) {
    expectNear(Transform::rotate(90.f, Vec3f{0, 0, 1}).applyVector(Vec3f{1, 0, 0}), Vec3f{0, 1, 0});
    expectNear(Transform::rotate(90.f, Vec3f{0, 1, 0}).applyVector(Vec3f{0, 0, 1}), Vec3f{1, 0, 0});
}

TEST(Transform, CompositionAppliesRightOperandFirst) {
    Transform t = Transform::translate(Vec3f{1, 2, 3}) * Transform::scale(Vec3f{2, 2, 2});
    expectNear(t.applyPoint(Vec3f{1, 1, 1}), Vec3f{3, 4, 5});
    Transform inv;
    ASSERT_TRUE(t.inverse(inv));
    expectNear(inv.applyPoint(Vec3f{3, 4, 5}), Vec3f{1, 1, 1});
    EXPECT_FALSE(Transform::scale(Vec3f{1, 0, 1}).inverse(inv));
}

TEST(Transform, NormalsStayPerpendicularToTransformedSurfaces) {
    // Tangents of a surface with normal n; after any invertible transform the
    // transformed normal must stay perpendicular to the transformed tangents.
    const Transform ts[] = {Transform::rotate(30.f, Vec3f{1, 2, 3}),
                            Transform::scale(Vec3f{3, 0.5f, 1}) * Transform::rotate(40.f, Vec3f{0, 1, 0}),
                            Transform::rotate(-25.f, Vec3f{1, 0, 0}) * Transform::scale(Vec3f{-1, 2, 4})};
    const Vec3f n = normalize(Vec3f{1, 1, 0}), t1{1, -1, 0}, t2{0, 0, 1};
    for (const Transform& t : ts) {
        Vec3f nn = normalize(t.applyNormal(n));
        EXPECT_NEAR(dot(nn, t.applyVector(t1)), 0.f, 1e-5f);
        EXPECT_NEAR(dot(nn, t.applyVector(t2)), 0.f, 1e-5f);
        // Orientation is kept: the normal stays on the side the transformed n points to.
        EXPECT_GT(dot(nn, t.applyVector(n)), 0.f);
    }
    // A pure rotation maps normals like vectors.
    Transform r = Transform::rotate(90.f, Vec3f{0, 0, 1});
    expectNear(normalize(r.applyNormal(Vec3f{1, 0, 0})), Vec3f{0, 1, 0});
}
