// PNG output through libpng (core/png_encoder.h): the codes read back exactly
// (OpenImageIO decodes), the metadata and the sRGB colour space are kept, and
// what libpng refuses is an error with its message, not a jump out of the process.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "core/film.h"
#include "core/image_io.h"
#include "core/png_encoder.h"
#include "core/srgb8.h"
#include "support/test_support.h"

namespace penumbra {
namespace {
namespace fs = std::filesystem;

TEST(PngEncoder, CodesReadBackExactly) {
    const int w = 37, h = 5;
    std::vector<uint8_t> rgb(size_t(w) * h * 3);
    for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = uint8_t((i * 7919u) >> 3);
    const std::vector<std::pair<std::string, std::string>> text = {{"Software", "test"}, {"penumbra:spp", "4"}};
    std::vector<unsigned char> bytes;
    std::string error;
    ASSERT_TRUE(encodePng(PngImage{w, h, rgb.data(), text, 4}, bytes, error)) << error;
    const fs::path out = test::tempDir() / "codes.png";
    std::ofstream(out, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    const ImageData img = readImage(out);
    ASSERT_EQ(img.width, w);
    ASSERT_EQ(img.height, h);
    ASSERT_EQ(img.channels, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c)
                ASSERT_EQ(int(img.at(x, y, c) * 255.f + 0.5f), rgb[(size_t(y) * w + x) * 3 + c]) << x << "," << y;
    auto attr = [&](const std::string& name) {
        for (const auto& [k, v] : img.attributes)
            if (k == name) return v;
        return std::string();
    };
    EXPECT_EQ(attr("Software"), "test");
    EXPECT_EQ(attr("penumbra:spp"), "4");
    EXPECT_EQ(attr("oiio:ColorSpace"), "sRGB");
}

TEST(PngEncoder, WhatLibpngRefusesIsAnError) {
    // Zero width: png_set_IHDR calls the error handler, which must come back as false.
    const uint8_t pixel[3] = {1, 2, 3};
    std::vector<unsigned char> bytes;
    std::string error;
    EXPECT_FALSE(encodePng(PngImage{0, 1, pixel, {}, 4}, bytes, error));
    EXPECT_NE(error.find("libpng"), std::string::npos) << error;
    EXPECT_NE(error.find("width"), std::string::npos) << error;
    // And a valid image right after encodes (no state left behind).
    bytes.clear();
    error.clear();
    EXPECT_TRUE(encodePng(PngImage{1, 1, pixel, {}, 4}, bytes, error)) << error;
    EXPECT_GT(bytes.size(), 8u);
}

TEST(PngEncoder, TheWriterKeepsTheFilmsSrgbCodesAndMetadata) {
    Film film(9, 3, false);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 9; ++x) film.addRadiance(film.index(x, y), Rgb(float(x) / 8.f, float(y) / 2.f, 0.37f));
    film.setSampleCount(1);
    ImageWriteOptions o;
    o.exposure = 1.f;
    o.metadata.spp = 16;
    o.metadata.seed = 12345678901234ull;
    o.metadata.renderSeconds = 0.25;
    const fs::path out = test::tempDir() / "film.png";
    writeImage(out, film, o);
    const ImageData img = readImage(out);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 9; ++x) {
            const Rgb L = film.radiance(film.index(x, y)) * 2.f;
            ASSERT_EQ(int(img.at(x, y, 0) * 255.f + 0.5f), srgb8Code(L.r)) << x << "," << y;
            ASSERT_EQ(int(img.at(x, y, 2) * 255.f + 0.5f), srgb8Code(L.b)) << x << "," << y;
        }
    std::string spp, seed, seconds;
    for (const auto& [k, v] : img.attributes) {
        if (k == "penumbra:spp") spp = v;
        if (k == "penumbra:seed") seed = v;
        if (k == "penumbra:render_seconds") seconds = v;
    }
    EXPECT_EQ(spp, "16");
    EXPECT_EQ(seed, "12345678901234");
    EXPECT_EQ(seconds, "0.25");
}

}  // namespace
}  // namespace penumbra
