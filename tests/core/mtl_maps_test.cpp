// MTL texture statements and PBR keys (core/io/mtl_materials.h,
// docs/mtl-mapping.md): map_Ke (with -mm), map_d and map_Kd's alpha, bump
// and norm (with -bm), Pr, Pm, map_Pr and map_Pm (with -imfchan, -o, -s,
// -clamp) into the material's slots; the Phong terms stay the MTL's.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "core/io/scene_loader.h"
#include "support/test_support.h"
#include "support/warning_log.h"

namespace penumbra {
namespace {
namespace fs = std::filesystem;

using Quiet = test::WarningLog;

const Material& named(const Scene& s, const std::string& name) {
    for (const Material& m : s.materials)
        if (m.name == name) return m;
    throw std::runtime_error("no material " + name);
}

/// An OBJ of one quad with uvs using each material of `mtl` once; the textures it names exist.
fs::path objWith(const fs::path& dir, const std::string& mtl, const std::vector<std::string>& materials) {
    for (const char* t : {"kd.png", "glow.png", "cut.png", "height.png", "normal.png", "rough.png", "metal.png"})
        test::writeFile(dir / t, "an image; not decoded when loading");
    test::writeFile(dir / "m.mtl", mtl);
    std::string obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n";
    for (const std::string& m : materials) obj += "usemtl " + m + "\nf 1/1/1 2/2/1 3/3/1 4/4/1\n";
    return test::writeFile(dir / "m.obj", obj);
}

TEST(MtlMaps, EmissionOpacityBumpAndNormalMaps) {
    const fs::path dir = test::tempDir();
    const fs::path obj = objWith(dir,
                                 "newmtl screen\nKd 0 0 0\nmap_Ke -mm 0 0.4 glow.png\n"
                                 "newmtl tinted\nKe 2 1 0.5\nmap_Ke glow.png\n"
                                 "newmtl leaf\nKd 0.5 0.5 0.5\nmap_Kd kd.png\nmap_d cut.png\n"
                                 "newmtl leafRed\nmap_d -imfchan r cut.png\n"
                                 "newmtl bumpy\nbump -bm 2.5 height.png\n"
                                 "newmtl normal\nnorm normal.png\n"
                                 "newmtl plain\nKd 0.5 0.5 0.5\n",
                                 {"screen", "tinted", "leaf", "leafRed", "bumpy", "normal", "plain"});
    Quiet q;
    const LoadedScene s = loadScene(obj, {}, q.logger);
    EXPECT_TRUE(q.warnings.empty()) << q.warnings.front();
    // map_Ke with no Ke: the map is the emission (Ke 1), times -mm's gain.
    const Material& screen = named(s.scene, "screen");
    EXPECT_FLOAT_EQ(screen.ke.r, 0.4f);
    ASSERT_TRUE(screen.emissiveMap.used());
    EXPECT_EQ(fs::path(screen.emissiveTexture.path).filename(), "glow.png");
    EXPECT_EQ(s.scene.textures[size_t(screen.emissiveMap.texture)].colorSpace, TextureColorSpace::FromFile);
    const Material& tinted = named(s.scene, "tinted");
    EXPECT_FLOAT_EQ(tinted.ke.r, 2.f);
    EXPECT_EQ(tinted.emissiveMap.texture, screen.emissiveMap.texture) << "one file, one texture";
    // map_d: the matte channel (alpha, or the grey of an image without one) cuts out; so does map_Kd's alpha.
    const Material& leaf = named(s.scene, "leaf");
    EXPECT_EQ(leaf.alphaMode, AlphaMode::Mask);
    EXPECT_FLOAT_EQ(leaf.alphaCutoff, 0.5f);
    ASSERT_TRUE(leaf.opacityMap.used());
    EXPECT_EQ(leaf.opacityMap.channel, 3);
    EXPECT_EQ(s.scene.textures[size_t(leaf.opacityMap.texture)].colorSpace, TextureColorSpace::Linear);
    EXPECT_GE(leaf.textureIndex, 0);
    EXPECT_EQ(named(s.scene, "leafRed").opacityMap.channel, 0);
    EXPECT_EQ(named(s.scene, "plain").alphaMode, AlphaMode::Opaque);
    // bump: a height map scaled by -bm; norm: a tangent-space normal map.
    const Material& bumpy = named(s.scene, "bumpy");
    ASSERT_TRUE(bumpy.normalMap.used());
    EXPECT_TRUE(bumpy.bumpMap);
    EXPECT_FLOAT_EQ(bumpy.normalScale, 2.5f);
    EXPECT_EQ(s.scene.textures[size_t(bumpy.normalMap.texture)].colorSpace, TextureColorSpace::Linear);
    const Material& normal = named(s.scene, "normal");
    ASSERT_TRUE(normal.normalMap.used());
    EXPECT_FALSE(normal.bumpMap);
    EXPECT_TRUE(normal.needsTangents());
    EXPECT_EQ(named(s.scene, "plain").kind, MaterialKind::Phong);
}

TEST(MtlMaps, PbrKeysMakeAMetalRoughnessMaterialWithTheirMaps) {
    const fs::path dir = test::tempDir();
    const fs::path obj = objWith(dir,
                                 "newmtl brass\nKd 0.8 0.6 0.2\nKs 0.5 0.5 0.5\nNs 98\nmap_Kd kd.png\nPm 1\n"
                                 "map_Pr -imfchan g -o 0.5 0.25 0 -s 2 4 1 -clamp on rough.png\nmap_Pm metal.png\n"
                                 "newmtl rough\nKd 0.2 0.2 0.2\nPr 0.3\n",
                                 {"brass", "rough"});
    Quiet q;
    const LoadedScene s = loadScene(obj, {}, q.logger);
    EXPECT_TRUE(q.warnings.empty()) << q.warnings.front();
    const Material& brass = named(s.scene, "brass");
    EXPECT_EQ(brass.kind, MaterialKind::MetalRoughness);
    EXPECT_FLOAT_EQ(brass.baseColor.r, 0.8f);
    EXPECT_FLOAT_EQ(brass.metallic, 1.f);
    EXPECT_FLOAT_EQ(brass.roughness, 1.f) << "a map without its factor has the factor 1";
    EXPECT_EQ(brass.baseColorMap.texture, brass.textureIndex);
    // The Phong terms stay the MTL's (the metal-roughness BSDF ignores them).
    EXPECT_FLOAT_EQ(brass.kd.r, 0.8f);
    EXPECT_FLOAT_EQ(brass.ks.r, 0.5f);
    EXPECT_FLOAT_EQ(brass.exponent, 98.f);
    ASSERT_TRUE(brass.roughnessMap.used());
    EXPECT_EQ(brass.roughnessMap.channel, 1);
    EXPECT_EQ(brass.metallicMap.channel, 3);  // the matte channel by default
    EXPECT_EQ(s.scene.textures[size_t(brass.roughnessMap.texture)].colorSpace, TextureColorSpace::Linear);
    EXPECT_EQ(brass.roughnessMap.wrapS, TextureWrap::ClampToEdge);
    EXPECT_EQ(brass.roughnessMap.wrapT, TextureWrap::ClampToEdge);
    // -o 0.5 0.25 -s 2 4 act on (u, v): u' = 2 u + 0.5, v' = 4 v + 0.25, in image coordinates t' = 1 - v'.
    for (const Vec2f uv : {Vec2f{0.f, 0.f}, Vec2f{0.25f, 0.75f}}) {
        const Vec2f st = brass.roughnessMap.imageCoordinates(uv);
        EXPECT_NEAR(st.x, 2.f * uv.x + 0.5f, 1e-6f);
        EXPECT_NEAR(st.y, 1.f - (4.f * uv.y + 0.25f), 1e-6f);
    }
    // Pr alone: no metal (Pm absent is 0).
    const Material& rough = named(s.scene, "rough");
    EXPECT_EQ(rough.kind, MaterialKind::MetalRoughness);
    EXPECT_FLOAT_EQ(rough.roughness, 0.3f);
    EXPECT_FLOAT_EQ(rough.metallic, 0.f);

    // Pm without Pr: the roughness of the Phong lobe, sqrt(alpha) with alpha^2 = 2 / (Ns + 2).
    const fs::path pm = objWith(dir, "newmtl metal\nNs 98\nPm 0.5\n", {"metal"});
    const LoadedScene p = loadScene(pm, {}, q.logger);
    EXPECT_NEAR(named(p.scene, "metal").roughness, std::pow(2.f / 100.f, 0.25f), 1e-6f);
    EXPECT_FLOAT_EQ(named(p.scene, "metal").metallic, 0.5f);
}

TEST(MtlMaps, AMissingMapIsOneWarningAndTheMaterialGoesWithoutIt) {
    const fs::path dir = test::tempDir();
    const fs::path obj = objWith(dir, "newmtl a\nmap_Ke absent.png\nnorm absent.png\n", {"a"});
    Quiet q;
    const LoadedScene s = loadScene(obj, {}, q.logger);
    ASSERT_EQ(q.warnings.size(), 1u);
    EXPECT_NE(q.warnings[0].find("m.mtl: material 'a': texture 'absent.png' not found"), std::string::npos) << q.warnings[0];
    EXPECT_NE(q.warnings[0].find("rendering without it"), std::string::npos) << q.warnings[0];
    const Material& a = named(s.scene, "a");
    EXPECT_FALSE(a.emissiveMap.used());
    EXPECT_FALSE(a.normalMap.used());
    EXPECT_TRUE(a.emissiveTexture.path.empty());
    EXPECT_FALSE(a.isEmissive()) << "the Ke 1 of map_Ke goes with the map";
}

}  // namespace
}  // namespace penumbra
