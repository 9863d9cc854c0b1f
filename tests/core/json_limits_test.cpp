// The JSON loader at its limits (issue 13 items 9 and 10): integers that a
// double cannot hold exactly, values that overflow a float (each with its own
// reason), geometry beyond what the accelerators represent, and errors about
// very deep documents that stay one short line.
#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "core/io/scene_loader.h"
#include "core/scene_range.h"
#include "support/test_support.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

Error loadError(const std::string& json) {
    fs::path p = test::writeFile(test::tempDir() / "scene.json", json);
    try {
        loadJsonScene(p, {}, Logger());
    } catch (const Error& e) {
        return e;
    }
    return Error(ErrorCode::Internal, "no error");
}

void expectError(const std::string& json, ErrorCode code, std::initializer_list<std::string_view> has,
                 std::initializer_list<std::string_view> hasNot = {}) {
    Error e = loadError(json);
    const std::string msg = e.what();
    EXPECT_EQ(e.code(), code) << msg;
    for (auto n : has) EXPECT_NE(msg.find(n), std::string::npos) << "'" << n << "' not in: " << msg;
    for (auto n : hasNot) EXPECT_EQ(msg.find(n), std::string::npos) << "'" << n << "' in: " << msg;
}

TEST(JsonLimits, SeedBeyondWhatADoubleHoldsExactlyIsAClearError) {
    // 9223372036854775807.0 reads as 2^63: converting it to int64 was undefined behaviour.
    expectError(R"({"render": {"seed": 9223372036854775807.0}})", ErrorCode::ParseError,
                {"/render/seed", "too large to be exact", "without a fraction or exponent"});
    expectError(R"({"render": {"seed": 1e19}})", ErrorCode::ParseError, {"/render/seed", "too large to be exact"});
    // Written as integers, every uint64 seed still loads exactly.
    fs::path p = test::writeFile(test::tempDir() / "s.json", R"({"render": {"seed": 18446744073709551615}})");
    EXPECT_EQ(loadJsonScene(p, {}, Logger()).settings.seed, 18446744073709551615ull);
    fs::path q = test::writeFile(test::tempDir() / "t.json", R"({"render": {"seed": 4096.0}})");
    EXPECT_EQ(loadJsonScene(q, {}, Logger()).settings.seed, 4096u);
}

TEST(JsonLimits, OverflowingValuesGetTheirOwnReason) {
    expectError(R"({"shapes": [{"type": "rectangle", "p0": [0, 0, 0], "a": [1e30, 0, 0], "b": [0, 0, 1e30]}]})",
                ErrorCode::InvalidScene, {"/shapes/0", "overflows"}, {"zero area"});
    expectError(R"({"shapes": [{"type": "box", "min": [0, 0, 0], "max": [1, 1, 1],
                                "transform": {"scale": [1e20, 1e20, 1e20]}}]})",
                ErrorCode::InvalidScene, {"/shapes/0/transform", "overflows"}, {"singular"});
    expectError(R"({"camera": {"eye": [3e38, 0, 0], "look_at": [-3e38, 0, 0]}})", ErrorCode::InvalidScene,
                {"/camera", "overflows"}, {"same point", "parallel"});
    expectError(R"({"camera": {"eye": [0, 0, 5], "look_at": [0, 0, 0], "up": [0, 1e20, 0]}})",
                ErrorCode::InvalidScene, {"/camera/up", "overflows"}, {"parallel"});
    expectError(R"({"lights": [{"type": "directional", "direction": [0, -1e20, 0], "irradiance": 1}]})",
                ErrorCode::InvalidScene, {"/lights/0/direction", "overflows"}, {"zero vector"});
}

TEST(JsonLimits, GeometryBeyondTheAcceleratorsRangeIsRefused) {
    expectError(R"({"lights": [{"type": "disk", "center": [0, 5, 0], "normal": [0, -1, 0], "radius": 1e19,
                                "radiance": 1}]})",
                ErrorCode::InvalidScene, {"/lights/0", "beyond", "1.8e18"});
    expectError(R"({"shapes": [{"type": "sphere", "center": [2e18, 0, 0], "radius": 1}]})", ErrorCode::InvalidScene,
                {"/shapes/0", "beyond"});
    expectError(R"({"shapes": [{"type": "mesh", "vertices": [[0, 0, 0], [1e19, 0, 0], [0, 1, 0]],
                                "indices": [[0, 1, 2]]}]})",
                ErrorCode::InvalidScene, {"/shapes/0/vertices", "beyond"});
    // Just inside the range loads.
    fs::path p = test::writeFile(test::tempDir() / "ok.json",
                                 R"({"shapes": [{"type": "sphere", "center": [1e18, 0, 0], "radius": 1e17}]})");
    EXPECT_EQ(loadJsonScene(p, {}, Logger()).scene.spheres.size(), 1u);
}

TEST(JsonLimits, FinalizeDropsWhatLiesBeyondTheRangeForEveryAccelerator) {
    Scene s;
    s.disks.push_back(Disk{{0.f, 5.f, 0.f}, {0.f, -1.f, 0.f}, 1e19f, 0});
    s.disks.push_back(Disk{{0.f, 5.f, 0.f}, {0.f, -1.f, 0.f}, 1.f, 0});
    TriangleMesh m;
    for (Vec3f p : {Vec3f{0.f, 0.f, 0.f}, Vec3f{1.f, 0.f, 0.f}, Vec3f{0.f, 1.f, 0.f}, Vec3f{3e18f, 0.f, 0.f}})
        m.positions.push_back(p);
    m.indices = {0, 1, 2, 0, 3, 2};
    s.meshes.push_back(m);
    std::vector<std::string> warnings;
    Logger log([&](LogLevel l, std::string_view msg) {
        if (l >= LogLevel::Warning) warnings.emplace_back(msg);
    });
    SceneFixups fix = s.finalize(log);
    EXPECT_EQ(s.disks.size(), 1u);
    EXPECT_EQ(s.disks[0].radius, 1.f);
    ASSERT_EQ(s.meshes.size(), 1u);
    EXPECT_EQ(s.meshes[0].triangleCount(), 1u);
    EXPECT_EQ(fix.droppedShapes, 1u);
    EXPECT_EQ(fix.droppedTriangles, 1u);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("beyond"), std::string::npos) << warnings[0];
    EXPECT_TRUE(withinSceneRange(Vec3f{1e18f, -1e18f, 0.f}));
    EXPECT_FALSE(withinSceneRange(Vec3f{0.f, 0.f, 1.9e18f}));
}

TEST(JsonLimits, DuplicateKeyFiftyThousandLevelsDeepGivesAShortMessage) {
    constexpr int kDepth = 50000;
    std::string json;
    for (int i = 0; i < kDepth; ++i) json += "{\"a\": ";
    json += "{\"k\": 1, \"k\": 2}";
    for (int i = 0; i < kDepth; ++i) json += "}";
    Error e = loadError(json);
    const std::string msg = e.what();
    EXPECT_EQ(e.code(), ErrorCode::ParseError);
    EXPECT_LT(msg.size(), 400u) << msg.substr(0, 400);
    EXPECT_NE(msg.find("scene.json: /a/a/a"), std::string::npos) << msg;
    EXPECT_NE(msg.find("levels"), std::string::npos) << msg;
    EXPECT_NE(msg.find("/a/a/k: duplicate key"), std::string::npos) << msg;
}

TEST(JsonLimits, DuplicateKeysAreFoundInLargeObjectsToo) {
    std::string json = R"({"materials": {)";
    for (int i = 0; i < 1000; ++i) json += "\"m" + std::to_string(i) + "\": {\"kd\": 0.5}, ";
    json += R"("m500": {"kd": 0.1}}})";
    expectError(json, ErrorCode::ParseError, {"/materials/m500", "duplicate key"});
    std::string nested = R"({"shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1},
                                      {"type": "sphere", "center": [0, 0, 0], "radius": 1, "radius": 2}]})";
    expectError(nested, ErrorCode::ParseError, {"/shapes/1/radius", "duplicate key"});
}

}  // namespace
}  // namespace penumbra
