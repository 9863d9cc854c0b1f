// Instancing through the C++ API: an instanced and a copied mesh render the
// same image with both accelerators, emissive instances are lights, and bad
// instances are refused with a message naming the problem.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <penumbra/penumbra.hpp>
#include <vector>

#include "support/both_accelerators.h"

namespace {

pnb::Renderer quietRenderer() {
    return pnb::Renderer([](pnb::LogLevel, std::string_view) {}, pnb::LogLevel::Error);
}

// A latitude-longitude sphere of radius 1 with smooth normals (its positions).
struct Grid {
    std::vector<float> positions, normals;
    std::vector<uint32_t> indices;
};

Grid lumpySphere() {
    Grid g;
    const int rings = 12, segments = 18;
    for (int i = 0; i <= rings; ++i) {
        const float theta = 3.14159265f * float(i) / rings;
        for (int j = 0; j < segments; ++j) {
            const float phi = 2.f * 3.14159265f * float(j) / segments;
            const float r = 1.f + 0.15f * std::sin(3.f * phi) * std::sin(theta);  // not a sphere: the normals matter
            const float n[3] = {std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)};
            for (int k = 0; k < 3; ++k) {
                g.positions.push_back(r * n[k]);
                g.normals.push_back(n[k]);
            }
        }
    }
    for (int i = 0; i < rings; ++i) {
        for (int j = 0; j < segments; ++j) {
            const uint32_t a = i * segments + j, b = i * segments + (j + 1) % segments, c = a + segments,
                           d = b + segments;
            if (i > 0) g.indices.insert(g.indices.end(), {a, b, c});
            if (i + 1 < rings) g.indices.insert(g.indices.end(), {b, d, c});
        }
    }
    return g;
}

pnb::MeshDesc desc(const Grid& g, pnb::MaterialId material) {
    pnb::MeshDesc d;
    d.name = "lumpy";
    d.positions = g.positions.data();
    d.vertexCount = g.positions.size() / 3;
    d.indices = g.indices.data();
    d.triangleCount = g.indices.size() / 3;
    d.normals = g.normals.data();
    d.material = material;
    return d;
}

// The mesh with its vertices placed by m (normals by the inverse transpose,
// through the cofactors), as a host would copy it.
Grid placed(const Grid& g, const pnb::Matrix3x4& m) {
    Grid out = g;
    const auto& a = m.m;
    const float c[3][3] = {{a[1][1] * a[2][2] - a[1][2] * a[2][1], a[1][2] * a[2][0] - a[1][0] * a[2][2],
                            a[1][0] * a[2][1] - a[1][1] * a[2][0]},
                           {a[0][2] * a[2][1] - a[0][1] * a[2][2], a[0][0] * a[2][2] - a[0][2] * a[2][0],
                            a[0][1] * a[2][0] - a[0][0] * a[2][1]},
                           {a[0][1] * a[1][2] - a[0][2] * a[1][1], a[0][2] * a[1][0] - a[0][0] * a[1][2],
                            a[0][0] * a[1][1] - a[0][1] * a[1][0]}};
    for (size_t v = 0; v < g.positions.size(); v += 3) {
        const float* p = &g.positions[v];
        const float* n = &g.normals[v];
        float len = 0.f;
        for (int r = 0; r < 3; ++r) {
            out.positions[v + r] = a[r][0] * p[0] + a[r][1] * p[1] + a[r][2] * p[2] + a[r][3];
            out.normals[v + r] = c[r][0] * n[0] + c[r][1] * n[1] + c[r][2] * n[2];
            len += out.normals[v + r] * out.normals[v + r];
        }
        for (int r = 0; r < 3; ++r) out.normals[v + r] /= std::sqrt(len);
    }
    return out;
}

const pnb::Matrix3x4 kPlacements[] = {
    pnb::Matrix3x4::translate({-1.6f, 1.f, 0.f}),
    pnb::Matrix3x4::translate({0.8f, 0.9f, 0.3f}) * pnb::Matrix3x4::rotate(35.f, {0.3f, 1.f, 0.2f}) *
        pnb::Matrix3x4::scale({1.3f, 0.6f, 0.9f}),
    pnb::Matrix3x4::translate({0.f, 0.7f, -1.8f}) * pnb::Matrix3x4::scale({-0.8f, 0.8f, 0.8f}),  // mirrored
};

// Floor, a lamp, a point light and three lumpy spheres, copied or instanced.
pnb::Scene lumpyScene(bool instanced) {
    pnb::Scene s;
    pnb::Material white, red, lamp;
    white.kd = pnb::gray(0.7f);
    red.kd = {0.7f, 0.15f, 0.1f};
    red.ks = pnb::gray(0.3f);
    red.exponent = 40.f;
    lamp.kd = pnb::gray(0.f);
    lamp.ke = pnb::gray(6.f);
    const auto w = s.addMaterial(white), r = s.addMaterial(red), l = s.addMaterial(lamp);
    s.addPlane({0, 0, 0}, {0, 1, 0}, w);
    s.addRectangle({-1, 4, -1}, {2, 0, 0}, {0, 0, 2}, l);
    s.addPointLight({3, 5, 4}, pnb::gray(10.f));
    const Grid g = lumpySphere();
    if (instanced) {
        const pnb::PrototypeId p = s.addPrototype("lumpy");
        s.addPrototypeMesh(p, desc(g, r));
        for (const auto& m : kPlacements) s.addInstance(p, m);
    } else {
        for (const auto& m : kPlacements) {
            const Grid copy = placed(g, m);
            s.addMesh(desc(copy, r));
        }
    }
    return s;
}

pnb::Camera lumpyCamera() {
    pnb::Camera c;
    c.eye = {0.5f, 2.5f, 6.f};
    c.lookAt = {0, 0.8f, 0};
    c.vfovDegrees = 40.f;
    return c;
}

struct ImageDiff {
    size_t pixels = 0, differing = 0;  // differing: some channel off by more than 1e-3 relative
    double meanAbs = 0.0, maxAbs = 0.0;
};

ImageDiff compare(const std::vector<float>& a, const std::vector<float>& b) {
    ImageDiff d;
    d.pixels = a.size() / 4;
    for (size_t p = 0; p < d.pixels; ++p) {
        bool differs = false;
        for (int c = 0; c < 3; ++c) {
            const double x = a[4 * p + c], y = b[4 * p + c], e = std::fabs(x - y);
            d.meanAbs += e;
            d.maxAbs = std::max(d.maxAbs, e);
            differs |= e > 1e-3 * std::max(1.0, std::fabs(x));
        }
        d.differing += differs;
    }
    d.meanAbs /= double(3 * d.pixels);
    return d;
}

class InstancedImage : public penumbra::test::ForBothAccelerators {};

// Not bit-identical, by design: an instance is intersected in its object
// space (the ray taken there by the inverse transform) while the copy is
// intersected in world space, so t, u and v round differently in the last
// bits. The hit is then completed from the placed triangle exactly as the
// copy's (Scene::completeInstanceHit), so a ray that meets the same triangle
// shades the same to ~1e-6; only rays that graze an edge between triangles,
// a silhouette or a shadow boundary can land on the other side. So: nearly
// every pixel within 1e-3, a handful of edge pixels off, the means equal.
TEST_P(InstancedImage, InstancedAndCopiedMeshesRenderTheSameImage) {
    pnb::Renderer renderer = quietRenderer();
    pnb::RenderSettings st;
    st.width = 64;  // small: the naive loop tests every triangle for every ray
    st.height = 48;
    st.spp = 2;
    st.lightSamples = 4;
    st.seed = 3;
    const pnb::PrepareOptions opt{GetParam()};
    const pnb::PreparedScene copied = renderer.prepare(lumpyScene(false), opt);
    const pnb::PreparedScene instanced = renderer.prepare(lumpyScene(true), opt);
    EXPECT_EQ(copied.triangleCount(), instanced.triangleCount());
    const auto a = renderer.render(copied, lumpyCamera(), st).rgba();
    const auto b = renderer.render(instanced, lumpyCamera(), st).rgba();
    const ImageDiff d = compare(a, b);
    std::cout << "[instanced vs copied, " << copied.accelerator() << "] " << d.differing << " of " << d.pixels
              << " pixels differ by > 1e-3, mean abs difference " << d.meanAbs << ", max " << d.maxAbs << "\n";
    double mean = 0.0;
    for (size_t p = 0; p < a.size(); p += 4) mean += a[p];
    EXPECT_GT(mean / double(d.pixels), 0.02);  // the image is not black
    // Measured: no pixel off by more than 1e-3, mean difference ~6e-8 (both
    // accelerators); the bounds leave room for a grazing ray or two.
    EXPECT_LE(d.differing, d.pixels / 500);
    EXPECT_LT(d.meanAbs, 1e-5);
}

PENUMBRA_FOR_BOTH_ACCELERATORS(InstancedImage);

TEST(InstanceApi, EmissiveInstancesAreLightsLikeCopies) {
    pnb::Scene s;
    pnb::Material white, lamp;
    lamp.kd = pnb::gray(0.f);
    lamp.ke = pnb::gray(4.f);
    const auto w = s.addMaterial(white), l = s.addMaterial(lamp);
    const std::vector<float> pos = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const std::vector<uint32_t> idx = {0, 1, 2};
    pnb::MeshDesc d;
    d.positions = pos.data();
    d.vertexCount = 3;
    d.indices = idx.data();
    d.triangleCount = 1;
    d.material = w;
    const pnb::PrototypeId plain = s.addPrototype("plain");
    s.addPrototypeMesh(plain, d);
    s.addInstance(plain, pnb::Matrix3x4::translate({0, 0, -1}));
    s.addInstance(plain, pnb::Matrix3x4::translate({0, 0, -2}), l);  // an emissive override: a light
    d.material = l;
    const pnb::PrototypeId glow = s.addPrototype("glow");
    s.addPrototypeMesh(glow, d);
    for (int i = 0; i < 3; ++i) s.addInstance(glow, pnb::Matrix3x4::translate({float(i), 2, 0}));
    EXPECT_EQ(s.prototypeCount(), 2u);
    EXPECT_EQ(s.instanceCount(), 5u);
    EXPECT_EQ(s.triangleCount(), 5u);
    pnb::Renderer renderer = quietRenderer();
    const pnb::PreparedScene p = renderer.prepare(s);
    EXPECT_EQ(p.lightCount(), 4u);
    EXPECT_EQ(p.triangleCount(), 5u);
}

template <class F>
std::string errorOf(F&& f, pnb::ErrorCode expected) {
    try {
        f();
    } catch (const pnb::Error& e) {
        EXPECT_EQ(e.code(), expected) << e.what();
        return e.what();
    }
    ADD_FAILURE() << "no pnb::Error thrown";
    return "";
}

TEST(InstanceApi, BadInstancesAreRefusedWithTheReason) {
    pnb::Scene s;
    const pnb::PrototypeId p = s.addPrototype("p");
    const std::vector<float> pos = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    pnb::MeshDesc d;
    d.positions = pos.data();
    d.vertexCount = 3;
    d.triangleCount = 1;
    EXPECT_NE(errorOf([&] { s.addPrototypeMesh(p, d); }, pnb::ErrorCode::InvalidArgument).find("indices are null"),
              std::string::npos);
    EXPECT_NE(errorOf([&] { s.addPrototypeMesh(p + 1, d); }, pnb::ErrorCode::InvalidArgument).find("prototype id 1"),
              std::string::npos);
    EXPECT_NE(errorOf([&] { s.addInstance(7, {}); }, pnb::ErrorCode::InvalidArgument).find("prototype id 7 does not exist"),
              std::string::npos);
    EXPECT_NE(errorOf([&] { s.addInstance(p, pnb::Matrix3x4::scale({1, 0, 1})); }, pnb::ErrorCode::InvalidArgument)
                  .find("singular"),
              std::string::npos);
    pnb::Matrix3x4 nan;
    nan.m[1][3] = std::nanf("");
    EXPECT_NE(errorOf([&] { s.addInstance(p, nan); }, pnb::ErrorCode::InvalidArgument).find("finite"), std::string::npos);
    EXPECT_NE(errorOf([&] { s.addInstance(p, {}, 3u); }, pnb::ErrorCode::InvalidArgument).find("material id 3"),
              std::string::npos);
    EXPECT_EQ(s.instanceCount(), 0u);
}

// Emissive instances are expanded into meshes when prepared: a scene built in
// code that would copy more than the limit (10,001 copies of 10,000 emissive
// triangles) is refused before a copy is made, not expanded into gigabytes.
TEST(InstanceApi, EmissiveInstancesThatWouldCopyTooMuchAreRefused) {
    pnb::Scene s;
    pnb::Material lamp;
    lamp.ke = pnb::gray(1.f);
    const auto l = s.addMaterial(lamp);
    std::vector<float> pos;
    std::vector<uint32_t> idx;
    for (uint32_t t = 0; t < 10000; ++t) {
        const float x = float(t % 100), y = float(t / 100);
        pos.insert(pos.end(), {x, y, 0, x + 1, y, 0, x, y + 1, 0});
        idx.insert(idx.end(), {3 * t, 3 * t + 1, 3 * t + 2});
    }
    pnb::MeshDesc d;
    d.positions = pos.data();
    d.vertexCount = pos.size() / 3;
    d.indices = idx.data();
    d.triangleCount = idx.size() / 3;
    d.material = l;
    const pnb::PrototypeId glow = s.addPrototype("glow");
    s.addPrototypeMesh(glow, d);
    for (int i = 0; i < 10001; ++i) s.addInstance(glow, pnb::Matrix3x4::translate({0, 0, float(i)}));
    pnb::Renderer renderer = quietRenderer();
    const std::string msg = errorOf([&] { (void)renderer.prepare(s); }, pnb::ErrorCode::InvalidScene);
    EXPECT_NE(msg.find("emissive instances"), std::string::npos) << msg;
    EXPECT_NE(msg.find("100010000 triangles"), std::string::npos) << msg;
}

}  // namespace
