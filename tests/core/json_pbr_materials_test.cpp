// JSON materials of the metal-roughness model and the texture slots of both
// models (docs/scene-format.md, "Materials"): every key lands in the material,
// a slot's sampling keys in its TextureRef, and mistakes are errors naming
// the file and the JSON path.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/io/scene_loader.h"
#include "support/test_support.h"

namespace penumbra {
namespace {
namespace fs = std::filesystem;

/// Loads `json` as dir/scene.json, the textures it may name present in dir.
LoadedScene loadIn(const fs::path& dir, const std::string& json) {
    for (const char* t : {"base.png", "mr.png", "n.png", "glow.png", "cut.png"}) test::writeFile(dir / t, "an image");
    return loadJsonScene(test::writeFile(dir / "scene.json", json), {}, Logger());
}

std::string errorIn(const fs::path& dir, const std::string& json) {
    try {
        loadIn(dir, json);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(JsonMaterials, MetalRoughnessKeysAndTextureSlots) {
    const fs::path dir = test::tempDir();
    const LoadedScene s = loadIn(dir, R"({"materials": {"brass": {
        "model": "metal_roughness", "base_color": [1, 0.8, 0.4], "metallic": 1, "roughness": 0.25,
        "base_color_texture": {"file": "base.png", "uv_set": 1, "wrap": ["clamp", "mirror"], "filter": "nearest",
                               "offset": [0.5, 0], "rotation": 90, "scale": [2, 2]},
        "metallic_texture": "mr.png", "roughness_texture": {"file": "mr.png", "channel": "g"},
        "normal_texture": "n.png", "normal_scale": 0.5, "emissive_texture": "glow.png", "ke": [2, 2, 2],
        "opacity_texture": "cut.png", "alpha_cutoff": 0.75, "transmission": 0.5, "ior": 1.4}}})");
    ASSERT_EQ(s.scene.materials.size(), 1u);
    const Material& m = s.scene.materials[0];
    EXPECT_EQ(m.kind, MaterialKind::MetalRoughness);
    EXPECT_FLOAT_EQ(m.baseColor.g, 0.8f);
    EXPECT_FLOAT_EQ(m.metallic, 1.f);
    EXPECT_FLOAT_EQ(m.roughness, 0.25f);
    EXPECT_FLOAT_EQ(m.transmission, 0.5f);
    EXPECT_FLOAT_EQ(m.ior, 1.4f);
    EXPECT_FLOAT_EQ(m.normalScale, 0.5f);
    EXPECT_FLOAT_EQ(m.ke.r, 2.f);
    ASSERT_TRUE(m.baseColorMap.used());
    EXPECT_EQ(m.baseColorMap.uvSet, 1);
    EXPECT_EQ(m.baseColorMap.wrapS, TextureWrap::ClampToEdge);
    EXPECT_EQ(m.baseColorMap.wrapT, TextureWrap::MirroredRepeat);
    EXPECT_EQ(m.baseColorMap.filter, TextureFilter::Nearest);
    EXPECT_NEAR(m.baseColorMap.m[1], 2.f, 1e-6f);  // rotated 90 degrees: s' = 2 t + 0.5
    EXPECT_NEAR(m.baseColorMap.m[2], 0.5f, 1e-6f);
    EXPECT_EQ(fs::path(m.baseColorTexture.path), dir / "base.png");
    // One file for metal (B by default) and roughness (G): one texture, two channels.
    EXPECT_EQ(m.metallicMap.texture, m.roughnessMap.texture);
    EXPECT_EQ(m.metallicMap.channel, 2);
    EXPECT_EQ(m.roughnessMap.channel, 1);
    EXPECT_EQ(s.scene.textures[size_t(m.metallicMap.texture)].colorSpace, TextureColorSpace::Linear);
    EXPECT_EQ(s.scene.textures[size_t(m.emissiveMap.texture)].colorSpace, TextureColorSpace::FromFile);
    EXPECT_TRUE(m.needsTangents());
    // An opacity map cuts out by default, at the given cutoff.
    EXPECT_EQ(m.alphaMode, AlphaMode::Mask);
    EXPECT_FLOAT_EQ(m.alphaCutoff, 0.75f);
    EXPECT_EQ(m.opacityMap.channel, 3);
    // A metal transmits nothing: shaded by the metal-roughness BSDF, its Phong terms hold no
    // glossy, mirror or glass term, and kd is the base colour (core/material.h, mapTransmissionOntoGlass).
    EXPECT_TRUE(m.shadedAsMetalRoughness());
    EXPECT_FLOAT_EQ(m.kd.g, 0.8f);
    EXPECT_FLOAT_EQ(m.ks.g, 0.f);
    EXPECT_FLOAT_EQ(m.kr.g, 0.f);
}

TEST(JsonMaterials, PhongMaterialsTakeTheSharedSlots) {
    const fs::path dir = test::tempDir();
    const LoadedScene s = loadIn(dir, R"({"materials": {
        "wall": {"kd": 0.5, "texture": "base.png", "bump_texture": "n.png", "normal_scale": 3},
        "glass": {"kd": 0.5, "opacity": 0.25},
        "sign": {"kd": 0.5, "texture": "base.png", "alpha_mode": "opaque"}}})");
    const auto& mats = s.scene.materials;
    EXPECT_EQ(mats[0].kind, MaterialKind::Phong);
    EXPECT_EQ(mats[0].alphaMode, AlphaMode::Mask) << "a texture's alpha cuts out, as map_Kd's does";
    EXPECT_TRUE(mats[0].bumpMap);
    EXPECT_FLOAT_EQ(mats[0].normalScale, 3.f);
    EXPECT_EQ(mats[1].alphaMode, AlphaMode::Blend);
    EXPECT_FLOAT_EQ(mats[1].opacity, 0.25f);
    EXPECT_EQ(mats[2].alphaMode, AlphaMode::Opaque);
}

TEST(JsonMaterials, MistakesAreErrorsNamingTheJsonPath) {
    const fs::path dir = test::tempDir();
    struct Case {
        const char* material;
        const char* path;
        const char* why;
    };
    const Case cases[] = {
        {R"({"model": "metal_roughness", "kd": 0.5})", "/materials/m/kd", "is a Phong key"},
        {R"({"base_color": [1, 1, 1]})", "/materials/m/base_color", "metal_roughness"},
        {R"({"model": "metal_roughness", "metallic": 2})", "/materials/m/metallic", "must lie in [0, 1]"},
        {R"({"model": "pbr"})", "/materials/m/model", "\"metal_roughness\""},
        {R"({"model": "metal_roughness", "base_color_texture": {"file": "base.png", "wrap": "tile"}})",
         "/materials/m/base_color_texture/wrap", "\"repeat\", \"clamp\" or \"mirror\""},
        {R"({"model": "metal_roughness", "roughness_texture": {"file": "mr.png", "channel": "x"}})",
         "/materials/m/roughness_texture/channel", "\"r\", \"g\", \"b\" or \"a\""},
        {R"({"model": "metal_roughness", "base_color_texture": {"file": "base.png", "uv_set": 2}})",
         "/materials/m/base_color_texture/uv_set", ""},
        {R"({"model": "metal_roughness", "base_color_texture": {"uv_set": 0}})", "/materials/m/base_color_texture", "file"},
        {R"({"normal_texture": "n.png", "bump_texture": "n.png"})", "/materials/m/bump_texture", "not both"},
        {R"({"alpha_mode": "sometimes"})", "/materials/m/alpha_mode", "\"opaque\", \"mask\" or \"blend\""},
        {R"({"alpha_cutoff": -0.5})", "/materials/m/alpha_cutoff", ""},
        {R"({"opacity": 1.5})", "/materials/m/opacity", "must lie in [0, 1]"}};
    for (const Case& c : cases) {
        const std::string e = errorIn(dir, std::string(R"({"materials": {"m": )") + c.material + "}}");
        EXPECT_NE(e.find("scene.json"), std::string::npos) << c.material << ": " << e;
        EXPECT_NE(e.find(c.path), std::string::npos) << c.material << ": " << e;
        EXPECT_NE(e.find(c.why), std::string::npos) << c.material << ": " << e;
    }
}

}  // namespace
}  // namespace penumbra
