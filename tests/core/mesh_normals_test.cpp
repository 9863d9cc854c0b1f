// Smooth normals for meshes without any (core/mesh_normals.h): a sphere-like
// mesh gets continuous normals, a cube keeps its sharp edges, 0 is faceted.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <tuple>

#include "core/mesh_normals.h"

namespace penumbra {
namespace {

/// A UV sphere of radius 1 as separate triangles (no shared vertices, as STL
/// files and de-indexed OBJ files come), without normals.
TriangleMesh unindexedSphere(int rings, int segments) {
    TriangleMesh m;
    auto at = [&](int i, int j) {
        const float theta = kPi * float(i) / float(rings), phi = 2.f * kPi * float(j % segments) / float(segments);
        return Vec3f{std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)};
    };
    auto tri = [&](Vec3f a, Vec3f b, Vec3f c) {
        const uint32_t base = static_cast<uint32_t>(m.positions.size());
        m.positions.push_back(a);
        m.positions.push_back(b);
        m.positions.push_back(c);
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
    };
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            // Outward (counter-clockwise seen from outside).
            if (i > 0) tri(at(i, j), at(i, j + 1), at(i + 1, j));
            if (i + 1 < rings) tri(at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
        }
    return m;
}

/// A unit cube, indexed with 8 shared corners (as PLY files come).
TriangleMesh cube() {
    TriangleMesh m;
    for (int i = 0; i < 8; ++i) m.positions.push_back({float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)});
    const uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : faces) m.indices.insert(m.indices.end(), {f[0], f[1], f[2], f[0], f[2], f[3]});
    return m;
}

Vec3f faceNormal(const TriangleMesh& m, size_t t) {
    Vec3f a, b, c;
    m.vertices(t, a, b, c);
    return normalize(cross(b - a, c - a));
}

TEST(MeshNormals, SphereGetsContinuousNormalsCloseToTheTrueOnes) {
    TriangleMesh m = unindexedSphere(16, 32);
    const size_t triangles = m.triangleCount();
    smoothNormals(m, 30.f);
    ASSERT_EQ(m.normals.size(), m.positions.size());
    EXPECT_EQ(m.triangleCount(), triangles);
    // Continuous: every copy of a position carries the same normal.
    std::map<std::tuple<float, float, float>, Vec3f> seen;
    size_t shared = 0;
    for (size_t v = 0; v < m.positions.size(); ++v) {
        const Vec3f& p = m.positions[v];
        auto [it, fresh] = seen.try_emplace({p.x, p.y, p.z}, m.normals[v]);
        if (!fresh) {
            ++shared;
            EXPECT_EQ(it->second.x, m.normals[v].x);
            EXPECT_EQ(it->second.y, m.normals[v].y);
            EXPECT_EQ(it->second.z, m.normals[v].z);
        }
        // And close to the sphere's own normal (the position), unlike a face normal.
        EXPECT_GT(dot(m.normals[v], normalize(p)), 0.99f) << v;
    }
    EXPECT_EQ(shared, 0u) << "corners at one position share one vertex";
    // Welded: far fewer vertices than the 3 per triangle it came with.
    EXPECT_LT(m.positions.size(), triangles);
}

TEST(MeshNormals, CubeKeepsItsSharpEdges) {
    TriangleMesh m = cube();
    smoothNormals(m, 30.f);
    ASSERT_EQ(m.normals.size(), m.positions.size());
    EXPECT_EQ(m.positions.size(), 24u) << "each corner splits into one vertex per face";
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        const Vec3f n = faceNormal(m, t);
        for (int k = 0; k < 3; ++k) {
            const Vec3f& s = m.normals[m.indices[3 * t + k]];
            EXPECT_NEAR(dot(s, n), 1.f, 1e-6f) << "triangle " << t;
        }
    }
    // Past 90 degrees the cube's edges smooth too: corners point along the diagonals.
    TriangleMesh round = cube();
    smoothNormals(round, 100.f);
    EXPECT_EQ(round.positions.size(), 8u);
    for (size_t v = 0; v < 8; ++v)
        EXPECT_NEAR(dot(round.normals[v], normalize(round.positions[v] - Vec3f{0.5f, 0.5f, 0.5f})), 1.f, 1e-5f);
}

TEST(MeshNormals, ZeroAngleOrExistingNormalsLeaveTheMeshAlone) {
    TriangleMesh m = unindexedSphere(4, 8);
    const size_t nv = m.positions.size();
    smoothNormals(m, 0.f);
    EXPECT_TRUE(m.normals.empty());
    EXPECT_EQ(m.positions.size(), nv);
    TriangleMesh c = cube();
    c.normals.assign(c.positions.size(), Vec3f{0.f, 0.f, 1.f});
    smoothNormals(c, 30.f);
    EXPECT_EQ(c.positions.size(), 8u);
    EXPECT_EQ(c.normals[0].z, 1.f);
}

TEST(MeshNormals, UvSeamsAreKeptWhileTheNormalIsShared) {
    // Two triangles of one plane meeting along an edge whose vertices are
    // duplicated with different UVs: the normals agree, the UVs stay.
    TriangleMesh m;
    for (Vec3f p : {Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{0, 1, 0}, Vec3f{1, 0, 0}, Vec3f{1, 1, 0}, Vec3f{0, 1, 0}})
        m.positions.push_back(p);
    m.uvs = {{0, 0}, {1, 0}, {0, 1}, {0.5f, 0}, {1, 1}, {0, 0.5f}};
    m.indices = {0, 1, 2, 3, 4, 5};
    smoothNormals(m, 30.f);
    ASSERT_EQ(m.uvs.size(), m.positions.size());
    EXPECT_EQ(m.positions.size(), 6u);
    for (size_t v = 0; v < 6; ++v) EXPECT_NEAR(m.normals[v].z, 1.f, 1e-6f);
    EXPECT_EQ(m.uvs[m.indices[3]].x, 0.5f);
}

}  // namespace
}  // namespace penumbra
