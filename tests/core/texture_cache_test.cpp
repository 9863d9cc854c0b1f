// TextureCache: texel values at known uv (v up, sRGB decoded), periodic
// wrapping, MIP filtering over a footprint, grey images, float images kept
// linear, missing files disabled with a warning, and concurrent lookups; a
// material slot's sampling: images from memory, colour spaces, alpha, the
// wrap modes, the nearest filter, transforms, one channel, normals, 16 bits,
// height maps.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <memory>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "core/texture_cache.h"
#include "support/test_support.h"

namespace penumbra {
namespace {

/// Texture sources for files named in code (with the loader's descriptors, where given).
std::vector<TextureSource> files(const std::vector<std::string>& names, const std::vector<int>& fds = {}) {
    std::vector<TextureSource> out;
    for (size_t i = 0; i < names.size(); ++i) out.push_back({names[i], TextureColorSpace::FromFile, i < fds.size() ? fds[i] : -1});
    return out;
}
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
    spec.attribute("oiio:UnassociatedAlpha", 1);  // an alpha channel's texels as given
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
    TextureCache cache(files({png.string()}), w.logger);
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
    TextureCache cache(files({png.string()}), w.logger);
    expectRgb(cache.lookup(0, {1.25f, 0.75f}, 0.f), 1, 0, 0);
    expectRgb(cache.lookup(0, {-0.25f, -0.25f}, 0.f), 0, 1, 0);  // v -0.25 = 0.75: top row
    expectRgb(cache.lookup(0, {3.75f, 5.25f}, 0.f), srgbToLinear(128.f / 255.f), srgbToLinear(128.f / 255.f),
              srgbToLinear(128.f / 255.f));
}

TEST(TextureCache, WideFootprintAveragesTheTexels) {
    // An 8x8 black/white checker: a footprint as wide as the texture reads the
    // 1x1 MIP level, the average of the light, 0.5 (texels are decoded before
    // they are averaged), within the step of the 8-bit code the level keeps.
    std::vector<unsigned char> px(8 * 8);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) px[y * 8 + x] = ((x + y) & 1) ? 255 : 0;
    fs::path png = writeImage(test::tempDir() / "checker.png", 8, 8, 1, px, OIIO::TypeDesc::UINT8);
    ASSERT_FALSE(png.empty());
    Warnings w;
    TextureCache cache(files({png.string()}), w.logger);
    Rgb sharp = cache.lookup(0, {0.5f / 8.f, 0.5f / 8.f}, 0.f);
    EXPECT_TRUE(sharp.r == 0.f || sharp.r == 1.f) << sharp.r;
    Rgb wide = cache.lookup(0, {0.3f, 0.6f}, 1.f);
    expectRgb(wide, 0.5f, 0.5f, 0.5f, 0.005f);  // grey image: all channels equal
}

TEST(TextureCache, MipLevelsAverageLinearValues) {
    // A 2x2 RGB checker of sRGB codes 0 and 255: its coarsest level is linear
    // 0.5 (code 188), not the decoded average code srgbToLinear(127.5 / 255) = 0.21.
    const std::vector<unsigned char> px = {0, 0, 0, 255, 255, 255, 255, 255, 255, 0, 0, 0};
    const fs::path png = writeImage(test::tempDir() / "checker2.png", 2, 2, 3, px, OIIO::TypeDesc::UINT8);
    ASSERT_FALSE(png.empty());
    Warnings w;
    TextureCache cache(files({png.string()}), w.logger);
    const float coarsest = srgbToLinear(188.f / 255.f);
    EXPECT_NEAR(coarsest, 0.5f, 0.003f);
    for (Vec2f uv : {Vec2f{0.1f, 0.2f}, Vec2f{0.5f, 0.5f}, Vec2f{0.9f, 0.7f}}) {
        expectRgb(cache.lookup(0, uv, 4.f), coarsest, coarsest, coarsest, 1e-6f);
        TextureRef ref;
        ref.texture = 0;
        expectRgb(cache.sample(ref, uv, 4.f).rgb, coarsest, coarsest, coarsest, 1e-6f);
    }
    // Bilinear blends between texels are blends of light too: halfway between
    // a black and a white texel (v up: the top row is black, white).
    expectRgb(cache.lookup(0, {0.5f, 0.75f}, 0.f), 0.5f, 0.5f, 0.5f, 1e-6f);
}

TEST(TextureCache, FloatImagesStayLinear) {
    std::vector<float> px = {0.5f, 0.25f, 2.f};
    fs::path exr = writeImage(test::tempDir() / "linear.exr", 1, 1, 3, px, OIIO::TypeDesc::FLOAT);
    if (exr.empty()) GTEST_SKIP() << "no OpenEXR writer";
    Warnings w;
    TextureCache cache(files({exr.string()}), w.logger);
    expectRgb(cache.lookup(0, {0.5f, 0.5f}, 0.f), 0.5f, 0.25f, 2.f);
}

TEST(TextureCache, MissingAndInvalidTexturesAreDisabled) {
    fs::path dir = test::tempDir();
    fs::path png = writeQuadrants(dir);
    test::writeFile(dir / "junk.png", "this is not a PNG");
    Warnings w;
    TextureCache cache(files({(dir / "absent.png").string(), png.string(), (dir / "junk.png").string()}), w.logger);
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
    TextureCache cache(files({png.string()}), w.logger);
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
        TextureCache first(files({png.string()}), w.logger);
        expectRgb(first.lookup(0, {0.25f, 0.75f}, 0.f), 1, 0, 0);
    }
    // The first cache is gone; a new one over a rewritten file sees the new content.
    std::vector<unsigned char> px = {0, 0, 255, 0, 0, 255, 0, 0, 255, 0, 0, 255};
    ASSERT_FALSE(writeImage(png, 2, 2, 3, px, OIIO::TypeDesc::UINT8).empty());
    TextureCache second(files({png.string()}), w.logger);
    expectRgb(second.lookup(0, {0.25f, 0.75f}, 0.f), 0, 0, 1);
}

/// The 2 x 2 quadrants image as a slot's texture (index 0), with `ref`'s sampling.
TextureRef slot(TextureRef ref = {}) {
    ref.texture = 0;
    return ref;
}

TEST(TextureSlots, ImagesFromMemoryInEachColourSpace) {
    const fs::path png = writeQuadrants(test::tempDir());
    std::ifstream in(png, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto image = std::make_shared<const std::vector<unsigned char>>(bytes.begin(), bytes.end());
    Warnings w;
    // The same bytes: as the file says (8-bit: sRGB), sRGB, and linear.
    TextureCache cache({TextureSource{"in memory", TextureColorSpace::FromFile, -1, nullptr, image},
                        TextureSource{"in memory", TextureColorSpace::Srgb, -1, nullptr, image},
                        TextureSource{"in memory", TextureColorSpace::Linear, -1, nullptr, image}},
                       w.logger);
    EXPECT_TRUE(w.lines.empty());
    const float grey = 128.f / 255.f;
    for (int t = 0; t < 3; ++t) {
        TextureRef r = slot();
        r.texture = t;
        const Rgba c = cache.sample(r, {0.75f, 0.25f}, 0.f);
        const float want = t == 2 ? grey : srgbToLinear(grey);
        expectRgb(c.rgb, want, want, want);
        EXPECT_FLOAT_EQ(c.a, 1.f);
        EXPECT_FALSE(cache.hasTransparency(t));
    }
}

TEST(TextureSlots, WrapModesNearestFilterAndTransforms) {
    // 4 x 1 grey ramp 0, 80, 160, 240 (linear, so values are exact).
    const fs::path png = writeImage(test::tempDir() / "ramp.png", 4, 1, 1, std::vector<unsigned char>{0, 80, 160, 240},
                                    OIIO::TypeDesc::UINT8);
    Warnings w;
    TextureCache cache({TextureSource{png.string(), TextureColorSpace::Linear}}, w.logger);
    auto at = [&](const TextureRef& r, float u) { return cache.sample(r, {u, 0.5f}, 0.f).rgb.r * 255.f; };
    // Texel centres are at s = (i + 0.5) / 4; past the right edge:
    TextureRef repeat = slot(), clamp = slot(), mirror = slot();
    clamp.wrapS = TextureWrap::ClampToEdge;
    mirror.wrapS = TextureWrap::MirroredRepeat;
    EXPECT_NEAR(at(repeat, 1.125f), 0.f, 1e-3f);    // texel 0 again
    EXPECT_NEAR(at(clamp, 1.125f), 240.f, 1e-3f);   // the edge texel
    EXPECT_NEAR(at(mirror, 1.125f), 240.f, 1e-3f);  // texel 3, mirrored
    EXPECT_NEAR(at(mirror, 1.375f), 160.f, 1e-3f);  // texel 2
    EXPECT_NEAR(at(clamp, -3.f), 0.f, 1e-3f);
    // Far from the image, on both sides: texel -4, -12 and 4096 wrap to 0; mirrored, -4 and -12 to 3.
    EXPECT_NEAR(at(repeat, -0.875f), 0.f, 1e-3f);
    EXPECT_NEAR(at(repeat, -2.875f), 0.f, 1e-3f);
    EXPECT_NEAR(at(repeat, 1024.125f), 0.f, 1e-3f);
    EXPECT_NEAR(at(mirror, -0.875f), 240.f, 1e-3f);
    EXPECT_NEAR(at(mirror, -2.875f), 240.f, 1e-3f);
    EXPECT_NEAR(at(mirror, -1.875f), 0.f, 1e-3f);  // texel -8: mirrored twice, texel 0
    // Bilinear between texels 1 and 2 at s = 0.5; nearest takes one of them.
    TextureRef nearest = slot();
    nearest.filter = TextureFilter::Nearest;
    EXPECT_NEAR(at(repeat, 0.5f), 120.f, 1e-3f);
    EXPECT_NEAR(at(nearest, 0.49f), 80.f, 1e-3f);
    EXPECT_NEAR(at(nearest, 0.51f), 160.f, 1e-3f);
    // A transform: s' = 0.5 s + 0.25 reads texel 1 at s = 0.25 (s' = 0.375).
    TextureSlot half;
    half.scale[0] = 0.5f;
    half.offset[0] = 0.25f;
    const TextureRef moved = TextureRef::of(half, 0);
    EXPECT_NEAR(at(moved, 0.25f), 80.f, 1e-3f);
}

TEST(TextureSlots, AlphaChannelsAndNormals) {
    const fs::path dir = test::tempDir();
    // Grey + alpha: 200 with alpha 100; RGB normal (128, 255, 128) = +y, slightly off in x.
    const fs::path ga = writeImage(dir / "ga.png", 1, 1, 2, std::vector<unsigned char>{200, 100}, OIIO::TypeDesc::UINT8);
    const fs::path n = writeImage(dir / "n.png", 1, 1, 3, std::vector<unsigned char>{191, 128, 255}, OIIO::TypeDesc::UINT8);
    const fs::path grey = writeImage(dir / "g.png", 1, 1, 1, std::vector<unsigned char>{50}, OIIO::TypeDesc::UINT8);
    Warnings w;
    TextureCache cache({TextureSource{ga.string(), TextureColorSpace::Linear}, TextureSource{n.string(), TextureColorSpace::Linear},
                        TextureSource{grey.string(), TextureColorSpace::Linear}},
                       w.logger);
    EXPECT_TRUE(w.lines.empty()) << w.lines.front();
    TextureRef a = slot();
    a.channel = 3;
    EXPECT_NEAR(cache.sampleChannel(a, {0.5f, 0.5f}, 0.f), 100.f / 255.f, 1e-6f);  // alpha
    a.channel = 1;
    EXPECT_NEAR(cache.sampleChannel(a, {0.5f, 0.5f}, 0.f), 200.f / 255.f, 1e-6f);  // grey in every colour channel
    EXPECT_TRUE(cache.hasTransparency(0));
    TextureRef matte = slot();
    matte.texture = 2;
    matte.channel = 3;
    EXPECT_NEAR(cache.sampleChannel(matte, {0.5f, 0.5f}, 0.f), 50.f / 255.f, 1e-6f) << "no alpha: the grey";
    TextureRef normal = slot();
    normal.texture = 1;
    const Vec3f flat = cache.sampleNormal(normal, {0.5f, 0.5f}, 0.f, 1.f);
    const Vec3f x = {2.f * 191.f / 255.f - 1.f, 2.f * 128.f / 255.f - 1.f, 1.f};
    EXPECT_NEAR(flat.x, x.x / length(x), 1e-6f);
    EXPECT_NEAR(length(flat), 1.f, 1e-6f);
    const Vec3f scaled = cache.sampleNormal(normal, {0.5f, 0.5f}, 0.f, 0.f);  // scale 0: the map flattened
    EXPECT_NEAR(scaled.z, 1.f, 1e-6f);
    EXPECT_EQ(cache.sampleNormal(TextureRef{}, {0.5f, 0.5f}, 0.f, 1.f).z, 1.f);
}

TEST(TextureSlots, SixteenBitImagesKeepTheirPrecision) {
    const std::vector<uint16_t> px = {1000, 40000};
    const fs::path png = writeImage(test::tempDir() / "deep.png", 2, 1, 1, px, OIIO::TypeDesc::UINT16);
    Warnings w;
    TextureCache cache({TextureSource{png.string(), TextureColorSpace::Linear}}, w.logger);
    EXPECT_NEAR(cache.sampleChannel(slot(), {0.25f, 0.5f}, 0.f), 1000.f / 65535.f, 1e-7f);
    EXPECT_NEAR(cache.sampleChannel(slot(), {0.75f, 0.5f}, 0.f), 40000.f / 65535.f, 1e-7f);
}

TEST(TextureSlots, HeightMapSlopesPerTexelThroughTransformsAndFootprints) {
    // 32 x 16 texels whose height rises by `step` per texel to the right.
    constexpr float step = 1000.f / 65535.f;
    std::vector<uint16_t> px;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x) px.push_back(uint16_t(1000 * x));
    const fs::path png = writeImage(test::tempDir() / "ramp.png", 32, 16, 1, px, OIIO::TypeDesc::UINT16);
    Warnings w;
    TextureCache cache({TextureSource{png.string(), TextureColorSpace::Linear}}, w.logger);
    const auto expectNormal = [](const Vec3f& got, const Vec3f& want) {
        EXPECT_NEAR(got.x, want.x, 2e-5f);
        EXPECT_NEAR(got.y, want.y, 2e-5f);
        EXPECT_NEAR(got.z, want.z, 2e-5f);
    };
    const Vec3f alongU = normalize(Vec3f{-10.f * step, 0.f, 1.f});
    expectNormal(cache.sampleHeightNormal(slot(), {0.5f, 0.5f}, 0.f, 10.f), alongU);
    // The box-filtered MIP levels of a ramp are ramps: a footprint of 8 texels reads the same slope per texel.
    expectNormal(cache.sampleHeightNormal(slot(), {0.5f, 0.5f}, 0.25f, 10.f), alongU);
    // Tiled twice: twice the texels per unit of u, the same slope per texel.
    TextureRef tiled = slot();
    tiled.m[0] = 2.f;
    expectNormal(cache.sampleHeightNormal(tiled, {0.25f, 0.5f}, 0.f, 10.f), alongU);
    // Turned a quarter (s' = 1 - v, t' = u): the rise runs down v, measured in the image's 32 texels across.
    TextureRef turned = slot();
    turned.m[0] = 0.f;
    turned.m[1] = 1.f;
    turned.m[3] = 1.f;
    turned.m[4] = 0.f;
    expectNormal(cache.sampleHeightNormal(turned, {0.5f, 0.5f}, 0.f, 10.f), normalize(Vec3f{0.f, 10.f * step, 1.f}));
    EXPECT_EQ(cache.sampleHeightNormal(TextureRef{}, {0.5f, 0.5f}, 0.f, 10.f).z, 1.f);
}

}  // namespace
}  // namespace penumbra
