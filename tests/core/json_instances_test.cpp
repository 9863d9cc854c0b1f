// JSON prototypes and instances (docs/scene-format.md#instances): where the
// entries land in the Scene, nested instances flattened, and every error
// naming the file and the JSON path.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/io/scene_loader.h"
#include "support/test_support.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using test::assetPath;
using test::sharedScenePath;
using test::tempDir;
using test::writeFile;

LoadedScene loadText(const std::string& json) {
    const fs::path p = writeFile(tempDir() / "scene.json", json);
    return loadJsonScene(p, LoadOptions{}, Logger());
}

void expectError(const std::string& json, ErrorCode code, const std::vector<std::string>& parts) {
    try {
        loadText(json);
        ADD_FAILURE() << "no error for: " << json;
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), code) << e.what();
        const std::string msg = e.what();
        EXPECT_NE(msg.find("scene.json"), std::string::npos) << msg;
        for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' not in: " << msg;
    }
}

// A unit triangle, inline.
const char* kTriangle = R"({"type": "mesh", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "indices": [[0, 1, 2]]})";

std::string withPrototypes(const std::string& prototypes, const std::string& shapes) {
    return R"({"materials": {"white": {"kd": 0.8}, "red": {"kd": [0.8, 0, 0]}, "lamp": {"ke": 3}},
              "prototypes": )" + prototypes + R"(, "shapes": )" + shapes + "}";
}

TEST(JsonInstances, InstancesPlaceOnePrototypeWithTransformsAndOverrides) {
    const LoadedScene ls = loadText(withPrototypes(
        std::string(R"([{"name": "tri", "shapes": [)") + kTriangle + "]}]",
        R"([{"type": "instance", "prototype": "tri", "transform": {"translate": [5, 0, 0]}},
            {"type": "instance", "prototype": "tri", "material": "red",
             "transform": {"scale": [2, 1, 1], "rotate": [90, 0, 1, 0], "translate": [0, 0, -3]}},
            {"type": "instance", "prototype": "tri"}])"));
    const Scene& s = ls.scene;
    EXPECT_TRUE(s.meshes.empty());  // the prototype's mesh is not drawn on its own
    ASSERT_EQ(s.prototypes.size(), 1u);
    EXPECT_EQ(s.prototypes[0].name, "tri");
    ASSERT_EQ(s.prototypes[0].meshes.size(), 1u);
    EXPECT_EQ(s.prototypes[0].meshes[0].positions[1], (Vec3f{1, 0, 0}));  // object space
    ASSERT_EQ(s.instances.size(), 3u);
    EXPECT_EQ(s.instances[0].worldFromObject.applyPoint({1, 0, 0}), (Vec3f{6, 0, 0}));
    EXPECT_EQ(s.instances[0].material, kNoMaterialOverride);
    // scale, then rotate (x -> -z), then translate: (1, 0, 0) -> (2, 0, 0) -> (0, 0, -2) -> (0, 0, -5).
    const Vec3f p = s.instances[1].worldFromObject.applyPoint({1, 0, 0});
    EXPECT_NEAR(p.x, 0.f, 1e-6f);
    EXPECT_NEAR(p.z, -5.f, 1e-6f);
    EXPECT_EQ(s.materials[s.instances[1].material].name, "red");
    EXPECT_TRUE(s.instances[2].worldFromObject.isIdentity());
    EXPECT_EQ(s.triangleCount(), 3u);
}

TEST(JsonInstances, GroupsHoldSeveralMeshesAndNestedInstancesAreFlattened) {
    const std::string tri = kTriangle;
    const LoadedScene ls = loadText(withPrototypes(
        // "pair" names "tri" before it is defined: order does not matter.
        R"([{"name": "pair", "shapes": [)" + tri + R"(,
               {"type": "instance", "prototype": "tri", "transform": {"translate": [0, 0, 1]}, "material": "red"}]},
            {"name": "tri", "shapes": [)" + tri + "]}]",
        R"([{"type": "instance", "prototype": "pair"}])"));
    const Scene& s = ls.scene;
    ASSERT_EQ(s.prototypes.size(), 2u);
    const Prototype& pair = s.prototypes[s.instances[0].prototype];
    EXPECT_EQ(pair.name, "pair");
    ASSERT_EQ(pair.meshes.size(), 2u);
    EXPECT_EQ(pair.meshes[1].positions[0], (Vec3f{0, 0, 1}));  // the nested instance, copied into place
    EXPECT_EQ(s.materials[pair.meshes[1].material].name, "red");
    EXPECT_EQ(s.triangleCount(), 2u);
}

TEST(JsonInstances, ErrorsNameTheJsonPath) {
    const std::string tri = std::string(R"([{"name": "tri", "shapes": [)") + kTriangle + "]}]";
    expectError(withPrototypes(tri, R"([{"type": "instance", "prototype": "dragon"}])"), ErrorCode::InvalidScene,
                {"/shapes/0/prototype", "unknown prototype \"dragon\"", "\"tri\""});
    expectError(withPrototypes(tri, R"([{"type": "instance"}])"), ErrorCode::ParseError, {"/shapes/0", "prototype"});
    expectError(withPrototypes(tri, R"([{"type": "instance", "prototype": "tri", "transform": {"scale": [1, 0, 1]}}])"),
                ErrorCode::InvalidScene, {"/shapes/0/transform/scale", "must not be 0"});
    expectError(withPrototypes(tri, R"([{"type": "instance", "prototype": "tri", "transform": {"shear": 1}}])"),
                ErrorCode::ParseError, {"/shapes/0/transform", "shear"});
    expectError(withPrototypes(tri, R"([{"type": "instance", "prototype": "tri", "material": "gold"}])"),
                ErrorCode::InvalidScene, {"/shapes/0/material", "gold"});
    expectError(withPrototypes(tri, R"([{"type": "instance", "prototype": "tri",
                                         "transform": {"translate": [2e18, 0, 0]}}])"),
                ErrorCode::InvalidScene, {"/shapes/0", "1.8e18"});
    expectError(withPrototypes(tri, R"([{"type": "instance", "prototype": "tri", "emission": 1}])"),
                ErrorCode::ParseError, {"/shapes/0", "emission"});
    // A cycle, named where it closes.
    expectError(withPrototypes(R"([{"name": "a", "shapes": [{"type": "instance", "prototype": "b"}]},
                                   {"name": "b", "shapes": [{"type": "instance", "prototype": "a"}]}])",
                               "[]"),
                ErrorCode::InvalidScene, {"/prototypes/1/shapes/0/prototype", "prototype cycle: \"a\" -> \"b\" -> \"a\""});
    expectError(withPrototypes(R"([{"name": "a", "shapes": [{"type": "instance", "prototype": "a"}]}])", "[]"),
                ErrorCode::InvalidScene, {"/prototypes/0/shapes/0/prototype", "cycle"});
    expectError(withPrototypes(R"([{"name": "a", "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1}]}])",
                               "[]"),
                ErrorCode::InvalidScene, {"/prototypes/0/shapes/0/type", "meshes and instances only"});
    expectError(withPrototypes(R"([{"name": "a", "shapes": []}])", "[]"), ErrorCode::InvalidScene,
                {"/prototypes/0/shapes", "at least one mesh"});
    expectError(withPrototypes(tri.substr(0, tri.size() - 1) + R"(, {"name": "tri", "shapes": []}])", "[]"),
                ErrorCode::InvalidScene, {"/prototypes/1/name", "defined twice"});
    expectError(withPrototypes(R"([{"shapes": []}])", "[]"), ErrorCode::ParseError, {"/prototypes/0", "name"});
    expectError(withPrototypes(R"({"tri": 1})", "[]"), ErrorCode::ParseError, {"/prototypes"});
    expectError(R"({"shapes": [{"type": "instance", "prototype": "x"}]})", ErrorCode::InvalidScene,
                {"/shapes/0/prototype", "no \"prototypes\""});
}

/// Prototypes "p0" .. "pN" as a JSON list: p0 holds a triangle, each other
/// one places the next lower `copies` times (outermost first when `outermostFirst`).
std::string prototypeList(int levels, int copies, bool outermostFirst = false) {
    std::vector<std::string> entries;
    entries.push_back(std::string(R"({"name": "p0", "shapes": [)") + kTriangle + "]}");
    for (int i = 1; i <= levels; ++i) {
        std::string shapes;
        for (int c = 0; c < copies; ++c)
            shapes += std::string(c ? ", " : "") + R"({"type": "instance", "prototype": "p)" + std::to_string(i - 1) +
                      R"(", "transform": {"translate": [)" + std::to_string(c) + ", 0, 0]}}";
        entries.push_back(R"({"name": "p)" + std::to_string(i) + R"(", "shapes": [)" + shapes + "]}");
    }
    if (outermostFirst) std::reverse(entries.begin(), entries.end());
    std::string list;
    for (const std::string& e : entries) list += (list.empty() ? "" : ",\n") + e;
    return "[" + list + "]";
}

/// The chain of prototypeList, its outermost prototype placed once.
std::string prototypeChain(int levels, int copies, bool outermostFirst = false) {
    return withPrototypes(prototypeList(levels, copies, outermostFirst),
                          R"([{"type": "instance", "prototype": "p)" + std::to_string(levels) + "\"}]");
}

// The resolver walked 10,000 levels with 10,000 nested calls and overflowed
// the stack; it is a loop now, so depth costs memory, not stack.
TEST(JsonInstances, PrototypesNestedTenThousandDeepOutermostFirstLoad) {
    const LoadedScene s = loadText(prototypeChain(10000, 1, true));
    EXPECT_EQ(s.scene.prototypes.size(), 10001u);
    EXPECT_EQ(s.scene.triangleCount(), 1u);
    EXPECT_EQ(loadText(prototypeChain(10000, 1)).scene.triangleCount(), 1u);
}

// 40 levels each placing the one below twice: 2^41 - 2 triangles of copies
// from under 8 KB of JSON, refused before any copy is made.
TEST(JsonInstances, NestedPlacementsThatWouldCopyTooMuchAreRefusedWithTheCount) {
    const std::string json = prototypeChain(40, 2);
    EXPECT_LT(json.size(), 8000u);
    expectError(json, ErrorCode::InvalidScene,
                {"/prototypes", "2199023255550 triangles", "6597069766650 vertices", "100000000"});
    // 2^12 triangles of copies are fine.
    EXPECT_EQ(loadText(prototypeChain(12, 2)).scene.triangleCount(), size_t(1) << 12);
}

// Emissive instances become meshes in Scene::finalize: a JSON file's are
// counted at load, so that the error names the file. 12,300 emissive copies
// of 8,192 triangles pass 100 million.
TEST(JsonInstances, EmissiveInstancesThatWouldCopyTooMuchAreRefusedAtLoad) {
    std::string instances;
    for (int i = 0; i < 12300; ++i)
        instances += std::string(i ? ", " : "") + R"({"type": "instance", "prototype": "p13", "material": "lamp"})";
    expectError(withPrototypes(prototypeList(13, 2), "[" + instances + "]"), ErrorCode::InvalidScene,
                {"emissive instances", "100777982 triangles"});
}

TEST(JsonInstances, TheExampleSceneExpandsItsLanternsIntoLights) {
    LoadedScene ls = loadJsonScene(assetPath("scenes/instancing.json"), LoadOptions{}, Logger());
    Scene& s = ls.scene;
    ASSERT_EQ(s.prototypes.size(), 2u);
    EXPECT_EQ(s.prototypes[0].meshes.size(), 2u);  // trunk and crown
    EXPECT_EQ(s.instances.size(), 11u);
    EXPECT_TRUE(s.meshes.empty());
    s.finalize(Logger());
    EXPECT_EQ(s.instances.size(), 9u);  // the trees
    ASSERT_EQ(s.meshes.size(), 2u);     // the lanterns, placed
    for (const TriangleMesh& m : s.meshes) EXPECT_TRUE(s.materials[m.material].isEmissive());
    EXPECT_EQ(s.meshes[0].positions[0], (Vec3f{-1.5f, 0.2f, 2.f}));
    EXPECT_EQ(s.triangleCount(), 9u * 14u + 2u * 2u);
}

// Issue 17's case: twenty dragons keep one dragon's vertices (the memory
// itself is measured by scripts/bench_instancing.py, docs/benchmarks.md).
TEST(JsonInstances, TwentyDragonsStoreOneDragon) {
    const fs::path dragon = sharedScenePath("dragon_100k/dragon.obj");
    if (dragon.empty() || !fs::exists(dragon)) GTEST_SKIP() << "../shared/scenes/dragon_100k is absent";
    std::string shapes = "[";
    for (int i = 0; i < 20; ++i)
        shapes += std::string(i ? "," : "") + R"({"type": "instance", "prototype": "dragon", "transform": {"translate": [)" +
                  std::to_string(16 * (i % 5)) + ", 0, " + std::to_string(-12 * (i / 5)) + "]}}";
    shapes += "]";
    const LoadedScene ls = loadText(withPrototypes(
        R"([{"name": "dragon", "shapes": [{"type": "mesh", "file": ")" + dragon.string() + R"("}]}])", shapes));
    const Scene& s = ls.scene;
    ASSERT_EQ(s.prototypes.size(), 1u);
    EXPECT_TRUE(s.meshes.empty());
    EXPECT_EQ(s.instances.size(), 20u);
    const size_t one = s.prototypes[0].triangleCount();
    EXPECT_EQ(one, 100000u);
    EXPECT_EQ(s.triangleCount(), 20 * one);
    size_t vertices = 0;
    for (const TriangleMesh& m : s.prototypes[0].meshes) vertices += m.positions.size();
    EXPECT_GT(vertices, 40000u);  // one dragon's worth, held once
    const Bounds3f b = s.bounds();
    EXPECT_NEAR(b.hi.x - b.lo.x, 64.f + 14.09f, 0.1f);  // 5 columns 16 apart, the dragon 14.09 wide
}

}  // namespace
}  // namespace penumbra
