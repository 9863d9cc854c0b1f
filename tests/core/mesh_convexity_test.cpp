// convexSlack and Scene::convexMeshOf: which meshes a ray leaving their
// surface cannot meet again (the accelerators' `leaving` hints).
#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "core/mesh_convexity.h"
#include "core/scene.h"
#include "support/test_meshes.h"

namespace penumbra {
namespace {

using test::makeIcosphere;
using test::makeTriangleCube;

Logger quiet() {
    return Logger([](LogLevel, std::string_view) {});
}

// A capped cylinder of `segments` sides around the y axis, as the textbook
// scene's mesh is built: side quads as two triangles, caps as fans from a
// rim vertex; counter-clockwise seen from outside.
TriangleMesh makeCylinder(float r, float h, int segments) {
    TriangleMesh m;
    const uint32_t n = uint32_t(segments);
    for (uint32_t i = 0; i < n; ++i) {
        const float a = 2.f * kPi * float(i) / float(n);
        m.positions.push_back({r * std::cos(a), 0.f, r * std::sin(a)});
    }
    for (uint32_t i = 0; i < n; ++i) m.positions.push_back({m.positions[i].x, h, m.positions[i].z});
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t j = (i + 1) % n;
        m.indices.insert(m.indices.end(), {i, n + i, j, j, n + i, n + j});
    }
    for (uint32_t i = 1; i + 1 < n; ++i) {
        m.indices.insert(m.indices.end(), {0, i, i + 1});              // bottom, facing -y
        m.indices.insert(m.indices.end(), {n, n + i + 1, n + i});      // top, facing +y
    }
    return m;
}

TEST(MeshConvexity, ConvexMeshesFacingOutwardsHaveASlackOfRoundingOnly) {
    EXPECT_LE(convexSlack(makeTriangleCube({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f})), 0.f);
    // Far from the origin: the slack stays the coordinates' rounding (2^-17 of them at most).
    const float farCube = convexSlack(makeTriangleCube({1e4f, 2e4f, -3e4f}, {1e4f + 2.f, 2e4f + 3.f, -3e4f + 1.f}));
    EXPECT_LE(farCube, 3e4f * 0x1p-20f);
    const float cylinder = convexSlack(makeCylinder(22.f, 85.f, 256));
    EXPECT_LE(cylinder, 85.f * 0x1p-20f);
    EXPECT_TRUE(std::isfinite(cylinder));
    const float ball = convexSlack(makeIcosphere({0.3f, -0.2f, 0.1f}, 2.f, 2));
    EXPECT_LE(ball, 2.f * 0x1p-20f);
    // One triangle: every vertex lies on its plane.
    TriangleMesh tri;
    for (Vec3f v : {Vec3f{0.f, 0.f, 0.f}, Vec3f{1.f, 0.f, 0.f}, Vec3f{0.f, 1.f, 0.f}}) tri.positions.push_back(v);
    tri.indices = {0, 1, 2};
    EXPECT_LE(convexSlack(tri), 0.f);
}

TEST(MeshConvexity, DentsInwardFacingTrianglesAndHugeMeshesAreNotConvex) {
    // A corner pushed in by a tenth of the side: the faces around it leave the other corners in front.
    TriangleMesh dented = makeTriangleCube({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f});
    dented.positions[7] = Vec3f{0.8f, 0.8f, 0.8f};
    EXPECT_EQ(convexSlack(dented), kInfinity);
    // The same cube wound the other way round: convex, but its triangles face inwards.
    TriangleMesh inward = makeTriangleCube({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f});
    for (size_t t = 0; t < inward.triangleCount(); ++t) std::swap(inward.indices[3 * t + 1], inward.indices[3 * t + 2]);
    EXPECT_EQ(convexSlack(inward), kInfinity);
    // Two cubes side by side: each convex, not the pair.
    TriangleMesh pair = makeTriangleCube({-1.f, -1.f, -1.f}, {0.f, 0.f, 0.f});
    const TriangleMesh other = makeTriangleCube({1.f, 1.f, 1.f}, {2.f, 2.f, 2.f});
    for (const Vec3f& p : other.positions) pair.positions.push_back(p);
    for (uint32_t i : other.indices) pair.indices.push_back(i + 8);
    EXPECT_EQ(convexSlack(pair), kInfinity);
    // Convex, but 5,120 triangles x 2,562 vertices is past the test's 2^22 steps.
    EXPECT_TRUE(std::isfinite(convexSlack(makeIcosphere({0.f, 0.f, 0.f}, 1.f, 3))));
    EXPECT_EQ(convexSlack(makeIcosphere({0.f, 0.f, 0.f}, 1.f, 4)), kInfinity);
    EXPECT_EQ(convexSlack(TriangleMesh{}), kInfinity);
}

TEST(MeshConvexity, SceneNamesTheConvexMeshOfAMeshHit) {
    Scene scene;
    scene.meshes.push_back(makeTriangleCube({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f}));
    TriangleMesh dented = makeTriangleCube({2.f, -1.f, -1.f}, {4.f, 1.f, 1.f});
    dented.positions[7] = Vec3f{3.8f, 0.8f, 0.8f};
    scene.meshes.push_back(dented);
    scene.meshes.push_back(makeCylinder(1.f, 2.f, 64));
    // A corner pushed out by 1e-3 on a cube of side 2,000: the two triangles
    // that do not hold it, of the faces it lies on, have it about 1e-3 in
    // front, above half the ray offset near the origin (7.6e-6) and below
    // half the one at 10^4 (0.076), where the same cube stands next.
    TriangleMesh bulging = makeTriangleCube({-1e3f, -1e3f, -1e3f}, {1e3f, 1e3f, 1e3f});
    bulging.positions[1] = Vec3f{1e3f + 1e-3f, -1e3f - 1e-3f, -1e3f - 1e-3f};
    scene.meshes.push_back(bulging);
    for (size_t i = 0; i < bulging.positions.size(); ++i) bulging.positions[i] += Vec3f{1.1e4f, 0.f, 0.f};
    scene.meshes.push_back(bulging);
    scene.spheres.push_back(Sphere{Vec3f{0.f, 5.f, 0.f}, 1.f, 0});
    EXPECT_EQ(scene.convexMeshOf(PrimRef{ShapeKind::Mesh, 0, 3, 0}), -1) << "before finalize()";
    scene.finalize(quiet());
    ASSERT_EQ(scene.meshes.size(), 5u);
    EXPECT_EQ(scene.convexMeshOf(PrimRef{ShapeKind::Mesh, 0, 3, 0}), 0);
    EXPECT_EQ(scene.convexMeshOf(PrimRef{ShapeKind::Mesh, 1, 3, 0}), -1);
    EXPECT_EQ(scene.convexMeshOf(PrimRef{ShapeKind::Mesh, 2, 7, 0}), 2);
    EXPECT_GT(convexSlack(scene.meshes[3]), 5e-4f);
    EXPECT_LT(convexSlack(scene.meshes[3]), 2e-3f);
    EXPECT_EQ(scene.convexMeshOf(PrimRef{ShapeKind::Mesh, 3, 0, 0}), -1);
    EXPECT_EQ(scene.convexMeshOf(PrimRef{ShapeKind::Mesh, 4, 0, 0}), 4);
    EXPECT_EQ(scene.convexMeshOf(PrimRef{ShapeKind::Sphere, 0, 0, 0}), -1);
    EXPECT_EQ(scene.convexMeshOf(PrimRef{ShapeKind::Instance, 0, 0, 0}), -1);
    EXPECT_EQ(scene.convexMeshOf(PrimRef{ShapeKind::Mesh, 7, 0, 0}), -1) << "no such mesh";
    // A copy (as a scene edit makes) keeps the answers.
    const Scene copy = scene;
    EXPECT_EQ(copy.convexMeshOf(PrimRef{ShapeKind::Mesh, 0, 3, 0}), 0);
}

TEST(MeshConvexity, ASceneOfManyMeshesTestsOnlyItsFirst8MillionSteps) {
    // Icospheres of 1,280 triangles and 642 vertices: 821,760 steps each, ten within 2^23.
    Scene scene;
    for (int i = 0; i < 12; ++i) scene.meshes.push_back(makeIcosphere({3.f * float(i), 0.f, 0.f}, 1.f, 3));
    scene.finalize(quiet());
    for (uint32_t i = 0; i < 12; ++i)
        EXPECT_EQ(scene.convexMeshOf(PrimRef{ShapeKind::Mesh, i, 0, 0}), i < 10 ? int32_t(i) : -1) << i;
}

}  // namespace
}  // namespace penumbra
