// The JSON "environment" block: colour or image (opened at load), rotate and
// scale, errors naming the JSON path, and the example scene that uses it.
#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "core/io/input_file.h"
#include "core/io/scene_loader.h"
#include "support/test_support.h"

using namespace penumbra;
using namespace penumbra::test;
namespace fs = std::filesystem;

namespace {

LoadedScene loadText(const std::string& json, const fs::path& dir) {
    return loadJsonScene(writeFile(dir / "scene.json", json), {}, Logger());
}

std::string errorOf(const std::string& json, const fs::path& dir) {
    try {
        (void)loadText(json, dir);
    } catch (const Error& e) {
        return e.what();
    }
    return "no error";
}

}  // namespace

TEST(JsonEnvironment, ColourAndImageWithRotateAndScale) {
    const fs::path dir = tempDir();
    LoadedScene s = loadText(R"({"environment": {"color": [0.1, 0.2, 0.3], "scale": 2}})", dir);
    ASSERT_TRUE(s.scene.environment.has_value());
    EXPECT_EQ(s.scene.environment->color, (Rgb{0.1f, 0.2f, 0.3f}));
    EXPECT_EQ(s.scene.environment->scale, 2.f);
    EXPECT_TRUE(s.scene.environment->image.empty());

    writeFile(dir / "sky.hdr", "not decoded at load");
    s = loadText(R"({"environment": {"image": "sky.hdr", "rotate": -30}})", dir);
    ASSERT_TRUE(s.scene.environment.has_value());
    EXPECT_EQ(fs::path(s.scene.environment->image), (dir / "sky.hdr").lexically_normal());
    EXPECT_EQ(s.scene.environment->rotateDegrees, -30.f);
    EXPECT_EQ(s.scene.environment->scale, 1.f);
    ASSERT_NE(s.scene.environment->imageFile, nullptr);  // opened once, here
    EXPECT_GE(s.scene.environment->imageFile->fd(), 0);
    EXPECT_FALSE(loadText("{}", dir).scene.environment.has_value());
}

TEST(JsonEnvironment, ErrorsNameTheJsonPath) {
    const fs::path dir = tempDir();
    const auto has = [](const std::string& what, const std::string& needle) {
        return what.find(needle) != std::string::npos;
    };
    std::string e = errorOf(R"({"environment": {"color": 1, "image": "a.exr"}})", dir);
    EXPECT_TRUE(has(e, "/environment: give \"color\" or \"image\", not both")) << e;
    e = errorOf(R"({"environment": {"scale": 1}})", dir);
    EXPECT_TRUE(has(e, "/environment: needs \"color\" or \"image\"")) << e;
    e = errorOf(R"({"environment": {"color": 1, "scale": -1}})", dir);
    EXPECT_TRUE(has(e, "/environment/scale")) << e;
    e = errorOf(R"({"environment": {"color": [1, -1, 0]}})", dir);
    EXPECT_TRUE(has(e, "/environment/color")) << e;
    e = errorOf(R"({"environment": {"color": 1, "rotation": 3}})", dir);
    EXPECT_TRUE(has(e, "/environment/rotation")) << e;
    e = errorOf(R"({"environment": {"image": "missing.exr"}})", dir);
    EXPECT_TRUE(has(e, "/environment/image")) << e;
    EXPECT_TRUE(has(e, "missing.exr: file not found")) << e;
    e = errorOf(R"({"environment": [1, 1, 1]})", dir);
    EXPECT_TRUE(has(e, "/environment")) << e;
}

TEST(JsonEnvironment, ExampleSceneUsesTheGeneratedSky) {
    const LoadedScene s = loadJsonScene(assetPath("scenes/environment.json"), {}, Logger());
    ASSERT_TRUE(s.scene.environment.has_value());
    EXPECT_EQ(fs::path(s.scene.environment->image).filename(), "sky.pfm");
    EXPECT_NE(s.scene.environment->imageFile, nullptr);
    EXPECT_TRUE(s.scene.hasLight());
}
