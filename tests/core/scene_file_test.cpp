// The JSON scene format: every documented key lands where docs/scene-format.md
// says, every error names the file and the JSON path, and the example scenes
// in assets/scenes load with the expected content.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/io/scene_loader.h"
#include "support/test_support.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using test::assetPath;
using test::tempDir;
using test::writeFile;

/// Collects log messages so tests can assert on warnings.
struct CapturedLog {
    std::vector<std::string> warnings;
    Logger logger{[this](LogLevel level, std::string_view msg) {
                      if (level >= LogLevel::Warning) warnings.emplace_back(msg);
                  },
                  LogLevel::Debug};
};

LoadedScene loadText(const std::string& json, const LoadOptions& options = {}, const Logger& log = Logger()) {
    fs::path p = writeFile(tempDir() / "scene.json", json);
    return loadJsonScene(p, options, log);
}

/// Loads `json` and returns the Error it must throw.
Error loadError(const std::string& json, const LoadOptions& options = {}) {
    try {
        loadText(json, options);
    } catch (const Error& e) {
        return e;
    } catch (const std::exception& e) {
        ADD_FAILURE() << "non-penumbra exception escaped: " << e.what();
        return Error(ErrorCode::Internal, e.what());
    }
    ADD_FAILURE() << "no error for: " << json;
    return Error(ErrorCode::Internal, "no error");
}

void expectError(const std::string& json, ErrorCode code, const std::vector<std::string>& parts) {
    Error e = loadError(json);
    EXPECT_EQ(e.code(), code) << e.what();
    std::string msg = e.what();
    EXPECT_NE(msg.find("scene.json"), std::string::npos) << msg;
    for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' not in: " << msg;
}

uint32_t materialId(const Scene& s, const std::string& name) {
    for (size_t i = 0; i < s.materials.size(); ++i)
        if (s.materials[i].name == name) return static_cast<uint32_t>(i);
    ADD_FAILURE() << "no material " << name;
    return 0;
}

void expectVec(const Vec3f& a, const Vec3f& b, float eps = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, eps);
    EXPECT_NEAR(a.y, b.y, eps);
    EXPECT_NEAR(a.z, b.z, eps);
}

const char* kOneSphere = R"("shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1}])";

// ---------------------------------------------------------------------------------------------
// Top level

TEST(SceneFile, EmptyObjectIsAnEmptyScene) {
    LoadedScene s = loadText("{}");
    EXPECT_FALSE(s.camera.has_value());
    EXPECT_FALSE(s.settings.width.has_value());
    EXPECT_EQ(s.scene.primitiveCount(), 0u);
    EXPECT_TRUE(s.scene.materials.empty());
    EXPECT_EQ(s.sourcePath.filename(), "scene.json");
}

TEST(SceneFile, CommentsAreAllowed) {
    LoadedScene s = loadText("// a scene\n{ /* grey */ \"background\": 0.5 }\n");
    EXPECT_EQ(s.scene.background, Rgb(0.5f));
}

TEST(SceneFile, BackgroundArrayAndGrey) {
    EXPECT_EQ(loadText(R"({"background": [0.1, 0.2, 0.3]})").scene.background, Rgb(0.1f, 0.2f, 0.3f));
    EXPECT_EQ(loadText(R"({"background": 0.25})").scene.background, Rgb(0.25f));
}

TEST(SceneFile, Ambient) {
    EXPECT_EQ(loadText(R"({"ambient": [0.1, 0.2, 0.3]})").scene.ambient, Rgb(0.1f, 0.2f, 0.3f));
}

// ---------------------------------------------------------------------------------------------
// Camera

TEST(SceneFile, CameraEyeLookAtUp) {
    LoadedScene s = loadText(R"({"camera": {"eye": [-20, 10, 20], "look_at": [0, 2, 0], "up": [0, 0, 1]}})");
    ASSERT_TRUE(s.camera.has_value());
    expectVec(s.camera->eye, {-20, 10, 20});
    expectVec(s.camera->lookAt, {0, 2, 0});
    expectVec(s.camera->up, {0, 0, 1});
}

TEST(SceneFile, CameraFov) {
    LoadedScene s = loadText(R"({"camera": {"fov": 21.5}})");
    EXPECT_FLOAT_EQ(s.camera->vfovDegrees, 21.5f);
}

TEST(SceneFile, CameraApertureAndFocusDistance) {
    LoadedScene s = loadText(R"({"camera": {"aperture": 0.1, "focus_distance": 7.5}})");
    EXPECT_FLOAT_EQ(s.camera->aperture, 0.1f);
    EXPECT_FLOAT_EQ(s.camera->focusDistance, 7.5f);
}

TEST(SceneFile, CameraDefaultsForMissingKeys) {
    LoadedScene s = loadText(R"({"camera": {}})");
    CameraDesc d;
    expectVec(s.camera->eye, d.eye);
    expectVec(s.camera->lookAt, d.lookAt);
    EXPECT_FLOAT_EQ(s.camera->vfovDegrees, d.vfovDegrees);
    EXPECT_FLOAT_EQ(s.camera->aperture, 0.f);
}

// ---------------------------------------------------------------------------------------------
// Render settings

TEST(SceneFile, RenderWidthHeight) {
    LoadedScene s = loadText(R"({"render": {"width": 600, "height": 400}})");
    EXPECT_EQ(s.settings.width, 600);
    EXPECT_EQ(s.settings.height, 400);
    EXPECT_FALSE(s.settings.spp.has_value());
}

TEST(SceneFile, RenderSpp) { EXPECT_EQ(loadText(R"({"render": {"spp": 64}})").settings.spp, 64); }

TEST(SceneFile, RenderLightSamples) {
    EXPECT_EQ(loadText(R"({"render": {"light_samples": 16}})").settings.lightSamples, 16);
}

TEST(SceneFile, RenderMaxDepth) {
    EXPECT_EQ(loadText(R"({"render": {"max_depth": 0}})").settings.maxDepth, 0);
    EXPECT_EQ(loadText(R"({"render": {"max_depth": 10}})").settings.maxDepth, 10);
}

TEST(SceneFile, RenderSeedTakesFull64Bits) {
    EXPECT_EQ(loadText(R"({"render": {"seed": 42}})").settings.seed, 42u);
    EXPECT_EQ(loadText(R"({"render": {"seed": 18446744073709551615}})").settings.seed, 18446744073709551615ull);
}

TEST(SceneFile, RenderThreads) { EXPECT_EQ(loadText(R"({"render": {"threads": 3}})").settings.threads, 3); }

TEST(SceneFile, RenderTileSize) { EXPECT_EQ(loadText(R"({"render": {"tile_size": 8}})").settings.tileSize, 8); }

TEST(SceneFile, RenderLightSelection) {
    EXPECT_EQ(loadText(R"({"render": {"light_selection": "all"}})").settings.lightSelection, LightSelection::All);
    EXPECT_EQ(loadText(R"({"render": {"light_selection": "power"}})").settings.lightSelection, LightSelection::Power);
}

TEST(SceneFile, RenderIntegralFloatAccepted) {
    EXPECT_EQ(loadText(R"({"render": {"spp": 8.0}})").settings.spp, 8);
}

TEST(SceneFile, RenderPatchAppliesAndValidates) {
    LoadedScene s = loadText(R"({"render": {"width": 7, "height": 5, "spp": 3, "light_samples": 2, "max_depth": 1,
                                            "seed": 9, "threads": 1, "tile_size": 4, "light_selection": "power"}})");
    RenderSettings r;
    s.settings.applyTo(r);
    EXPECT_EQ(r.width, 7);
    EXPECT_EQ(r.height, 5);
    EXPECT_EQ(r.tileSize, 4);
    EXPECT_EQ(r.seed, 9u);
    EXPECT_NO_THROW(validateSettings(r));
}

// ---------------------------------------------------------------------------------------------
// Materials

TEST(SceneFile, MaterialsAsObjectKeepFileOrder) {
    LoadedScene s = loadText(R"({"materials": {"zeta": {}, "alpha": {}}})");
    ASSERT_EQ(s.scene.materials.size(), 2u);
    EXPECT_EQ(s.scene.materials[0].name, "zeta");
    EXPECT_EQ(s.scene.materials[1].name, "alpha");
}

TEST(SceneFile, MaterialsAsArrayOfNamed) {
    LoadedScene s = loadText(R"({"materials": [{"name": "a", "kd": 0.1}, {"name": "b", "kd": 0.2}]})");
    ASSERT_EQ(s.scene.materials.size(), 2u);
    EXPECT_EQ(s.scene.materials[1].name, "b");
    EXPECT_EQ(s.scene.materials[1].kd, Rgb(0.2f));
}

TEST(SceneFile, MaterialDefaults) {
    Material m = loadText(R"({"materials": {"m": {}}})").scene.materials[0];
    Material d;
    EXPECT_EQ(Rgb(m.kd), d.kd);
    EXPECT_EQ(Rgb(m.ks), d.ks);
    EXPECT_EQ(m.exponent, d.exponent);
    EXPECT_EQ(m.model, PhongModel::Normalized);
    EXPECT_EQ(m.textureIndex, -1);
}

TEST(SceneFile, MaterialKa) {
    EXPECT_EQ(loadText(R"({"materials": {"m": {"ka": [0.1, 0.2, 0.3]}}})").scene.materials[0].ka, Rgb(0.1f, 0.2f, 0.3f));
}

TEST(SceneFile, MaterialKdGrey) {
    EXPECT_EQ(loadText(R"({"materials": {"m": {"kd": 0.5}}})").scene.materials[0].kd, Rgb(0.5f));
}

TEST(SceneFile, MaterialKs) {
    EXPECT_EQ(loadText(R"({"materials": {"m": {"ks": [0.15, 0.15, 0.15]}}})").scene.materials[0].ks, Rgb(0.15f));
}

TEST(SceneFile, MaterialN) {
    EXPECT_FLOAT_EQ(loadText(R"({"materials": {"m": {"n": 100}}})").scene.materials[0].exponent, 100.f);
}

TEST(SceneFile, MaterialExponentAlias) {
    EXPECT_FLOAT_EQ(loadText(R"({"materials": {"m": {"exponent": 32}}})").scene.materials[0].exponent, 32.f);
}

TEST(SceneFile, MaterialKr) {
    EXPECT_EQ(loadText(R"({"materials": {"m": {"kr": 0.75}}})").scene.materials[0].kr, Rgb(0.75f));
}

TEST(SceneFile, MaterialKeAndTwoSided) {
    Material m = loadText(R"({"materials": {"m": {"ke": [4, 5, 6], "two_sided": true}}})").scene.materials[0];
    EXPECT_EQ(m.ke, Rgb(4, 5, 6));
    EXPECT_TRUE(m.twoSidedEmission);
    EXPECT_TRUE(m.isEmissive());
}

TEST(SceneFile, MaterialGlass) {
    Material m = loadText(R"({"materials": {"m": {"kd": 0, "kt": [0.9, 0.8, 0.7], "ior": 1.33}}})").scene.materials[0];
    EXPECT_EQ(m.kt, Rgb(0.9f, 0.8f, 0.7f));
    EXPECT_FLOAT_EQ(m.ior, 1.33f);
    EXPECT_TRUE(m.isDielectric());
    Material d = loadText(R"({"materials": {"m": {"kd": 0.5}}})").scene.materials[0];
    EXPECT_FALSE(d.isDielectric());
    EXPECT_FLOAT_EQ(d.ior, 1.5f);
}

TEST(SceneFile, RenderIntegrator) {
    EXPECT_EQ(loadText(R"({"render": {"integrator": "path"}})").settings.integrator, IntegratorKind::Path);
    EXPECT_EQ(loadText(R"({"render": {"integrator": "whitted"}})").settings.integrator, IntegratorKind::Whitted);
    EXPECT_FALSE(loadText(R"({"render": {}})").settings.integrator);
}

TEST(SceneFile, MaterialModel) {
    LoadedScene s = loadText(R"({"materials": {"c": {"model": "classic"}, "n": {"model": "normalized"}}})");
    EXPECT_EQ(s.scene.materials[0].model, PhongModel::Classic);
    EXPECT_EQ(s.scene.materials[1].model, PhongModel::Normalized);
}

void writePng(const fs::path& path) {
    fs::create_directories(path.parent_path());
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(2, 2, 3, OIIO::TypeDesc::UINT8);
    const unsigned char px[12] = {255, 255, 255, 0, 0, 0, 0, 0, 0, 255, 255, 255};
    ASSERT_TRUE(out->open(path.string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px));
    out->close();
}

TEST(SceneFile, MaterialTextureResolvesRelativeToSceneAndIsShared) {
    fs::path dir = tempDir();
    writePng(dir / "tex" / "checker.png");
    fs::path scene = writeFile(dir / "scene.json", R"({"materials": {
        "a": {"texture": "tex/checker.png"}, "b": {}, "c": {"texture": "tex/../tex/checker.png"}}})");
    LoadedScene s = loadJsonScene(scene, {}, Logger());
    ASSERT_EQ(s.scene.textures.size(), 1u);
    EXPECT_TRUE(fs::equivalent(s.scene.textures[0].name, dir / "tex" / "checker.png"));
    EXPECT_EQ(s.scene.materials[0].textureIndex, 0);
    EXPECT_EQ(s.scene.materials[1].textureIndex, -1);
    EXPECT_EQ(s.scene.materials[2].textureIndex, 0);
}

TEST(SceneFile, MissingTextureWarnsOrFailsInStrictMode) {
    CapturedLog log;
    LoadedScene s = loadText(R"({"materials": {"a": {"texture": "nope.png"}}})", {}, log.logger);
    EXPECT_EQ(s.scene.materials[0].textureIndex, -1);
    EXPECT_TRUE(s.scene.textures.empty());
    ASSERT_EQ(log.warnings.size(), 1u);
    EXPECT_NE(log.warnings[0].find("/materials/a/texture"), std::string::npos) << log.warnings[0];

    LoadOptions strict;
    strict.strict = true;
    Error e = loadError(R"({"materials": {"a": {"texture": "nope.png"}}})", strict);
    EXPECT_EQ(e.code(), ErrorCode::FileNotFound);
    EXPECT_NE(std::string(e.what()).find("nope.png"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------
// Shapes

TEST(SceneFile, Sphere) {
    LoadedScene s = loadText(R"({"materials": {"m": {}},
        "shapes": [{"type": "sphere", "center": [1, 2, 3], "radius": 0.5, "material": "m"}]})");
    ASSERT_EQ(s.scene.spheres.size(), 1u);
    expectVec(s.scene.spheres[0].center, {1, 2, 3});
    EXPECT_FLOAT_EQ(s.scene.spheres[0].radius, 0.5f);
    EXPECT_EQ(s.scene.spheres[0].material, 0u);
}

TEST(SceneFile, ShapeWithoutMaterialGetsDefault) {
    LoadedScene s = loadText(std::string("{") + kOneSphere + "}");
    ASSERT_EQ(s.scene.materials.size(), 1u);
    EXPECT_EQ(s.scene.materials[0].name, "default");
    EXPECT_EQ(Rgb(s.scene.materials[0].kd), Material().kd);
    EXPECT_EQ(s.scene.spheres[0].material, 0u);
}

TEST(SceneFile, ShapeWithoutMaterialUsesTheFilesDefault) {
    LoadedScene s = loadText(std::string(R"({"materials": {"x": {}, "default": {"kd": 0.1}},)") + kOneSphere + "}");
    ASSERT_EQ(s.scene.materials.size(), 2u);
    EXPECT_EQ(s.scene.spheres[0].material, 1u);
}

TEST(SceneFile, ShapeMaterialByName) {
    LoadedScene s = loadText(R"({"materials": {"a": {}, "b": {"kd": 0.3}},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "b"}]})");
    EXPECT_EQ(s.scene.spheres[0].material, 1u);
}

TEST(SceneFile, ShapeEmissionMakesPrivateCopy) {
    LoadedScene s = loadText(R"({"materials": {"m": {"kd": 0.3, "ks": 0.1}},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m", "emission": [1, 2, 3]},
                   {"type": "sphere", "center": [3, 0, 0], "radius": 1, "material": "m"}]})");
    ASSERT_EQ(s.scene.materials.size(), 2u);
    const Material& base = s.scene.materials[0];
    const Material& copy = s.scene.materials[s.scene.spheres[0].material];
    EXPECT_NE(s.scene.spheres[0].material, 0u);
    EXPECT_EQ(s.scene.spheres[1].material, 0u);
    EXPECT_TRUE(Rgb(base.ke).isBlack());
    EXPECT_EQ(copy.ke, Rgb(1, 2, 3));
    EXPECT_EQ(copy.kd, Rgb(0.3f));
    EXPECT_EQ(copy.ks, Rgb(0.1f));
}

TEST(SceneFile, ShapeNameIsAccepted) {
    LoadedScene s = loadText(R"({"shapes": [{"type": "sphere", "name": "ball", "center": [0, 0, 0], "radius": 1}]})");
    EXPECT_EQ(s.scene.spheres.size(), 1u);
}

TEST(SceneFile, Plane) {
    LoadedScene s = loadText(R"({"shapes": [{"type": "plane", "point": [0, -1, 0], "normal": [0, 2, 0]},
        {"type": "plane", "point": [0, 0, -5], "normal": [0, 0, 1], "two_sided": false}]})");
    ASSERT_EQ(s.scene.planes.size(), 2u);
    expectVec(s.scene.planes[0].point, {0, -1, 0});
    expectVec(s.scene.planes[0].normal, {0, 1, 0});  // normalised
    EXPECT_TRUE(s.scene.planes[0].twoSided);         // default
    EXPECT_FALSE(s.scene.planes[1].twoSided);
}

TEST(SceneFile, BoxAxisAligned) {
    LoadedScene s = loadText(R"({"shapes": [{"type": "box", "min": [-1, 0, -2], "max": [1, 3, 2]}]})");
    ASSERT_EQ(s.scene.boxes.size(), 1u);
    expectVec(s.scene.boxes[0].lo, {-1, 0, -2});
    expectVec(s.scene.boxes[0].hi, {1, 3, 2});
    EXPECT_TRUE(s.scene.boxes[0].worldFromObject.isIdentity());
}

TEST(SceneFile, BoxTransformAndInverseKeptInSync) {
    LoadedScene s = loadText(R"({"shapes": [{"type": "box", "min": [0, 0, 0], "max": [1, 1, 1],
        "transform": {"translate": [5, 0, 0], "rotate": [90, 0, 1, 0], "scale": 2}}]})");
    const Box& b = s.scene.boxes[0];
    // Scale, then rotate 90 degrees about y ((x, y, z) -> (z, y, -x)), then translate.
    expectVec(b.worldFromObject.applyPoint({1, 1, 0}), {5, 2, -2});
    expectVec(b.objectFromWorld.applyPoint({5, 2, -2}), {1, 1, 0});
}

TEST(SceneFile, Rectangle) {
    LoadedScene s = loadText(R"({"shapes": [{"type": "rectangle", "p0": [0, 1, 0], "a": [2, 0, 0], "b": [0, 0, 3]}]})");
    ASSERT_EQ(s.scene.rectangles.size(), 1u);
    expectVec(s.scene.rectangles[0].p0, {0, 1, 0});
    expectVec(s.scene.rectangles[0].a, {2, 0, 0});
    expectVec(s.scene.rectangles[0].b, {0, 0, 3});
    EXPECT_FLOAT_EQ(area(s.scene.rectangles[0]), 6.f);
}

TEST(SceneFile, Disk) {
    LoadedScene s = loadText(R"({"shapes": [{"type": "disk", "center": [1, 2, 3], "normal": [0, 0, -4], "radius": 2}]})");
    ASSERT_EQ(s.scene.disks.size(), 1u);
    expectVec(s.scene.disks[0].center, {1, 2, 3});
    expectVec(s.scene.disks[0].normal, {0, 0, -1});
    EXPECT_FLOAT_EQ(s.scene.disks[0].radius, 2.f);
}

TEST(SceneFile, InlineMeshNested) {
    LoadedScene s = loadText(R"({"shapes": [{"type": "mesh", "name": "quad",
        "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], "indices": [[0, 1, 2], [0, 2, 3]]}]})");
    ASSERT_EQ(s.scene.meshes.size(), 1u);
    const TriangleMesh& m = s.scene.meshes[0];
    EXPECT_EQ(m.name, "quad");
    EXPECT_EQ(m.positions.size(), 4u);
    expectVec(m.positions[2], {1, 1, 0});
    EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
    EXPECT_TRUE(m.normals.empty());
    EXPECT_TRUE(m.uvs.empty());
}

TEST(SceneFile, InlineMeshFlatIndicesAndVertices) {
    LoadedScene s = loadText(R"({"shapes": [{"type": "mesh",
        "vertices": [0, 0, 0, 1, 0, 0, 0, 1, 0], "indices": [0, 1, 2]}]})");
    const TriangleMesh& m = s.scene.meshes[0];
    EXPECT_EQ(m.positions.size(), 3u);
    expectVec(m.positions[1], {1, 0, 0});
    EXPECT_EQ(m.triangleCount(), 1u);
}

TEST(SceneFile, InlineMeshNormalsAndUvs) {
    LoadedScene s = loadText(R"({"shapes": [{"type": "mesh", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
        "indices": [0, 1, 2], "normals": [[0, 0, 2], [0, 0, 1], [0, 0, 1]], "uvs": [[0, 0], [1, 0], [0, 1]]}]})");
    const TriangleMesh& m = s.scene.meshes[0];
    ASSERT_EQ(m.normals.size(), 3u);
    expectVec(m.normals[0], {0, 0, 1});
    ASSERT_EQ(m.uvs.size(), 3u);
    EXPECT_FLOAT_EQ(m.uvs[2].y, 1.f);
}

TEST(SceneFile, InlineMeshTransformMovesPointsAndNormals) {
    LoadedScene s = loadText(R"({"shapes": [{"type": "mesh", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
        "indices": [0, 1, 2], "normals": [[0, 0, 1], [0, 0, 1], [0, 0, 1]],
        "transform": {"rotate": [90, 1, 0, 0], "translate": [0, 0, 5]}}]})");
    const TriangleMesh& m = s.scene.meshes[0];
    // 90 degrees about x: (x, y, z) -> (x, -z, y).
    expectVec(m.positions[2], {0, 0, 6});
    expectVec(m.normals[0], {0, -1, 0});
}

TEST(SceneFile, TransformScalePerAxis) {
    LoadedScene s = loadText(R"({"shapes": [{"type": "mesh", "vertices": [[1, 1, 1], [2, 1, 1], [1, 2, 1]],
        "indices": [0, 1, 2], "transform": {"scale": [2, 3, 4]}}]})");
    expectVec(s.scene.meshes[0].positions[0], {2, 3, 4});
}

TEST(SceneFile, TransformRotateListAppliesInOrder) {
    LoadedScene s = loadText(R"({"shapes": [{"type": "mesh", "vertices": [[1, 0, 0], [2, 0, 0], [1, 1, 0]],
        "indices": [0, 1, 2], "transform": {"rotate": [[90, 0, 0, 1], [90, 1, 0, 0]]}}]})");
    // First about z: (1,0,0) -> (0,1,0); then about x: (0,1,0) -> (0,0,1).
    expectVec(s.scene.meshes[0].positions[0], {0, 0, 1});
}

TEST(SceneFile, MeshMaterialAndEmission) {
    LoadedScene s = loadText(R"({"materials": {"m": {"kd": 0.2}}, "shapes": [{"type": "mesh", "material": "m",
        "emission": 5, "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "indices": [0, 1, 2]}]})");
    const Material& m = s.scene.materials[s.scene.meshes[0].material];
    EXPECT_EQ(m.kd, Rgb(0.2f));
    EXPECT_EQ(m.ke, Rgb(5.f));
}

const char* kTriangleObj =
    "mtllib tri.mtl\n"
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
    "usemtl red\nf 1 2 3\n"
    "usemtl blue\nf 2 4 3\n";
const char* kTriangleMtl = "newmtl red\nKd 1 0 0\n\nnewmtl blue\nKd 0 0 1\n";

fs::path writeObj(const fs::path& dir) {
    writeFile(dir / "models" / "tri.mtl", kTriangleMtl);
    return writeFile(dir / "models" / "tri.obj", kTriangleObj);
}

/// Material of every triangle of every mesh.
std::vector<uint32_t> faceMaterials(const Scene& s) {
    std::vector<uint32_t> ids;
    for (const auto& m : s.meshes)
        for (size_t t = 0; t < m.triangleCount(); ++t) ids.push_back(m.materialOf(t));
    return ids;
}

TEST(SceneFile, MeshFromObjUsesMtlMaterialsAndTransform) {
    fs::path dir = tempDir();
    writeObj(dir);
    fs::path scene = writeFile(dir / "scene.json", R"({"shapes": [{"type": "mesh", "file": "models/tri.obj",
        "transform": {"translate": [10, 0, 0]}}]})");
    LoadedScene s = loadJsonScene(scene, {}, Logger());
    EXPECT_EQ(s.scene.triangleCount(), 2u);
    Bounds3f b = s.scene.bounds();
    expectVec(b.lo, {10, 0, 0});
    expectVec(b.hi, {11, 1, 0});
    std::vector<uint32_t> ids = faceMaterials(s.scene);
    ASSERT_EQ(ids.size(), 2u);
    EXPECT_EQ(s.scene.materials[ids[0]].kd, Rgb(1, 0, 0));
    EXPECT_EQ(s.scene.materials[ids[1]].kd, Rgb(0, 0, 1));
}

TEST(SceneFile, MeshFromObjMaterialOverridesAllFaces) {
    fs::path dir = tempDir();
    writeObj(dir);
    fs::path scene = writeFile(dir / "scene.json", R"({"materials": {"gold": {"kd": [0.8, 0.6, 0.2]}},
        "shapes": [{"type": "mesh", "name": "golden", "file": "models/tri.obj", "material": "gold"}]})");
    LoadedScene s = loadJsonScene(scene, {}, Logger());
    ASSERT_FALSE(s.scene.meshes.empty());
    for (const auto& m : s.scene.meshes) EXPECT_EQ(m.name, "golden");
    for (uint32_t id : faceMaterials(s.scene)) EXPECT_EQ(id, 0u);
    EXPECT_EQ(faceMaterials(s.scene).size(), 2u);
}

TEST(SceneFile, MeshFromObjEmissionWithoutMaterialKeepsMtlColours) {
    fs::path dir = tempDir();
    writeObj(dir);
    fs::path scene = writeFile(dir / "scene.json", R"({"shapes": [{"type": "mesh", "file": "models/tri.obj",
        "emission": [2, 2, 2]}]})");
    LoadedScene s = loadJsonScene(scene, {}, Logger());
    std::vector<uint32_t> ids = faceMaterials(s.scene);
    ASSERT_EQ(ids.size(), 2u);
    EXPECT_EQ(s.scene.materials[ids[0]].ke, Rgb(2.f));
    EXPECT_EQ(s.scene.materials[ids[1]].ke, Rgb(2.f));
    EXPECT_EQ(s.scene.materials[ids[0]].kd, Rgb(1, 0, 0));
    EXPECT_EQ(s.scene.materials[ids[1]].kd, Rgb(0, 0, 1));
}

TEST(SceneFile, MeshFileMissingIsFileNotFoundWithPath) {
    expectError(R"({"shapes": [{"type": "mesh", "file": "missing.obj"}]})", ErrorCode::FileNotFound,
                {"/shapes/0/file", "missing.obj"});
}

TEST(SceneFile, AllowedRootsApplyToReferencedFiles) {
    fs::path dir = tempDir();
    writeObj(dir);
    fs::path scene = writeFile(dir / "sub" / "scene.json",
                               R"({"shapes": [{"type": "mesh", "file": "../models/tri.obj"}]})");
    LoadOptions opts;
    opts.allowedRoots = {dir / "sub"};
    try {
        loadJsonScene(scene, opts, Logger());
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("/shapes/0/file"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("tri.obj"), std::string::npos) << e.what();
    }
    opts.allowedRoots = {dir};
    EXPECT_EQ(loadJsonScene(scene, opts, Logger()).scene.triangleCount(), 2u);
}

// ---------------------------------------------------------------------------------------------
// Lights

TEST(SceneFile, PointLight) {
    LoadedScene s = loadText(R"({"lights": [{"type": "point", "position": [1, 2, 3], "intensity": [10, 20, 30]}]})");
    ASSERT_EQ(s.scene.pointLights.size(), 1u);
    expectVec(s.scene.pointLights[0].position, {1, 2, 3});
    EXPECT_EQ(s.scene.pointLights[0].intensity, Rgb(10, 20, 30));
}

TEST(SceneFile, DirectionalLight) {
    LoadedScene s = loadText(R"({"lights": [{"type": "directional", "direction": [0, -2, 0], "irradiance": 3}]})");
    ASSERT_EQ(s.scene.directionalLights.size(), 1u);
    expectVec(s.scene.directionalLights[0].direction, {0, -1, 0});
    EXPECT_EQ(s.scene.directionalLights[0].irradiance, Rgb(3.f));
}

TEST(SceneFile, AmbientLightAddsToAmbient) {
    LoadedScene s = loadText(R"({"ambient": 0.1, "lights": [{"type": "ambient", "radiance": [0.2, 0.3, 0.4]}]})");
    EXPECT_NEAR(s.scene.ambient.r, 0.3f, 1e-6f);
    EXPECT_NEAR(s.scene.ambient.g, 0.4f, 1e-6f);
    EXPECT_NEAR(s.scene.ambient.b, 0.5f, 1e-6f);
}

TEST(SceneFile, RectangleLightBecomesEmissiveShape) {
    LoadedScene s = loadText(R"({"lights": [{"type": "rectangle", "name": "panel", "p0": [-2, 10, -2],
        "a": [4, 0, 0], "b": [0, 0, 4], "radiance": 40}]})");
    ASSERT_EQ(s.scene.rectangles.size(), 1u);
    const Material& m = s.scene.materials[s.scene.rectangles[0].material];
    EXPECT_EQ(m.name, "panel");
    EXPECT_EQ(m.ke, Rgb(40.f));
    EXPECT_TRUE(Rgb(m.kd).isBlack());
    EXPECT_TRUE(Rgb(m.ks).isBlack());
    EXPECT_TRUE(Rgb(m.kr).isBlack());
    EXPECT_FALSE(m.twoSidedEmission);
    expectVec(rectangleNormal(s.scene.rectangles[0]), {0, -1, 0});
}

TEST(SceneFile, DiskLightTwoSided) {
    LoadedScene s = loadText(R"({"lights": [{"type": "disk", "center": [0, 5, 0], "normal": [0, -1, 0],
        "radius": 0.5, "radiance": [1, 2, 3], "two_sided": true}]})");
    ASSERT_EQ(s.scene.disks.size(), 1u);
    EXPECT_FLOAT_EQ(s.scene.disks[0].radius, 0.5f);
    const Material& m = s.scene.materials[s.scene.disks[0].material];
    EXPECT_EQ(m.ke, Rgb(1, 2, 3));
    EXPECT_TRUE(m.twoSidedEmission);
}

TEST(SceneFile, SphereLight) {
    LoadedScene s = loadText(R"({"lights": [{"type": "sphere", "center": [0, 5, 0], "radius": 0.25, "radiance": 7}]})");
    ASSERT_EQ(s.scene.spheres.size(), 1u);
    EXPECT_FLOAT_EQ(s.scene.spheres[0].radius, 0.25f);
    EXPECT_EQ(s.scene.materials[s.scene.spheres[0].material].ke, Rgb(7.f));
}

TEST(SceneFile, LoadedIdsSurviveFinalizeUnchanged) {
    LoadedScene s = loadText(R"({"materials": {"m": {}}, "shapes": [
        {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m", "emission": 1},
        {"type": "mesh", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "indices": [0, 1, 2]}],
        "lights": [{"type": "disk", "center": [0, 5, 0], "normal": [0, -1, 0], "radius": 1, "radiance": 2}]})");
    std::vector<uint32_t> before = {s.scene.spheres[0].material, s.scene.meshes[0].material, s.scene.disks[0].material};
    CapturedLog log;
    SceneFixups fix = s.scene.finalize(log.logger);
    EXPECT_EQ(fix.droppedShapes, 0u);
    EXPECT_EQ(fix.droppedTriangles, 0u);
    EXPECT_TRUE(log.warnings.empty());
    std::vector<uint32_t> after = {s.scene.spheres[0].material, s.scene.meshes[0].material, s.scene.disks[0].material};
    EXPECT_EQ(before, after);
    EXPECT_EQ(s.scene.materials.size(), 4u);  // m, its emissive copy, default, the light's
}

// ---------------------------------------------------------------------------------------------
// Errors

TEST(SceneFileErrors, SyntaxErrorReportsLineAndColumn) {
    Error e = loadError("{\n  \"background\": 0.5,\n  \"ambient\": tru\n}\n");
    EXPECT_EQ(e.code(), ErrorCode::ParseError);
    std::string msg = e.what();
    EXPECT_NE(msg.find("scene.json:3:17: JSON syntax error"), std::string::npos) << msg;
}

TEST(SceneFileErrors, SyntaxErrorTrailingComma) {
    Error e = loadError("{\n  \"a\": 1,\n}");
    EXPECT_EQ(e.code(), ErrorCode::ParseError);
    EXPECT_NE(std::string(e.what()).find("scene.json:3:1:"), std::string::npos) << e.what();
}

TEST(SceneFileErrors, SyntaxErrorUnexpectedEnd) {
    Error e = loadError("{\"shapes\": [\n");
    EXPECT_EQ(e.code(), ErrorCode::ParseError);
    EXPECT_NE(std::string(e.what()).find("scene.json:2:1:"), std::string::npos) << e.what();
}

TEST(SceneFileErrors, NumberOverflowReportsPosition) {
    Error e = loadError("{\n \"background\": 1e999\n}");
    EXPECT_EQ(e.code(), ErrorCode::ParseError);
    EXPECT_NE(std::string(e.what()).find("scene.json:2:16:"), std::string::npos) << e.what();
}

TEST(SceneFileErrors, TruncatedFilesOnlyThrowParseErrors) {
    std::ifstream in(assetPath("scenes/showcase.json"));
    std::stringstream ss;
    ss << in.rdbuf();
    std::string text = ss.str();
    ASSERT_GT(text.size(), 1000u);
    for (size_t n = 0; n < text.size() - 2; n += 97) {
        Error e = loadError(text.substr(0, n));
        EXPECT_EQ(e.code(), ErrorCode::ParseError) << "prefix " << n << ": " << e.what();
    }
}

TEST(SceneFileErrors, DuplicateKey) {
    expectError(R"({"shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "radius": 2}]})",
                ErrorCode::ParseError, {"/shapes/0/radius", "duplicate key"});
}

TEST(SceneFileErrors, TopLevelMustBeObject) {
    expectError("[1, 2]", ErrorCode::ParseError, {"object"});
}

TEST(SceneFileErrors, UnknownTopLevelKey) {
    expectError(R"({"backgroud": 0.5})", ErrorCode::ParseError, {"/backgroud", "unknown key", "background"});
}

TEST(SceneFileErrors, UnknownNestedKey) {
    expectError(R"({"shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "colour": 1}]})",
                ErrorCode::ParseError, {"/shapes/0/colour", "unknown key"});
    expectError(R"({"materials": {"m": {"kdd": 1}}})", ErrorCode::ParseError, {"/materials/m/kdd"});
    expectError(R"({"render": {"samples": 4}})", ErrorCode::ParseError, {"/render/samples"});
    expectError(R"({"camera": {"lookat": [0, 0, 0]}})", ErrorCode::ParseError, {"/camera/lookat"});
}

TEST(SceneFileErrors, TransformOnlyWhereDocumented) {
    expectError(R"({"shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "transform": {}}]})",
                ErrorCode::ParseError, {"/shapes/0/transform", "unknown key"});
}

TEST(SceneFileErrors, WrongType) {
    expectError(R"({"shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": "big"}]})", ErrorCode::ParseError,
                {"/shapes/0/radius", "expected a number"});
    expectError(R"({"shapes": [{"type": "sphere", "center": [0, 0], "radius": 1}]})", ErrorCode::ParseError,
                {"/shapes/0/center", "3 numbers"});
    expectError(R"({"shapes": {}})", ErrorCode::ParseError, {"/shapes", "expected an array"});
    expectError(R"({"render": {"spp": 2.5}})", ErrorCode::ParseError, {"/render/spp", "integer"});
    expectError(R"({"shapes": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "two_sided": 1}]})",
                ErrorCode::ParseError, {"/shapes/0/two_sided", "true or false"});
}

TEST(SceneFileErrors, MissingRequiredKey) {
    expectError(R"({"shapes": [{"type": "sphere", "center": [0, 0, 0]}]})", ErrorCode::ParseError,
                {"/shapes/0/radius", "missing"});
    expectError(R"({"shapes": [{"center": [0, 0, 0]}]})", ErrorCode::ParseError, {"/shapes/0/type", "missing"});
}

TEST(SceneFileErrors, NegativeOrZeroRadius) {
    expectError(R"({"shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": -1}]})", ErrorCode::InvalidScene,
                {"scene.json: /shapes/0/radius: must be > 0"});
    expectError(R"({"shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1},
                               {"type": "disk", "center": [0, 0, 0], "normal": [0, 1, 0], "radius": 0}]})",
                ErrorCode::InvalidScene, {"/shapes/1/radius", "must be > 0"});
}

TEST(SceneFileErrors, ZeroAreaRectangleLight) {
    expectError(R"({"lights": [{"type": "rectangle", "p0": [0, 0, 0], "a": [1, 0, 0], "b": [2, 0, 0], "radiance": 1}]})",
                ErrorCode::InvalidScene, {"/lights/0", "zero area"});
}

TEST(SceneFileErrors, ZeroNormalAndZeroDirection) {
    expectError(R"({"shapes": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 0, 0]}]})", ErrorCode::InvalidScene,
                {"/shapes/0/normal", "zero"});
    expectError(R"({"lights": [{"type": "directional", "direction": [0, 0, 0], "irradiance": 1}]})",
                ErrorCode::InvalidScene, {"/lights/0/direction"});
}

TEST(SceneFileErrors, BoxMinNotBelowMax) {
    expectError(R"({"shapes": [{"type": "box", "min": [0, 0, 0], "max": [1, 0, 1]}]})", ErrorCode::InvalidScene,
                {"/shapes/0/max"});
}

TEST(SceneFileErrors, SingularTransform) {
    expectError(R"({"shapes": [{"type": "box", "min": [0, 0, 0], "max": [1, 1, 1], "transform": {"scale": [1, 0, 1]}}]})",
                ErrorCode::InvalidScene, {"/shapes/0/transform/scale"});
    expectError(R"({"shapes": [{"type": "box", "min": [0, 0, 0], "max": [1, 1, 1],
                   "transform": {"rotate": [[90, 0, 1, 0], [10, 0, 0, 0]]}}]})",
                ErrorCode::InvalidScene, {"/shapes/0/transform/rotate/1", "axis"});
}

TEST(SceneFileErrors, FovOutOfRange) {
    expectError(R"({"camera": {"fov": 180}})", ErrorCode::InvalidScene, {"/camera/fov", "(0, 180)"});
    expectError(R"({"camera": {"fov": 0}})", ErrorCode::InvalidScene, {"/camera/fov"});
}

TEST(SceneFileErrors, InvalidCameraIsRewrappedWithPath) {
    expectError(R"({"camera": {"eye": [1, 2, 3], "look_at": [1, 2, 3]}})", ErrorCode::InvalidScene,
                {"scene.json: /camera: eye and look-at are the same point"});
    expectError(R"({"camera": {"eye": [0, 5, 0], "look_at": [0, 0, 0], "up": [0, 1, 0]}})", ErrorCode::InvalidScene,
                {"/camera", "parallel"});
}

TEST(SceneFileErrors, RenderOutOfRange) {
    expectError(R"({"render": {"spp": 0}})", ErrorCode::InvalidScene, {"/render/spp", "[1, "});
    expectError(R"({"render": {"width": -5}})", ErrorCode::InvalidScene, {"/render/width"});
    expectError(R"({"render": {"height": 0}})", ErrorCode::InvalidScene, {"/render/height"});
    expectError(R"({"render": {"max_depth": -1}})", ErrorCode::InvalidScene, {"/render/max_depth"});
    expectError(R"({"render": {"seed": -1}})", ErrorCode::InvalidScene, {"/render/seed"});
    expectError(R"({"render": {"light_selection": "random"}})", ErrorCode::InvalidScene,
                {"/render/light_selection", "\"all\" or \"power\""});
    expectError(R"({"render": {"integrator": "bdpt"}})", ErrorCode::InvalidScene,
                {"/render/integrator", "\"whitted\" or \"path\""});
    expectError(R"({"materials": {"g": {"kt": 1, "ior": 0}}})", ErrorCode::InvalidScene, {"/materials/g/ior", "> 0"});
    expectError(R"({"materials": {"g": {"kt": -1}}})", ErrorCode::InvalidScene, {"/materials/g/kt"});
}

TEST(SceneFileErrors, UnknownShapeAndLightType) {
    expectError(R"({"shapes": [{"type": "cone"}]})", ErrorCode::ParseError, {"/shapes/0/type", "cone"});
    expectError(R"({"lights": [{"type": "spot"}]})", ErrorCode::ParseError, {"/lights/0/type", "spot"});
}

TEST(SceneFileErrors, UnknownMaterial) {
    expectError(R"({"materials": {"m": {}}, "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1,
                   "material": "gold"}]})",
                ErrorCode::InvalidScene, {"/shapes/0/material", "unknown material \"gold\""});
}

TEST(SceneFileErrors, DuplicateMaterialName) {
    expectError(R"({"materials": [{"name": "a"}, {"name": "a"}]})", ErrorCode::InvalidScene,
                {"/materials/1", "defined twice"});
}

TEST(SceneFileErrors, MaterialInArrayNeedsName) {
    expectError(R"({"materials": [{"kd": 1}]})", ErrorCode::ParseError, {"/materials/0/name", "missing"});
}

TEST(SceneFileErrors, NegativeColourComponent) {
    expectError(R"({"materials": {"m": {"kd": [0.5, -0.1, 0.5]}}})", ErrorCode::InvalidScene,
                {"/materials/m/kd/1", ">= 0"});
    expectError(R"({"materials": {"m": {"n": -2}}})", ErrorCode::InvalidScene, {"/materials/m/n", ">= 0"});
}

TEST(SceneFileErrors, PointerTokensAreEscaped) {
    expectError(R"({"materials": {"a/b~c": {"kd": -1}}})", ErrorCode::InvalidScene, {"/materials/a~1b~0c/kd"});
}

TEST(SceneFileErrors, NExponentBothGiven) {
    expectError(R"({"materials": {"m": {"n": 2, "exponent": 3}}})", ErrorCode::ParseError, {"/materials/m/exponent"});
}

TEST(SceneFileErrors, UnknownModel) {
    expectError(R"({"materials": {"m": {"model": "blinn"}}})", ErrorCode::InvalidScene, {"/materials/m/model", "blinn"});
}

TEST(SceneFileErrors, NonFiniteAfterFloatConversion) {
    expectError(R"({"background": [1e39, 0, 0]})", ErrorCode::InvalidScene, {"/background/0", "finite"});
    expectError(R"({"shapes": [{"type": "sphere", "center": [0, -1e300, 0], "radius": 1}]})", ErrorCode::InvalidScene,
                {"/shapes/0/center/1", "finite"});
}

TEST(SceneFileErrors, MeshIndexOutOfRange) {
    expectError(R"({"shapes": [{"type": "mesh", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
                   "indices": [[0, 1, 2], [0, 2, 3]]}]})",
                ErrorCode::InvalidScene, {"/shapes/0/indices/1/2", "out of range"});
    expectError(R"({"shapes": [{"type": "mesh", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "indices": [0, 1, -2]}]})",
                ErrorCode::InvalidScene, {"/shapes/0/indices/2"});
}

TEST(SceneFileErrors, MeshShapeMismatches) {
    expectError(R"({"shapes": [{"type": "mesh", "vertices": [0, 0, 0, 1], "indices": [0, 0, 0]}]})",
                ErrorCode::ParseError, {"/shapes/0/vertices", "multiple of 3"});
    expectError(R"({"shapes": [{"type": "mesh", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "indices": [0, 1, 2],
                   "normals": [[0, 0, 1]]}]})",
                ErrorCode::InvalidScene, {"/shapes/0/normals", "1 normals for 3 vertices"});
    expectError(R"({"shapes": [{"type": "mesh", "vertices": [[0, 0, 0]], "indices": []}]})", ErrorCode::InvalidScene,
                {"/shapes/0/indices", "at least one triangle"});
}

TEST(SceneFileErrors, EmissivePlaneWarnsOrFailsInStrictMode) {
    const char* json = R"({"materials": {"glow": {"ke": 1}},
        "shapes": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "glow"}]})";
    CapturedLog log;
    EXPECT_EQ(loadText(json, {}, log.logger).scene.planes.size(), 1u);
    ASSERT_EQ(log.warnings.size(), 1u);
    EXPECT_NE(log.warnings[0].find("/shapes/0/material"), std::string::npos);
    LoadOptions strict;
    strict.strict = true;
    EXPECT_EQ(loadError(json, strict).code(), ErrorCode::InvalidScene);
    expectError(R"({"shapes": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "emission": 1}]})",
                ErrorCode::ParseError, {"/shapes/0/emission", "unknown key"});
}

TEST(SceneFileErrors, MissingFileIsFileNotFound) {
    fs::path p = tempDir() / "nowhere.json";
    try {
        loadJsonScene(p, {}, Logger());
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::FileNotFound);
        EXPECT_NE(std::string(e.what()).find("nowhere.json"), std::string::npos);
    }
}

TEST(SceneFileErrors, DirectoryIsFileNotFound) {
    fs::path dir = tempDir() / "a_dir.json";
    fs::create_directories(dir);
    try {
        loadJsonScene(dir, {}, Logger());
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::FileNotFound);
        EXPECT_NE(std::string(e.what()).find("a_dir.json"), std::string::npos);
    }
}

// ---------------------------------------------------------------------------------------------
// Example scenes

/// Film position in [-1, 1]^2 of a world point for the camera (|x|, |y| <= 1: inside the frame).
Vec2f project(const CameraDesc& c, float aspect, const Vec3f& p) {
    Vec3f w = normalize(c.eye - c.lookAt), u = normalize(cross(c.up, w)), v = cross(w, u);
    Vec3f d = p - c.eye;
    float z = -dot(d, w);
    float h = std::tan(0.5f * c.vfovDegrees * kPi / 180.f);
    return {dot(d, u) / z / (h * aspect), dot(d, v) / z / h};
}

void expectInFrame(const LoadedScene& s, const Vec3f& p) {
    float aspect = static_cast<float>(*s.settings.width) / static_cast<float>(*s.settings.height);
    Vec2f f = project(*s.camera, aspect, p);
    EXPECT_LT(std::fabs(f.x), 1.f) << p.x << "," << p.y << "," << p.z;
    EXPECT_LT(std::fabs(f.y), 1.f) << p.x << "," << p.y << "," << p.z;
}

LoadedScene loadAsset(const std::string& name) {
    CapturedLog log;
    LoadedScene s = loadJsonScene(assetPath("scenes/" + name), {}, log.logger);
    EXPECT_TRUE(log.warnings.empty()) << log.warnings.front();
    SceneFixups fix = s.scene.finalize(log.logger);
    EXPECT_EQ(fix.droppedShapes, 0u);
    EXPECT_EQ(fix.droppedTriangles, 0u);
    EXPECT_TRUE(log.warnings.empty());
    return s;
}

TEST(SceneFileExamples, LectureAreaLight) {
    LoadedScene s = loadAsset("lecture_area_light.json");
    ASSERT_TRUE(s.camera.has_value());
    expectVec(s.camera->eye, {-20, 10, 20});
    expectVec(s.camera->lookAt, {0, 2, 0});
    EXPECT_GE(s.camera->vfovDegrees, 20.f);
    EXPECT_LE(s.camera->vfovDegrees, 30.f);
    EXPECT_EQ(s.settings.width, 600);
    EXPECT_EQ(s.settings.height, 400);
    EXPECT_EQ(s.settings.lightSamples, 16);
    EXPECT_EQ(s.scene.background, Rgb(0.5f));
    EXPECT_EQ(s.scene.planes.size(), 1u);
    EXPECT_EQ(s.scene.spheres.size(), 3u);
    EXPECT_EQ(s.scene.boxes.size(), 1u);
    ASSERT_EQ(s.scene.rectangles.size(), 1u);
    EXPECT_EQ(s.scene.materials.size(), 6u);  // five named + the light's
    const Rectangle& light = s.scene.rectangles[0];
    EXPECT_EQ(s.scene.materials[light.material].ke, Rgb(40.f));
    expectVec(rectangleNormal(light), {0, -1, 0});
    EXPECT_GT(light.p0.y, 5.f);
    for (const Sphere& sp : s.scene.spheres) expectInFrame(s, sp.center);
    expectInFrame(s, s.scene.boxes[0].worldFromObject.applyPoint(s.scene.boxes[0].lo));
    expectInFrame(s, s.scene.boxes[0].worldFromObject.applyPoint(s.scene.boxes[0].hi));
}

TEST(SceneFileExamples, LectureWhitted) {
    LoadedScene s = loadAsset("lecture_whitted.json");
    EXPECT_EQ(s.settings.maxDepth, 10);
    EXPECT_EQ(s.scene.background, Rgb(0.15f));
    EXPECT_GT(s.scene.ambient.average(), 0.f);
    EXPECT_EQ(s.scene.pointLights.size(), 1u);
    EXPECT_EQ(s.scene.planes.size(), 1u);
    EXPECT_EQ(s.scene.spheres.size(), 5u);
    EXPECT_EQ(s.scene.materials.size(), 5u);
    const Material& y = s.scene.materials[materialId(s.scene, "yellow_mirror")];
    EXPECT_EQ(y.ka, Rgb(0.25f));
    EXPECT_EQ(y.kd, Rgb(0.375f, 0.375f, 0.f));
    EXPECT_EQ(y.ks, Rgb(0.15f));
    EXPECT_FLOAT_EQ(y.exponent, 100.f);
    EXPECT_EQ(y.kr, Rgb(0.75f));
    EXPECT_EQ(y.model, PhongModel::Classic);
    int mirrors = 0, matte = 0;
    for (const Sphere& sp : s.scene.spheres) {
        (s.scene.materials[sp.material].isMirror() ? mirrors : matte)++;
        expectInFrame(s, sp.center);
    }
    EXPECT_GE(mirrors, 2);
    EXPECT_GE(matte, 2);
}

TEST(SceneFileExamples, Showcase) {
    LoadedScene s = loadAsset("showcase.json");
    const Scene& sc = s.scene;
    // Every shape type and every light type.
    EXPECT_EQ(sc.spheres.size(), 4u);     // mirror, orange, glowing, sphere light
    EXPECT_EQ(sc.planes.size(), 1u);
    EXPECT_EQ(sc.boxes.size(), 1u);
    EXPECT_EQ(sc.rectangles.size(), 3u);  // wall, neon panel, rectangle light
    EXPECT_EQ(sc.disks.size(), 2u);       // disk, disk light
    EXPECT_EQ(sc.triangleCount(), 8u + 8u + 6u);
    EXPECT_EQ(sc.pointLights.size(), 1u);
    EXPECT_EQ(sc.directionalLights.size(), 1u);
    EXPECT_NEAR(sc.ambient.r, 0.05f, 1e-6f);
    EXPECT_FALSE(sc.planes[0].twoSided);
    EXPECT_FALSE(sc.boxes[0].worldFromObject.isIdentity());
    // Materials: classic and normalized, two-sided emission, emission on an ordinary shape.
    EXPECT_EQ(sc.materials[materialId(sc, "classic_orange")].model, PhongModel::Classic);
    EXPECT_EQ(sc.materials[materialId(sc, "glossy_white")].model, PhongModel::Normalized);
    EXPECT_TRUE(sc.materials[materialId(sc, "neon")].twoSidedEmission);
    EXPECT_EQ(sc.materials[sc.spheres[2].material].ke, Rgb(3.f, 2.4f, 1.2f));
    EXPECT_EQ(sc.materials[sc.spheres[3].material].ke, Rgb(2.f, 4.f, 8.f));
    int emissiveShapes = 0;
    for (const auto& q : sc.rectangles) emissiveShapes += sc.materials[q.material].isEmissive();
    for (const auto& d : sc.disks) emissiveShapes += sc.materials[d.material].isEmissive();
    for (const auto& sp : sc.spheres) emissiveShapes += sc.materials[sp.material].isEmissive();
    EXPECT_EQ(emissiveShapes, 5);
    // The gem with its MTL materials (two), the override gem with the mirror, the inline pyramid.
    const uint32_t mirror = materialId(sc, "mirror");
    int mirrorFaces = 0, orangeFaces = 0, mtlFaces = 0;
    for (uint32_t id : faceMaterials(sc)) {
        if (id == mirror)
            ++mirrorFaces;
        else if (id == materialId(sc, "classic_orange"))
            ++orangeFaces;
        else
            ++mtlFaces;
    }
    EXPECT_EQ(mirrorFaces, 8);
    EXPECT_EQ(orangeFaces, 6);
    EXPECT_EQ(mtlFaces, 8);
    // Render settings, all keys.
    EXPECT_EQ(s.settings.width, 640);
    EXPECT_EQ(s.settings.lightSelection, LightSelection::Power);
    EXPECT_EQ(s.settings.tileSize, 32);
    EXPECT_EQ(s.settings.threads, 0);
    EXPECT_EQ(s.settings.seed, 7u);
    EXPECT_FLOAT_EQ(s.camera->aperture, 0.05f);
    for (const Sphere& sp : sc.spheres) expectInFrame(s, sp.center);
    Bounds3f b = sc.bounds();
    expectInFrame(s, {b.center().x, 0.5f, b.center().z});
}

}  // namespace
}  // namespace penumbra
