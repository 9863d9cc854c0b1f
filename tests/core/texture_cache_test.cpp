// TextureCache: texel values at known uv (v up, sRGB decoded), periodic
// wrapping, MIP filtering over a footprint, grey images, float images kept
// linear, missing files disabled with a warning, and concurrent lookups.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "core/texture_cache.h"
#include "support/test_support.h"

namespace penumbra {
namespace {
namespace fs = std::filesystem;

float srgbToLinear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

struct Warnings {
    std::vector<std::string> lines;
    Logger logger{[this](LogLevel level, std::string_view m) {
        if (level == LogLevel::Warning) lines.emplace_back(m);
    }};
    Warnings() = default;
    Warnings(const Warnings&) = delete;
};

// Writes an image of w x h pixels with `channels` channels; `px` holds the rows top first.
template <class T>
fs::path writeImage(const fs::path& path, int w, int h, int channels, const std::vector<T>& px, OIIO::TypeDesc type) {
    auto out = OIIO::ImageOutput::create(path.string());
    if (!out) return {};
    OIIO::ImageSpec spec(w, h, channels, type);
    if (!out->open(path.string(), spec)) return {};
    if (!out->write_image(type, px.data())) return {};
    out->close();
    return path;
}

void expectRgb(const Rgb& c, float r, float g, float b, float eps = 1e-4f) {
    EXPECT_NEAR(c.r, r, eps);
    EXPECT_NEAR(c.g, g, eps);
    EXPECT_NEAR(c.b, b, eps);
}

// 2x2 RGB: top row red, green; bottom row blue, 50% grey (sRGB 128).
fs::path writeQuadrants(const fs::path& dir) {
    std::vector<unsigned char> px = {255, 0, 0, 0, 255, 0, 0, 0, 255, 128, 128, 128};
    return writeImage(dir / "quad.png", 2, 2, 3, px, OIIO::TypeDesc::UINT8);
}

TEST(TextureCache, TexelsAtKnownUvWithVUp) {
    fs::path png = writeQuadrants(test::tempDir());
    ASSERT_FALSE(png.empty());
    Warnings w;
    TextureCache cache({png.string()}, w.logger);
    EXPECT_TRUE(w.lines.empty());
    ASSERT_EQ(cache.size(), 1u);
    EXPECT_TRUE(cache.enabled(0));
    // Texel centres; v = 1 is the top row of the image.
    expectRgb(cache.lookup(0, {0.25f, 0.75f}, 0.f), 1, 0, 0);
    expectRgb(cache.lookup(0, {0.75f, 0.75f}, 0.f), 0, 1, 0);
    expectRgb(cache.lookup(0, {0.25f, 0.25f}, 0.f), 0, 0, 1);
    const float grey = srgbToLinear(128.f / 255.f);  // 0.2158: decoded, not 0.502
    expectRgb(cache.lookup(0, {0.75f, 0.25f}, 0.f), grey, grey, grey);
}

TEST(TextureCache, WrapsPeriodically) {
    fs::path png = writeQuadrants(test::tempDir());
    Warnings w;
    TextureCache cache({png.string()}, w.logger);
    expectRgb(cache.lookup(0, {1.25f, 0.75f}, 0.f), 1, 0, 0);
    expectRgb(cache.lookup(0, {-0.25f, -0.25f}, 0.f), 0, 1, 0);  // v -0.25 = 0.75: top row
    expectRgb(cache.lookup(0, {3.75f, 5.25f}, 0.f), srgbToLinear(128.f / 255.f), srgbToLinear(128.f / 255.f),
              srgbToLinear(128.f / 255.f));
}

TEST(TextureCache, WideFootprintAveragesTheTexels) {
    // An 8x8 black/white checker: a footprint as wide as the texture reads the
    // 1x1 MIP level, the encoded average 0.5 (filtering happens before decoding).
    std::vector<unsigned char> px(8 * 8);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) px[y * 8 + x] = ((x + y) & 1) ? 255 : 0;
    fs::path png = writeImage(test::tempDir() / "checker.png", 8, 8, 1, px, OIIO::TypeDesc::UINT8);
    ASSERT_FALSE(png.empty());
    Warnings w;
    TextureCache cache({png.string()}, w.logger);
    Rgb sharp = cache.lookup(0, {0.5f / 8.f, 0.5f / 8.f}, 0.f);
    EXPECT_TRUE(sharp.r == 0.f || sharp.r == 1.f) << sharp.r;
    Rgb wide = cache.lookup(0, {0.3f, 0.6f}, 1.f);
    const float half = srgbToLinear(0.5f);
    expectRgb(wide, half, half, half, 0.01f);  // grey image: all channels equal
}

TEST(TextureCache, FloatImagesStayLinear) {
    std::vector<float> px = {0.5f, 0.25f, 2.f};
    fs::path exr = writeImage(test::tempDir() / "linear.exr", 1, 1, 3, px, OIIO::TypeDesc::FLOAT);
    if (exr.empty()) GTEST_SKIP() << "no OpenEXR writer";
    Warnings w;
    TextureCache cache({exr.string()}, w.logger);
    expectRgb(cache.lookup(0, {0.5f, 0.5f}, 0.f), 0.5f, 0.25f, 2.f);
}

TEST(TextureCache, MissingAndInvalidTexturesAreDisabled) {
    fs::path dir = test::tempDir();
    fs::path png = writeQuadrants(dir);
    test::writeFile(dir / "junk.png", "this is not a PNG");
    Warnings w;
    TextureCache cache({(dir / "absent.png").string(), png.string(), (dir / "junk.png").string()}, w.logger);
    ASSERT_EQ(w.lines.size(), 2u);
    EXPECT_NE(w.lines[0].find("absent.png"), std::string::npos) << w.lines[0];
    EXPECT_NE(w.lines[1].find("junk.png"), std::string::npos) << w.lines[1];
    EXPECT_FALSE(cache.enabled(0));
    EXPECT_TRUE(cache.enabled(1));
    EXPECT_FALSE(cache.enabled(2));
    expectRgb(cache.lookup(0, {0.25f, 0.75f}, 0.f), 1, 1, 1);
    expectRgb(cache.lookup(1, {0.25f, 0.75f}, 0.f), 1, 0, 0);
    expectRgb(cache.lookup(-1, {0.25f, 0.75f}, 0.f), 1, 1, 1);
    expectRgb(cache.lookup(7, {0.25f, 0.75f}, 0.f), 1, 1, 1);
    expectRgb(cache.lookup(1, {NAN, 0.5f}, 0.f), 1, 1, 1);
}

TEST(TextureCache, ConcurrentLookupsAgree) {
    fs::path png = writeQuadrants(test::tempDir());
    Warnings w;
    TextureCache cache({png.string()}, w.logger);
    std::vector<int> wrong(4, 0);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            for (int i = 0; i < 2000; ++i) {
                Rgb c = cache.lookup(0, {0.25f + static_cast<float>(i % 3), 0.75f}, 0.f);
                if (std::fabs(c.r - 1.f) > 1e-4f || c.g > 1e-4f || c.b > 1e-4f) ++wrong[t];
            }
        });
    for (auto& th : threads) th.join();
    for (int t = 0; t < 4; ++t) EXPECT_EQ(wrong[t], 0) << t;
}

TEST(TextureCache, TwoCachesAreIndependent) {
    fs::path dir = test::tempDir();
    fs::path png = writeQuadrants(dir);
    Warnings w;
    {
        TextureCache first({png.string()}, w.logger);
        expectRgb(first.lookup(0, {0.25f, 0.75f}, 0.f), 1, 0, 0);
    }
    // The first cache is gone; a new one over a rewritten file sees the new content.
    std::vector<unsigned char> px = {0, 0, 255, 0, 0, 255, 0, 0, 255, 0, 0, 255};
    ASSERT_FALSE(writeImage(png, 2, 2, 3, px, OIIO::TypeDesc::UINT8).empty());
    TextureCache second({png.string()}, w.logger);
    expectRgb(second.lookup(0, {0.25f, 0.75f}, 0.f), 0, 0, 1);
}

}  // namespace
}  // namespace penumbra
