// The environment light through the C++ and C APIs, and the default light of
// scenes without any (seen through PreparedScene::defaultLightAdded, turned off
// with Scene::setDefaultLight).
#include <gtest/gtest.h>

#include <cmath>
#include <penumbra/penumbra.h>
#include <penumbra/penumbra.hpp>
#include <string>
#include <vector>

#include "core/film.h"
#include "core/image_io.h"
#include "support/test_support.h"

namespace {

// A grey floor seen from above: kd 0.5 under whatever lights it.
pnb::Scene floorScene() {
    pnb::Scene s;
    pnb::Material m;
    m.kd = pnb::gray(0.5f);
    const pnb::MaterialId id = s.addMaterial(m);
    s.addPlane({0, 0, 0}, {0, 1, 0}, id);
    return s;
}

pnb::Camera topCamera() {
    pnb::Camera c;
    c.eye = {0, 2, 0};
    c.lookAt = {0, 0, 0};
    c.up = {0, 0, -1};
    c.vfovDegrees = 30.f;
    return c;
}

pnb::RenderSettings smallSettings() {
    pnb::RenderSettings s;
    s.width = s.height = 8;
    s.spp = 16;
    s.lightSamples = 16;
    return s;
}

double meanGreen(const pnb::Framebuffer& fb) {
    double sum = 0;
    for (int y = 0; y < fb.height(); ++y)
        for (int x = 0; x < fb.width(); ++x) sum += fb.pixel(x, y).g;
    return sum / (fb.width() * fb.height());
}

}  // namespace

TEST(ApiEnvironment, ConstantEnvironmentLightsTheFloor) {
    std::vector<std::string> warnings;
    pnb::Renderer r([&](pnb::LogLevel, std::string_view m) { warnings.emplace_back(m); });
    pnb::Scene s = floorScene();
    EXPECT_FALSE(s.hasEnvironment());
    s.setEnvironment({0.2f, 0.4f, 0.8f}, 2.f);
    EXPECT_TRUE(s.hasEnvironment());
    const pnb::PreparedScene p = r.prepare(s);
    EXPECT_FALSE(p.defaultLightAdded());
    EXPECT_EQ(p.lightCount(), 1u);  // the environment is a light
    EXPECT_NEAR(meanGreen(r.render(p, topCamera(), smallSettings())), 0.5 * 0.8, 0.01);
    EXPECT_TRUE(warnings.empty());
    EXPECT_THROW(s.setEnvironment({-1.f, 0.f, 0.f}), pnb::Error);
    EXPECT_THROW(s.setEnvironment({1.f, 1.f, 1.f}, NAN), pnb::Error);
    s.clearEnvironment();
    EXPECT_FALSE(s.hasEnvironment());
}

TEST(ApiEnvironment, DefaultLightIsVisibleAndCanBeTurnedOff) {
    std::vector<std::string> warnings;
    pnb::Renderer r([&](pnb::LogLevel level, std::string_view m) {
        if (level == pnb::LogLevel::Warning) warnings.emplace_back(m);
    });
    pnb::Scene s = floorScene();
    EXPECT_TRUE(s.defaultLight());
    pnb::PreparedScene lit = r.prepare(s);
    EXPECT_TRUE(lit.defaultLightAdded());
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("no light"), std::string::npos) << warnings[0];
    EXPECT_NEAR(meanGreen(r.render(lit, topCamera(), smallSettings())), 0.5, 0.01);

    s.setDefaultLight(false);
    warnings.clear();
    pnb::PreparedScene dark = r.prepare(s);
    EXPECT_FALSE(dark.defaultLightAdded());
    EXPECT_TRUE(warnings.empty());
    EXPECT_EQ(meanGreen(r.render(dark, topCamera(), smallSettings())), 0.0);

    // Any light at all (here a background) means no default.
    s.setDefaultLight(true);
    s.setBackground(pnb::gray(0.1f));
    EXPECT_FALSE(r.prepare(s).defaultLightAdded());
}

TEST(ApiEnvironment, ImageErrorsNameTheFile) {
    pnb::Renderer r([](pnb::LogLevel, std::string_view) {}, pnb::LogLevel::Error);
    pnb::Scene s = floorScene();
    const std::filesystem::path dir = penumbra::test::tempDir();
    try {
        s.setEnvironmentImage((dir / "absent.exr").string());
        FAIL() << "no error";
    } catch (const pnb::Error& e) {
        EXPECT_EQ(e.code(), pnb::ErrorCode::FileNotFound);
        EXPECT_NE(std::string(e.what()).find("absent.exr"), std::string::npos) << e.what();
    }
    const auto bad = penumbra::test::writeFile(dir / "bad.hdr", "not an image");
    s.setEnvironmentImage(bad.string(), 45.f);  // opened now, decoded by prepare
    try {
        (void)r.prepare(s);
        FAIL() << "no error";
    } catch (const pnb::Error& e) {
        EXPECT_EQ(e.code(), pnb::ErrorCode::IoError);
        EXPECT_NE(std::string(e.what()).find("bad.hdr: cannot read image"), std::string::npos) << e.what();
    }
}

TEST(CApiEnvironment, SetEnvironmentAndSeeTheDefaultLight) {
    pnb_renderer* r = nullptr;
    ASSERT_EQ(pnb_renderer_create(&r), PNB_OK);
    pnb_renderer_set_log(r, nullptr, nullptr, PNB_LOG_ERROR);
    pnb_scene* s = nullptr;
    ASSERT_EQ(pnb_scene_create(&s), PNB_OK);
    pnb_material m;
    pnb_material_init(&m);
    uint32_t id = 0;
    ASSERT_EQ(pnb_scene_add_material(s, &m, &id), PNB_OK);
    ASSERT_EQ(pnb_scene_add_plane(s, pnb_vec3{0, 0, 0}, pnb_vec3{0, 1, 0}, 1, id), PNB_OK);
    pnb_prepared_scene* p = nullptr;
    pnb_prepared_info info{};
    ASSERT_EQ(pnb_prepare(r, s, nullptr, &p), PNB_OK);
    ASSERT_EQ(pnb_prepared_scene_get_info(p, &info), PNB_OK);
    EXPECT_EQ(info.default_light_added, 1);
    pnb_prepared_scene_destroy(p);

    ASSERT_EQ(pnb_scene_set_environment(s, pnb_color{1, 1, 1}, 0.5f), PNB_OK);
    ASSERT_EQ(pnb_prepare(r, s, nullptr, &p), PNB_OK);
    ASSERT_EQ(pnb_prepared_scene_get_info(p, &info), PNB_OK);
    EXPECT_EQ(info.default_light_added, 0);
    EXPECT_EQ(info.light_count, 1u);
    pnb_prepared_scene_destroy(p);

    ASSERT_EQ(pnb_scene_clear_environment(s), PNB_OK);
    ASSERT_EQ(pnb_scene_set_default_light(s, 0), PNB_OK);
    ASSERT_EQ(pnb_prepare(r, s, nullptr, &p), PNB_OK);
    ASSERT_EQ(pnb_prepared_scene_get_info(p, &info), PNB_OK);
    EXPECT_EQ(info.default_light_added, 0);
    EXPECT_EQ(info.light_count, 0u);
    pnb_prepared_scene_destroy(p);

    EXPECT_EQ(pnb_scene_set_environment(s, pnb_color{-1, 0, 0}, 1.f), PNB_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(pnb_scene_set_environment_image(s, "/nonexistent/sky.exr", 0.f, 1.f), PNB_ERROR_FILE_NOT_FOUND);
    EXPECT_NE(std::string(pnb_scene_last_error(s)).find("sky.exr"), std::string::npos);
    pnb_scene_destroy(s);
    pnb_renderer_destroy(r);
}

TEST(ApiEnvironment, JsonImageIsReadFromTheFileOpenedAtLoadAndKeptInsideTheRoots) {
    namespace fs = std::filesystem;
    const fs::path dir = penumbra::test::tempDir();
    // A uniform lat-long image of radiance 2.
    penumbra::Film film(8, 4, false);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) film.addRadiance(film.index(x, y), penumbra::Rgb(2.f));
    film.setSampleCount(1);
    fs::create_directories(dir / "scene");
    penumbra::writeImage(dir / "sky.exr", film, penumbra::ImageWriteOptions{});
    penumbra::writeImage(dir / "scene" / "sky.exr", film, penumbra::ImageWriteOptions{});
    penumbra::test::writeFile(dir / "scene" / "floor.json", R"({
  "materials": {"grey": {"kd": 0.5}},
  "shapes": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "grey"}],
  "environment": {"image": "sky.exr", "rotate": 45}
})");
    pnb::Renderer r([](pnb::LogLevel, std::string_view) {}, pnb::LogLevel::Error);
    pnb::Scene s = r.loadScene((dir / "scene" / "floor.json").string());
    EXPECT_TRUE(s.hasEnvironment());
    // Swapped for garbage after loading: the open file is what is decoded, never the path again.
    fs::remove(dir / "scene" / "sky.exr");
    penumbra::test::writeFile(dir / "scene" / "sky.exr", "garbage");
    const pnb::PreparedScene p = r.prepare(s);
    EXPECT_NEAR(meanGreen(r.render(p, topCamera(), smallSettings())), 0.5 * 2.0, 0.02);

    // Like textures, an environment image outside the scene's folder is refused by default.
    penumbra::test::writeFile(dir / "scene" / "outside.json", R"({"environment": {"image": "../sky.exr"}})");
    try {
        (void)r.loadScene((dir / "scene" / "outside.json").string());
        FAIL() << "no error";
    } catch (const pnb::Error& e) {
        EXPECT_EQ(e.code(), pnb::ErrorCode::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("/environment/image"), std::string::npos) << e.what();
    }
}
