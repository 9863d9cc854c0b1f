// The glTF reader (core/io/gltf_loader.h) on files the tests write: every
// material channel (factors, textures, uv sets, samplers, transforms),
// emissive strength, images inside GLB buffers and data: URIs decoded to
// their pixels, tangents read and made, alpha, and bad input: undecodable
// and oversized images, a bad alphaCutoff, a missing tangent frame, deep and
// looping node graphs, count and expansion bombs, malformed containers, and
// the restricted-path policy for every image byte read.
#include <gtest/gtest.h>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/io/scene_loader.h"
#include "core/texture_cache.h"
#include "support/gltf_builder.h"
#include "support/test_support.h"
#include "support/warning_log.h"

namespace penumbra {
namespace {
namespace fs = std::filesystem;
using test::GltfBuilder;
using Json = GltfBuilder::Json;

using Quiet = test::WarningLog;

/// A PNG of w x h pixels of `channels` 8-bit channels (rows top first), as bytes.
std::string png(int w, int h, int channels, const std::vector<unsigned char>& px) {
    OIIO::Filesystem::IOVecOutput memory;
    auto out = OIIO::ImageOutput::create("png");
    OIIO::ImageSpec spec(w, h, channels, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:UnassociatedAlpha", 1);  // the alpha as given, not divided out of the colour
    if (!out || !out->set_ioproxy(&memory) || !out->open("memory.png", spec) ||
        !out->write_image(OIIO::TypeDesc::UINT8, px.data()))
        return {};
    out->close();
    return std::string(memory.buffer().begin(), memory.buffer().end());
}

LoadedScene load(const fs::path& file, Quiet& q, const LoadOptions& options = {}) { return loadScene(file, options, q.logger); }

std::string errorOf(const fs::path& file, const LoadOptions& options = {}) {
    Quiet q;
    try {
        load(file, q, options);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

/// The material of the first mesh.
const Material& firstMaterial(const LoadedScene& s) { return s.scene.materials.at(s.scene.meshes.at(0).material); }

float srgb(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

TEST(Gltf, FactorsAndEveryTextureChannelWithUvSetsSamplersAndTransforms) {
    const fs::path dir = test::tempDir();
    for (const char* name : {"base.png", "mr.png", "normal.png", "emissive.png", "transmission.png"})
        test::writeFile(dir / name, png(1, 1, 3, {10, 20, 30}));
    GltfBuilder g;
    g.doc["samplers"] = Json::array({{{"wrapS", 33071}, {"wrapT", 33648}, {"magFilter", 9728}}});
    const int base = g.textureFile("base.png", 0), mr = g.textureFile("mr.png"), normal = g.textureFile("normal.png"),
              emissive = g.textureFile("emissive.png"), transmission = g.textureFile("transmission.png");
    Json m{{"name", "everything"},
           {"pbrMetallicRoughness",
            {{"baseColorFactor", {0.5, 0.25, 1.0, 0.75}},
             {"metallicFactor", 0.2},
             {"roughnessFactor", 0.6},
             {"baseColorTexture", {{"index", base}, {"texCoord", 1}}},
             {"metallicRoughnessTexture", {{"index", mr}}}}},
           {"normalTexture", {{"index", normal}, {"scale", 0.5}}},
           {"emissiveTexture",
            {{"index", emissive},
             {"extensions",
              {{"KHR_texture_transform", {{"offset", {0.5, 0.25}}, {"rotation", kPi / 2}, {"scale", {2, 3}}, {"texCoord", 1}}}}}}},
           {"emissiveFactor", {1.0, 0.5, 0.25}},
           {"alphaMode", "MASK"},
           {"alphaCutoff", 0.3},
           {"doubleSided", true},
           {"extensions",
            {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}},
             {"KHR_materials_transmission", {{"transmissionFactor", 0.5}, {"transmissionTexture", {{"index", transmission}}}}},
             {"KHR_materials_ior", {{"ior", 1.33}}}}}};
    Json prim = g.quad();
    prim["material"] = g.material(m);
    g.node(Json::array({prim}));
    test::writeFile(dir / "m.gltf", g.gltf());
    Quiet q;
    const LoadedScene s = load(dir / "m.gltf", q);
    EXPECT_TRUE(q.warnings.empty()) << q.warnings.front();
    const Material& mat = firstMaterial(s);
    EXPECT_EQ(mat.name, "everything");
    EXPECT_EQ(mat.kind, MaterialKind::MetalRoughness);
    EXPECT_FLOAT_EQ(mat.baseColor.r, 0.5f);
    EXPECT_FLOAT_EQ(mat.baseColor.g, 0.25f);
    EXPECT_FLOAT_EQ(mat.opacity, 0.75f);
    EXPECT_FLOAT_EQ(mat.metallic, 0.2f);
    EXPECT_FLOAT_EQ(mat.roughness, 0.6f);
    EXPECT_FLOAT_EQ(mat.ke.r, 4.f);
    EXPECT_FLOAT_EQ(mat.ke.g, 2.f);
    EXPECT_FLOAT_EQ(mat.ke.b, 1.f);
    EXPECT_TRUE(mat.twoSidedEmission);
    EXPECT_EQ(mat.alphaMode, AlphaMode::Mask);
    EXPECT_FLOAT_EQ(mat.alphaCutoff, 0.3f);
    EXPECT_FLOAT_EQ(mat.transmission, 0.5f);
    EXPECT_FLOAT_EQ(mat.ior, 1.33f);
    EXPECT_FLOAT_EQ(mat.normalScale, 0.5f);

    // Base colour: sRGB, uv set 1, the sampler's clamp / mirror wrap and nearest filter.
    ASSERT_TRUE(mat.baseColorMap.used());
    EXPECT_EQ(mat.baseColorMap.uvSet, 1);
    EXPECT_EQ(mat.baseColorMap.wrapS, TextureWrap::ClampToEdge);
    EXPECT_EQ(mat.baseColorMap.wrapT, TextureWrap::MirroredRepeat);
    EXPECT_EQ(mat.baseColorMap.filter, TextureFilter::Nearest);
    const auto& tex = s.scene.textures;
    EXPECT_EQ(tex[size_t(mat.baseColorMap.texture)].colorSpace, TextureColorSpace::Srgb);
    EXPECT_EQ(fs::path(mat.baseColorTexture.path).filename(), "base.png");
    // Metallic-roughness: one linear image, B = metal, G = roughness; the sampler defaults (repeat, linear).
    ASSERT_TRUE(mat.metallicMap.used());
    EXPECT_EQ(mat.metallicMap.texture, mat.roughnessMap.texture);
    EXPECT_EQ(mat.metallicMap.channel, 2);
    EXPECT_EQ(mat.roughnessMap.channel, 1);
    EXPECT_EQ(mat.metallicMap.wrapS, TextureWrap::Repeat);
    EXPECT_EQ(mat.metallicMap.filter, TextureFilter::Linear);
    EXPECT_EQ(tex[size_t(mat.metallicMap.texture)].colorSpace, TextureColorSpace::Linear);
    EXPECT_EQ(tex[size_t(mat.normalMap.texture)].colorSpace, TextureColorSpace::Linear);
    EXPECT_EQ(tex[size_t(mat.transmissionMap.texture)].colorSpace, TextureColorSpace::Linear);
    EXPECT_EQ(mat.transmissionMap.channel, 0);
    // Emissive: sRGB, KHR_texture_transform's texCoord, and T * R * S as one map of (s, t).
    ASSERT_TRUE(mat.emissiveMap.used());
    EXPECT_EQ(tex[size_t(mat.emissiveMap.texture)].colorSpace, TextureColorSpace::Srgb);
    EXPECT_EQ(mat.emissiveMap.uvSet, 1);
    const float expected[6] = {0.f, 3.f, 0.5f, -2.f, 0.f, 0.25f};  // cos 90 = 0, sin 90 = 1
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(mat.emissiveMap.m[i], expected[i], 1e-6f) << i;
    EXPECT_FLOAT_EQ(mat.emissiveTexture.rotation, float(kPi / 2));

    // Transmission makes the smooth dielectric over a diffuse part (mapTransmissionOntoGlass).
    EXPECT_NEAR(mat.kd.r, 0.8f * 0.6f * 0.96f * 0.5f, 1e-6f);  // (1 - metallic)(1 - transmitted)(1 - 4%) base
    EXPECT_EQ(mat.textureIndex, mat.baseColorMap.texture);
    EXPECT_NEAR(mat.kt.r, 0.4f * 0.5f, 1e-6f);                 // transmission * (1 - metallic) * base
}

TEST(Gltf, ImagesInGlbBuffersAndDataUrisDecodeToTheirPixels) {
    const fs::path dir = test::tempDir();
    // 2 x 1 RGBA: opaque red, half-transparent blue; and a grey for the linear channels.
    const std::string rgba = png(2, 1, 4, {255, 0, 0, 255, 0, 0, 255, 128});
    const std::string grey = png(1, 1, 1, {128});
    GltfBuilder g;
    const int inBuffer = g.textureBytes(rgba), inUri = g.textureDataUri(grey);
    Json prim = g.quad();
    prim["material"] = g.material({{"pbrMetallicRoughness",
                                    {{"baseColorTexture", {{"index", inBuffer}}}, {"metallicRoughnessTexture", {{"index", inUri}}}}},
                                   {"emissiveTexture", {{"index", inUri}}},
                                   {"alphaMode", "BLEND"}});
    g.node(Json::array({prim}));
    for (const char* name : {"m.glb", "m.gltf"}) {
        SCOPED_TRACE(name);
        test::writeFile(dir / name, std::string(name) == "m.glb" ? g.glb() : g.gltf());
        Quiet q;
        const LoadedScene s = load(dir / name, q);
        EXPECT_TRUE(q.warnings.empty()) << q.warnings.front();
        const Material& m = firstMaterial(s);
        EXPECT_EQ(m.alphaMode, AlphaMode::Blend);
        ASSERT_TRUE(m.baseColorMap.used());
        const TextureSource& image = s.scene.textures[size_t(m.baseColorMap.texture)];
        EXPECT_EQ(image.name, (dir / name).string() + "#image0.png");
        ASSERT_NE(image.bytes, nullptr);
        EXPECT_EQ(image.fd, -1);

        TextureCache cache(s.scene.textures, q.logger);
        EXPECT_TRUE(q.warnings.empty()) << q.warnings.front();
        // Texel centres: s = 0.25 and 0.75 (uv's v up, so t = 1 - v).
        const Rgba left = cache.sample(m.baseColorMap, {0.25f, 0.5f}, 0.f), right = cache.sample(m.baseColorMap, {0.75f, 0.5f}, 0.f);
        EXPECT_NEAR(left.rgb.r, 1.f, 1e-5f);
        EXPECT_NEAR(left.rgb.b, 0.f, 1e-5f);
        EXPECT_NEAR(left.a, 1.f, 1e-5f);
        EXPECT_NEAR(right.rgb.b, 1.f, 1e-5f);
        EXPECT_NEAR(right.a, 128.f / 255.f, 1e-5f);  // alpha is never sRGB-decoded
        EXPECT_TRUE(cache.hasTransparency(m.baseColorMap.texture));
        // The same grey image: linear for metallic-roughness, sRGB for emission.
        EXPECT_NEAR(cache.sampleChannel(m.metallicMap, {0.5f, 0.5f}, 0.f), 128.f / 255.f, 1e-5f);
        EXPECT_NEAR(cache.sample(m.emissiveMap, {0.5f, 0.5f}, 0.f).rgb.g, srgb(128.f / 255.f), 1e-5f);
        EXPECT_NE(m.metallicMap.texture, m.emissiveMap.texture) << "one image, two colour spaces: two textures";
    }
}

TEST(Gltf, EmissiveStrengthScalesTheEmissionOneToSixteen) {
    const fs::path dir = test::tempDir();
    GltfBuilder g;
    Json prims = Json::array();
    for (int strength : {1, 2, 4, 8, 16}) {
        Json prim = g.quad();
        prim["material"] = g.material({{"emissiveFactor", {0.1, 0.5, 0.9}},
                                       {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", strength}}}}}});
        prims.push_back(prim);
    }
    g.node(prims);
    test::writeFile(dir / "e.glb", g.glb());
    Quiet q;
    const LoadedScene s = load(dir / "e.glb", q);
    ASSERT_EQ(s.scene.meshes.size(), 5u);
    for (size_t i = 0; i < 5; ++i) {
        const Material& m = s.scene.materials[s.scene.meshes[i].material];
        EXPECT_FLOAT_EQ(m.ke.b, 0.9f * float(1 << i)) << i;
        EXPECT_FLOAT_EQ(m.ke.r / m.ke.b, 0.1f / 0.9f) << i;
    }
}

TEST(SharedScenes, EmissiveStrengthTestCubesLoadWithRatiosOneToSixteen) {
    const fs::path file = test::sharedScenePath("khronos_gltf/EmissiveStrengthTest/glTF-Binary/EmissiveStrengthTest.glb");
    if (file.empty()) GTEST_SKIP() << "../shared/scenes not present";
    Quiet q;
    const LoadedScene s = load(file, q);
    float emit1 = 0.f;
    std::map<int, float> blue;
    for (const Material& m : s.scene.materials)
        if (m.name.rfind("Emit", 0) == 0) blue[std::stoi(m.name.substr(4))] = m.ke.b;
    ASSERT_EQ(blue.size(), 5u);
    emit1 = blue[1];
    EXPECT_FLOAT_EQ(emit1, 0.9f);
    for (int k : {2, 4, 8, 16}) EXPECT_FLOAT_EQ(blue[k] / emit1, float(k)) << k;
}

TEST(Gltf, TangentsAreReadOrMadeFromTheUvsAndFollowMirroring) {
    const fs::path dir = test::tempDir();
    test::writeFile(dir / "n.png", png(1, 1, 3, {128, 128, 255}));
    GltfBuilder g;
    const int normal = g.textureFile("n.png");
    const int mapped = g.material({{"normalTexture", {{"index", normal}}}});
    // 1: the file's tangents (-y, w = -1); 2: none, made from TEXCOORD_0; 3: the same mirrored in x.
    Json withTangents = g.quad();
    withTangents["attributes"]["TANGENT"] = g.floats({0, -1, 0, -1, 0, -1, 0, -1, 0, -1, 0, -1, 0, -1, 0, -1}, 4);
    withTangents["material"] = mapped;
    g.node(Json::array({withTangents}), {{"name", "read"}});
    Json made = g.quad();
    made["material"] = mapped;
    g.node(Json::array({made}), {{"name", "made"}});
    g.node(Json::array({made}), {{"name", "mirrored"}, {"scale", {-1, 1, 1}}});
    test::writeFile(dir / "t.gltf", g.gltf());
    Quiet q;
    const LoadedScene s = load(dir / "t.gltf", q);
    EXPECT_TRUE(q.warnings.empty()) << q.warnings.front();
    ASSERT_EQ(s.scene.meshes.size(), 3u);
    for (const TriangleMesh& m : s.scene.meshes) ASSERT_EQ(m.tangents.size(), m.positions.size()) << m.name;
    const Tangent& read = s.scene.meshes[0].tangents[0];
    EXPECT_NEAR(read.direction.y, -1.f, 1e-6f);
    EXPECT_EQ(read.sign, -1.f);
    // Made: dp/du is +x, and +v (up the image) is +y = cross(+z, +x): sign +1.
    const Tangent& made0 = s.scene.meshes[1].tangents[0];
    EXPECT_NEAR(made0.direction.x, 1.f, 1e-6f);
    EXPECT_EQ(made0.sign, 1.f);
    // Mirrored in x: dp/du is -x, the normal still +z, dp/dv still +y: cross(+z, -x) = -y, sign -1.
    const Tangent& mirrored = s.scene.meshes[2].tangents[0];
    EXPECT_NEAR(mirrored.direction.x, -1.f, 1e-6f);
    EXPECT_EQ(mirrored.sign, -1.f);
}

// Scene::completeHit computes neither tangents nor the second uv set; a
// material that needs them asks for them from the hit (Scene::tangentAt, uv1At).
TEST(Gltf, HitsGiveTheirTangentAndSecondUvSetOnDemand) {
    const fs::path dir = test::tempDir();
    test::writeFile(dir / "n.png", png(1, 1, 3, {128, 128, 255}));
    GltfBuilder g;
    Json prim = g.quad();
    prim["material"] = g.material({{"normalTexture", {{"index", g.textureFile("n.png")}, {"texCoord", 1}}}});
    g.node(Json::array({prim}), {{"rotation", {0, 0, 0.7071068, 0.7071068}}});  // turned 90 degrees about +z
    test::writeFile(dir / "t.gltf", g.gltf());
    Quiet q;
    LoadedScene s = load(dir / "t.gltf", q);
    s.scene.finalize(q.logger);
    // A ray down -z onto triangle 0 (corners 0, 1, 2) at barycentrics (0.25, 0.5).
    const TriangleMesh& m = s.scene.meshes.at(0);
    const float u = 0.25f, v = 0.5f;
    const Vec3f p = (1 - u - v) * m.positions[m.indices[0]] + u * m.positions[m.indices[1]] + v * m.positions[m.indices[2]];
    const Ray ray{p + Vec3f{0, 0, 1}, {0, 0, -1}, 0.f, kInfinity};
    const Hit h = s.scene.completeHit(ray, PrimRef{ShapeKind::Mesh, 0, 0, 0}, 1.f, u, v);
    const Vec2f uv1 = s.scene.uv1At(h);
    const auto at = [&](const std::vector<Vec2f>& a, int c) {
        return (1 - u - v) * (c ? a[m.indices[0]].y : a[m.indices[0]].x) + u * (c ? a[m.indices[1]].y : a[m.indices[1]].x) +
               v * (c ? a[m.indices[2]].y : a[m.indices[2]].x);
    };
    EXPECT_NEAR(uv1.x, at(m.uvs1, 0), 1e-5f);
    EXPECT_NEAR(uv1.y, at(m.uvs1, 1), 1e-5f);
    // The quad's +u now runs along +y (turned about +z): so does its tangent, and +v along -x.
    const Tangent t = s.scene.tangentAt(h, 1);
    EXPECT_NEAR(t.direction.y, 1.f, 1e-5f);
    EXPECT_EQ(t.sign, 1.f);
    EXPECT_NEAR(dot(t.direction, h.ns), 0.f, 1e-6f);
}

TEST(Gltf, ANormalMapWithoutItsUvSetWarnsAndIsDroppedThereNotAFailure) {
    const fs::path dir = test::tempDir();
    test::writeFile(dir / "n.png", png(1, 1, 3, {128, 128, 255}));
    GltfBuilder g;
    const int normal = g.textureFile("n.png");
    Json prim = g.quad();
    prim["attributes"].erase("TEXCOORD_1");
    prim["material"] = g.material({{"name", "bumpy"}, {"normalTexture", {{"index", normal}, {"texCoord", 1}}}});
    g.node(Json::array({prim}), {{"name", "plate"}});
    test::writeFile(dir / "t.gltf", g.gltf());
    Quiet q;
    const LoadedScene s = load(dir / "t.gltf", q);
    ASSERT_EQ(q.warnings.size(), 1u);
    EXPECT_NE(q.warnings[0].find((dir / "t.gltf").string()), std::string::npos) << q.warnings[0];
    EXPECT_NE(q.warnings[0].find("no TEXCOORD_1 for material 'bumpy'"), std::string::npos) << q.warnings[0];
    EXPECT_NE(q.warnings[0].find("no tangent frame"), std::string::npos) << q.warnings[0];
    EXPECT_FALSE(firstMaterial(s).needsTangents());
    EXPECT_TRUE(s.scene.meshes[0].tangents.empty());
}

TEST(Gltf, AlphaModesAndABadAlphaCutoff) {
    const fs::path dir = test::tempDir();
    GltfBuilder g;
    Json prims = Json::array();
    for (const Json& m : {Json{{"alphaMode", "OPAQUE"}}, Json{{"alphaMode", "MASK"}, {"alphaCutoff", 0.25}},
                          Json{{"alphaMode", "BLEND"}}, Json{{"name", "bad"}, {"alphaMode", "MASK"}, {"alphaCutoff", -1}},
                          Json{{"alphaMode", "SOMETIMES"}}}) {
        Json prim = g.quad();
        prim["material"] = g.material(m);
        prims.push_back(prim);
    }
    g.node(prims);
    test::writeFile(dir / "a.gltf", g.gltf());
    Quiet q;
    const LoadedScene s = load(dir / "a.gltf", q);
    auto mat = [&](size_t i) { return s.scene.materials[s.scene.meshes.at(i).material]; };
    EXPECT_EQ(mat(0).alphaMode, AlphaMode::Opaque);
    EXPECT_EQ(mat(1).alphaMode, AlphaMode::Mask);
    EXPECT_FLOAT_EQ(mat(1).alphaCutoff, 0.25f);
    EXPECT_EQ(mat(2).alphaMode, AlphaMode::Blend);
    EXPECT_EQ(mat(3).alphaMode, AlphaMode::Mask);
    EXPECT_FLOAT_EQ(mat(3).alphaCutoff, 0.5f);
    EXPECT_EQ(mat(4).alphaMode, AlphaMode::Opaque);
    ASSERT_EQ(q.warnings.size(), 2u);
    EXPECT_NE(q.warnings[0].find((dir / "a.gltf").string() + ": materials[3] 'bad': alphaCutoff -1"), std::string::npos)
        << q.warnings[0];
    EXPECT_NE(q.warnings[1].find("alphaMode \"SOMETIMES\""), std::string::npos) << q.warnings[1];
}

TEST(Gltf, UndecodableAndOverBudgetImagesAreWarningsNamingThem) {
    const fs::path dir = test::tempDir();
    GltfBuilder g;
    const int junk = g.textureBytes("not a PNG at all");
    const int big = g.textureBytes(png(64, 64, 3, std::vector<unsigned char>(64 * 64 * 3, 200)));
    Json prim = g.quad();
    prim["material"] = g.material({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", junk}}}}},
                                   {"emissiveTexture", {{"index", big}}}});
    g.node(Json::array({prim}));
    test::writeFile(dir / "bad.glb", g.glb());
    Quiet q;
    const LoadedScene s = load(dir / "bad.glb", q);
    EXPECT_TRUE(q.warnings.empty()) << q.warnings.front();  // not decoded when loading
    // A budget that a 64 x 64 RGB image with its MIP levels (16 KiB) does not fit.
    TextureCache cache(s.scene.textures, q.logger, TextureBudget{8u << 10});
    ASSERT_EQ(q.warnings.size(), 2u);
    EXPECT_NE(q.warnings[0].find((dir / "bad.glb").string() + "#image0.png: cannot read texture"), std::string::npos)
        << q.warnings[0];
    EXPECT_NE(q.warnings[1].find((dir / "bad.glb").string() + "#image1.png: cannot read texture"), std::string::npos)
        << q.warnings[1];
    EXPECT_NE(q.warnings[1].find("texture budget"), std::string::npos) << q.warnings[1];
    const Material& m = firstMaterial(s);
    EXPECT_FALSE(cache.enabled(m.baseColorMap.texture));
    EXPECT_FALSE(cache.enabled(m.emissiveMap.texture));
    EXPECT_NEAR(cache.sample(m.baseColorMap, {0.5f, 0.5f}, 0.f).rgb.r, 1.f, 0.f);  // rendered without it
}

TEST(Gltf, ADeepNodeChainLoadsAndALoopIsCutWithAWarning) {
    const fs::path dir = test::tempDir();
    GltfBuilder g;
    const int leaf = g.node(Json::array({g.quad()}));
    g.doc["scenes"][0]["nodes"] = Json::array();
    // 20,000 nodes, each the only child of the next; the scene holds the outermost.
    for (int i = 0; i < 20000; ++i) g.doc["nodes"].push_back({{"children", {leaf + i}}, {"translation", {0.001, 0, 0}}});
    g.doc["scenes"][0]["nodes"] = {int(g.doc["nodes"].size() - 1)};
    test::writeFile(dir / "deep.glb", g.glb());
    Quiet q;
    const LoadedScene deep = load(dir / "deep.glb", q);
    EXPECT_EQ(deep.scene.triangleCount(), 2u);
    EXPECT_NEAR(deep.scene.bounds().center().x, 20.f, 1e-2f);
    EXPECT_TRUE(q.warnings.empty());

    // Node 0 holds node 1, which holds node 0 again.
    GltfBuilder loop;
    loop.node(Json::array({loop.quad()}), {{"children", {1}}});
    loop.doc["nodes"].push_back({{"children", {0}}});
    test::writeFile(dir / "loop.gltf", loop.gltf());
    Quiet l;
    EXPECT_EQ(load(dir / "loop.gltf", l).scene.triangleCount(), 2u);
    ASSERT_EQ(l.warnings.size(), 1u);
    EXPECT_NE(l.warnings[0].find("reach a node a second time"), std::string::npos) << l.warnings[0];
}

TEST(Gltf, SparseAccessorsReplaceTheirElements) {
    const fs::path dir = test::tempDir();
    GltfBuilder g;
    Json prim = g.quad();
    // Vertex 2 moves from (1, 1, 0) to (1, 3, 0) through a sparse part.
    const int pos = prim["attributes"]["POSITION"];
    const uint32_t index = 2;
    const float value[3] = {1, 3, 0};
    g.doc["accessors"][size_t(pos)]["sparse"] = {
        {"count", 1},
        {"indices", {{"bufferView", g.view(std::string(reinterpret_cast<const char*>(&index), 4))}, {"componentType", 5125}}},
        {"values", {{"bufferView", g.view(std::string(reinterpret_cast<const char*>(value), 12))}}}};
    g.node(Json::array({prim}));
    test::writeFile(dir / "s.gltf", g.gltf());
    Quiet q;
    const LoadedScene s = load(dir / "s.gltf", q);
    EXPECT_FLOAT_EQ(s.scene.bounds().hi.y, 3.f);
    // A sparse index past the accessor's count is an error naming the file.
    g.doc["accessors"][size_t(pos)]["sparse"]["indices"]["bufferView"] =
        g.view(std::string("\x09\0\0\0", 4));
    test::writeFile(dir / "far.gltf", g.gltf());
    const std::string e = errorOf(dir / "far.gltf");
    EXPECT_NE(e.find((dir / "far.gltf").string() + ": cannot read as glTF: accessors["), std::string::npos) << e;
    EXPECT_NE(e.find("sparse.indices holds an index past the accessor's count"), std::string::npos) << e;
}

TEST(Gltf, CountAndExpansionBombsAreRefusedBeforeAnythingIsMade) {
    const fs::path dir = test::tempDir();
    // An accessor with no buffer view claiming a billion zero vertices (from 200 bytes of JSON).
    GltfBuilder g;
    g.doc["accessors"] = Json::array({{{"componentType", 5126}, {"count", 1000000000}, {"type", "VEC3"}}});
    g.node(Json::array({{{"attributes", {{"POSITION", 0}}}}}));
    test::writeFile(dir / "count.gltf", g.gltf());
    std::string e = errorOf(dir / "count.gltf");
    EXPECT_NE(e.find("accessors[0] has no bufferView and claims 1000000000 elements"), std::string::npos) << e;

    // 3,500 nodes drawing one mesh of 65,535 vertices and 21,845 triangles: 3.1e8 from 50 KB.
    GltfBuilder many;
    many.doc["accessors"] = Json::array({{{"componentType", 5126}, {"count", 65535}, {"type", "VEC3"}}});
    many.node(Json::array({{{"attributes", {{"POSITION", 0}}}}}));
    for (int i = 1; i < 3500; ++i) {
        many.doc["nodes"].push_back({{"mesh", 0}});
        many.doc["scenes"][0]["nodes"].push_back(i);
    }
    test::writeFile(dir / "many.gltf", many.gltf());
    e = errorOf(dir / "many.gltf");
    EXPECT_NE(e.find((dir / "many.gltf").string() + ": its nodes place more than 268435456 vertices and triangles"),
              std::string::npos)
        << e;
}

TEST(Gltf, MalformedContainersAndUnreadableDocumentsAreErrorsNamingTheFile) {
    const fs::path dir = test::tempDir();
    GltfBuilder g;
    g.node(Json::array({g.quad()}));
    const std::string glb = g.glb();
    struct Case {
        const char* name;
        std::string bytes;
        const char* why;
    };
    std::string longBin = glb;
    const uint32_t jsonLength = *reinterpret_cast<const uint32_t*>(glb.data() + 12);
    const uint32_t claimed = uint32_t(glb.size() - 20 - jsonLength - 8 + 4);  // 4 bytes past the end
    std::memcpy(longBin.data() + 20 + jsonLength, &claimed, 4);
    std::string version1 = glb;
    version1[4] = 1;
    Json v1 = g.doc;
    v1["asset"]["version"] = "1.0";
    Json draco = g.doc;
    draco["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    std::string nested = R"({"asset": {"version": "2.0"}, "extras": )" + std::string(1000, '[') + std::string(1000, ']') + "}";
    const Case cases[] = {
        {"long_bin.glb", longBin, "the chunk after the JSON is not a BIN chunk inside the file"},
        {"version1.glb", version1, "binary glTF version 1 (only glTF 2.0 is read)"},
        {"short.glb", glb.substr(0, 16), "a binary glTF is at least 20 bytes long"},
        {"v1.gltf", v1.dump(), "asset.version is \"1.0\" (only glTF 2.0 is read)"},
        {"draco.gltf", draco.dump(), "it requires the extension KHR_draco_mesh_compression"},
        {"nested.gltf", nested, "its JSON nests arrays and objects more than 256 deep"}};
    for (const Case& c : cases) {
        test::writeFile(dir / c.name, c.bytes);
        const std::string err = errorOf(dir / c.name);
        EXPECT_NE(err.find((dir / c.name).string() + ": cannot read as glTF: "), std::string::npos) << c.name << ": " << err;
        EXPECT_NE(err.find(c.why), std::string::npos) << c.name << ": " << err;
    }
}

TEST(Gltf, TexCoordsFollowTheScenesConventionAndStripsAndFansAreTriangles) {
    const fs::path dir = test::tempDir();
    GltfBuilder g;
    Json list = g.quad();
    Json strip = g.quad(), fan = g.quad();
    strip["indices"] = g.indices({0, 1, 3, 2});  // (0 1 3), then (1 2 3): every other one turned
    strip["mode"] = 5;
    fan["indices"] = g.indices({0, 1, 2, 3});  // (1 2 0), (2 3 0)
    fan["mode"] = 6;
    Json points = g.quad();
    points["mode"] = 0;
    g.node(Json::array({list, strip, fan, points}));
    test::writeFile(dir / "p.gltf", g.gltf());
    Quiet q;
    const LoadedScene s = load(dir / "p.gltf", q);
    ASSERT_EQ(s.scene.meshes.size(), 3u) << "points are not a surface";
    // glTF's (u, v) = (0, 1) (the bottom-left corner) is the scene's (0, 0): v up.
    EXPECT_FLOAT_EQ(s.scene.meshes[0].uvs[0].x, 0.f);
    EXPECT_FLOAT_EQ(s.scene.meshes[0].uvs[0].y, 0.f);
    EXPECT_FLOAT_EQ(s.scene.meshes[0].uvs1[0].y, -1.f);
    for (const TriangleMesh& m : s.scene.meshes) {
        ASSERT_EQ(m.triangleCount(), 2u);
        for (size_t t = 0; t < 2; ++t) {
            Vec3f a, b, c;
            m.vertices(t, a, b, c);
            EXPECT_GT(cross(b - a, c - a).z, 0.f) << "triangle " << t << " faces away";
        }
    }
    EXPECT_EQ(s.scene.meshes[1].indices, (std::vector<uint32_t>{0, 1, 3, 1, 2, 3}));
}

// Every image byte is read from a file checked against the allowed folders:
// one outside them is an error, and one swapped for a symlink leading out
// between loading and preparing is not read through it.
TEST(Gltf, ImageFilesAreCheckedOpenedOnceAndReadFromTheirDescriptor) {
    const fs::path dir = test::tempDir();
    fs::create_directories(dir / "scene");
    test::writeFile(dir / "scene" / "tex.png", png(1, 1, 3, {255, 0, 0}));
    test::writeFile(dir / "outside.png", png(1, 1, 3, {0, 0, 255}));
    GltfBuilder g;
    Json prim = g.quad();
    prim["material"] = g.material({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", g.textureFile("tex.png")}}}}}});
    g.node(Json::array({prim}));
    test::writeFile(dir / "scene" / "m.gltf", g.gltf());
    LoadOptions confined;
    confined.allowedRoots = {dir / "scene"};
    Quiet q;
    const LoadedScene s = load(dir / "scene" / "m.gltf", q, confined);
    const Material& m = firstMaterial(s);
    ASSERT_TRUE(m.baseColorMap.used());
    EXPECT_GE(s.scene.textures[size_t(m.baseColorMap.texture)].fd, 0);
    fs::remove(dir / "scene" / "tex.png");
    fs::create_symlink(dir / "outside.png", dir / "scene" / "tex.png");
    TextureCache cache(s.scene.textures, q.logger);
    const Rgba c = cache.sample(m.baseColorMap, {0.5f, 0.5f}, 0.f);
    EXPECT_NEAR(c.rgb.r, 1.f, 1e-5f);
    EXPECT_EQ(c.rgb.b, 0.f) << "the texture was read through the symlink, outside the allowed folder";

    g.doc["images"][0]["uri"] = "../outside.png";
    test::writeFile(dir / "scene" / "escape.gltf", g.gltf());
    const std::string e = errorOf(dir / "scene" / "escape.gltf", confined);
    EXPECT_NE(e.find("escape.gltf"), std::string::npos) << e;
    EXPECT_NE(e.find("outside.png"), std::string::npos) << e;
    EXPECT_NE(e.find("outside the allowed directories"), std::string::npos) << e;
    // A missing image is a warning naming it; the material goes without the texture.
    g.doc["images"][0]["uri"] = "lost.png";
    test::writeFile(dir / "scene" / "lost.gltf", g.gltf());
    Quiet l;
    EXPECT_FALSE(firstMaterial(load(dir / "scene" / "lost.gltf", l)).baseColorMap.used());
    ASSERT_EQ(l.warnings.size(), 1u);
    EXPECT_NE(l.warnings[0].find("lost.png: file not found"), std::string::npos) << l.warnings[0];
}

}  // namespace
}  // namespace penumbra
