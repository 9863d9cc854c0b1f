// glTF files rendered through the public API: emissive strength reaches the
// image through the emission path (ratios 1:2:4:8:16), and the automatic
// camera sees a plane lying flat (TwoSidedPlane) instead of its edge; and
// metal-roughness materials built in code. The shared Khronos models are
// skipped cleanly when ../shared is absent.
#include <gtest/gtest.h>

#include <penumbra/penumbra.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "support/gltf_builder.h"
#include "support/test_support.h"

namespace {
namespace fs = std::filesystem;
using penumbra::test::GltfBuilder;
using Json = GltfBuilder::Json;

pnb::Renderer quietRenderer() {
    return pnb::Renderer([](pnb::LogLevel, std::string_view) {}, pnb::LogLevel::Error);
}

/// The blue radiance seen at the centre of the image of a camera at (x, 0, 4) looking at (x, 0, 0).
float centreBlue(const pnb::Renderer& r, const pnb::PreparedScene& p, float x) {
    pnb::Camera cam;
    cam.eye = {x, 0.f, 4.f};
    cam.lookAt = {x, 0.f, 0.f};
    cam.vfovDegrees = 5.f;
    pnb::RenderSettings st;
    st.width = st.height = 9;
    st.spp = 1;
    return r.render(p, cam, st).pixel(4, 4).b;
}

TEST(GltfRender, EmissiveStrengthScalesTheRenderedEmissionOneToSixteen) {
    const fs::path dir = penumbra::test::tempDir();
    GltfBuilder g;
    for (int k = 0; k < 5; ++k) {
        Json prim = g.quad();
        prim["material"] = g.material({{"emissiveFactor", {0.1, 0.5, 0.9}},
                                       {"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}}},
                                       {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 1 << k}}}}}});
        g.node(Json::array({prim}), {{"translation", {3.0 * k, 0, 0}}});
    }
    const fs::path file = penumbra::test::writeFile(dir / "strength.glb", g.glb());
    const pnb::Renderer r = quietRenderer();
    pnb::Scene s = r.loadScene(file.string());
    s.setDefaultLight(false);  // emission alone
    const pnb::PreparedScene p = r.prepare(s);
    const float one = centreBlue(r, p, 0.f);
    EXPECT_NEAR(one, 0.9f, 1e-5f);
    for (int k = 1; k < 5; ++k) EXPECT_NEAR(centreBlue(r, p, 3.f * k) / one, float(1 << k), 1e-4f) << k;
}

TEST(GltfRender, SharedEmissiveStrengthTestCubesRenderOneToSixteen) {
    const fs::path file = penumbra::test::sharedScenePath("khronos_gltf/EmissiveStrengthTest/glTF-Binary/EmissiveStrengthTest.glb");
    if (file.empty()) GTEST_SKIP() << "../shared/scenes not present";
    const pnb::Renderer r = quietRenderer();
    pnb::Scene s = r.loadScene(file.string());
    s.setDefaultLight(false);
    const pnb::PreparedScene p = r.prepare(s);
    // Cubes at x = -6 (strength 1), -3, 0, 3, 6 (16); what the cube faces reflect of the others is small.
    const float one = centreBlue(r, p, -6.f);
    EXPECT_NEAR(one, 0.9f, 0.02f);
    for (int k = 1; k < 5; ++k) EXPECT_NEAR(centreBlue(r, p, -6.f + 3.f * k) / one, float(1 << k), 0.02f * (1 << k)) << k;
}

/// The share of pixels of an image of the scene's default camera that are not the background (black).
double coverage(const pnb::Renderer& r, const pnb::Scene& s) {
    const pnb::PreparedScene p = r.prepare(s);
    pnb::RenderSettings st;
    st.width = st.height = 32;
    st.spp = 1;
    const pnb::Framebuffer fb = r.render(p, p.defaultCamera(1.f), st);
    int seen = 0;
    for (int y = 0; y < st.height; ++y)
        for (int x = 0; x < st.width; ++x) {
            const pnb::Color c = fb.pixel(x, y);
            seen += c.r + c.g + c.b > 0.f;
        }
    return double(seen) / (st.width * st.height);
}

TEST(GltfRender, TheDefaultCameraSeesAPlaneLyingFlat) {
    const fs::path dir = penumbra::test::tempDir();
    GltfBuilder g;
    Json prim = g.quad();
    prim["material"] = g.material({{"pbrMetallicRoughness", {{"metallicFactor", 0}}}});
    g.node(Json::array({prim}), {{"rotation", {-0.7071068, 0, 0, 0.7071068}}});  // the quad turned to face +y
    g.doc["extensions"]["KHR_lights_punctual"]["lights"] = Json::array({{{"type", "directional"}, {"intensity", 3}}});
    g.doc["nodes"].push_back({{"rotation", {-0.7071068, 0, 0, 0.7071068}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    g.doc["scenes"][0]["nodes"].push_back(1);
    const fs::path file = penumbra::test::writeFile(dir / "flat.gltf", g.gltf());
    const pnb::Renderer r = quietRenderer();
    pnb::Scene s = r.loadScene(file.string());
    s.setDefaultLight(false);
    EXPECT_GT(coverage(r, s), 0.2) << "the plane is seen edge-on";
}

TEST(GltfRender, SharedTwoSidedPlaneIsNotSeenEdgeOn) {
    const fs::path file = penumbra::test::sharedScenePath("khronos_gltf/TwoSidedPlane/glTF/TwoSidedPlane.gltf");
    if (file.empty()) GTEST_SKIP() << "../shared/scenes not present";
    const pnb::Renderer r = quietRenderer();
    pnb::Scene s = r.loadScene(file.string());
    s.setDefaultLight(false);
    s.addDirectionalLight({0.2f, -1.f, -0.3f}, pnb::gray(3.f));
    EXPECT_GT(coverage(r, s), 0.2) << "the plane is seen edge-on";
}

// A metal-roughness material built in code is checked, and renders through
// the metal-roughness BSDF.
TEST(ApiMaterials, MetalRoughnessMaterialsAreCheckedAndShaded) {
    std::vector<std::string> warnings;
    const pnb::Renderer r([&](pnb::LogLevel level, std::string_view m) {
        if (level == pnb::LogLevel::Warning) warnings.emplace_back(m);
    });
    pnb::Scene s;
    pnb::Material red;
    red.kind = pnb::MaterialKind::MetalRoughness;
    red.baseColor = {1.f, 0.f, 0.f};
    red.metallic = 0.f;
    red.kd = pnb::gray(1.f);  // a Phong term: ignored by the metal-roughness model
    red.emissiveTexture.path = "/nonexistent/glow.png";
    s.addRectangle({-1, -1, 0}, {2, 0, 0}, {0, 2, 0}, s.addMaterial(red));
    pnb::Camera cam;
    cam.eye = {0, 0, 3};
    cam.lookAt = {0, 0, 0};
    pnb::RenderSettings st;
    st.width = st.height = 8;
    st.spp = 1;
    const pnb::Color c = r.render(r.prepare(s), cam, st).pixel(4, 4);
    EXPECT_GT(c.r, 0.1f);
    // kd is the base colour's non-metal part (red), not the Phong kd given; green is F0's 4% highlight.
    EXPECT_LT(c.g, 0.1f * c.r);
    ASSERT_FALSE(warnings.empty());
    EXPECT_NE(warnings.back().find("/nonexistent/glow.png: cannot read texture"), std::string::npos) << warnings.back();

    pnb::Material bad = red;
    bad.metallic = 2.f;
    try {
        s.addMaterial(bad);
        ADD_FAILURE() << "metallic 2 was accepted";
    } catch (const pnb::Error& e) {
        EXPECT_EQ(e.code(), pnb::ErrorCode::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("metallic must lie in [0, 1]"), std::string::npos) << e.what();
    }
    bad = red;
    bad.baseColorTexture.uvSet = 2;
    EXPECT_THROW(s.addMaterial(bad), pnb::Error);
}

}  // namespace
