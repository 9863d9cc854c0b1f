// PNG output (core/png_encoder.h): the codes read back exactly (OpenImageIO
// decodes), the metadata and the sRGB colour space are kept, the file's chunks
// are well formed (lengths and CRCs), and what PNG cannot store is an error
// that says why.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <libdeflate.h>

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

TEST(PngEncoder, WhatPngCannotStoreIsAnError) {
    const uint8_t pixel[3] = {1, 2, 3};
    std::vector<unsigned char> bytes;
    std::string error;
    EXPECT_FALSE(encodePng(PngImage{0, 1, pixel, {}, 4}, bytes, error));
    EXPECT_NE(error.find("width and height must be at least 1"), std::string::npos) << error;
    EXPECT_TRUE(bytes.empty());
    const std::vector<std::pair<std::string, std::string>> badKey = {{"two  spaces", "x"}};
    error.clear();
    EXPECT_FALSE(encodePng(PngImage{1, 1, pixel, badKey, 4}, bytes, error));
    EXPECT_NE(error.find("'two  spaces' is not a valid text keyword"), std::string::npos) << error;
    const std::vector<std::pair<std::string, std::string>> nul = {{"Comment", std::string("a\0b", 3)}};
    error.clear();
    EXPECT_FALSE(encodePng(PngImage{1, 1, pixel, nul, 4}, bytes, error));
    EXPECT_NE(error.find("NUL"), std::string::npos) << error;
    EXPECT_TRUE(bytes.empty());
    // And a valid image right after encodes.
    error.clear();
    EXPECT_TRUE(encodePng(PngImage{1, 1, pixel, {}, 4}, bytes, error)) << error;
    EXPECT_GT(bytes.size(), 8u);
}

// CRC-32 as the PNG specification's Annex D computes it, bit by bit: an
// implementation apart from the encoder's (libdeflate's).
uint32_t referenceCrc32(const unsigned char* p, size_t n) {
    uint32_t c = 0xffffffffu;
    for (size_t i = 0; i < n; ++i) {
        c ^= p[i];
        for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xedb88320u ^ (c >> 1) : c >> 1;
    }
    return c ^ 0xffffffffu;
}

// Walks the chunks: signature, then length, type, data and a CRC-32 over type
// and data, IHDR first and IEND last.
TEST(PngEncoder, ChunksAreWellFormed) {
    const int w = 301, h = 17;
    std::vector<uint8_t> rgb(size_t(w) * h * 3);
    for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = uint8_t(i % 251);
    const std::vector<std::pair<std::string, std::string>> text = {{"Software", "test"}};
    std::vector<unsigned char> bytes;
    std::string error;
    ASSERT_TRUE(encodePng(PngImage{w, h, rgb.data(), text, 4}, bytes, error)) << error;
    const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    ASSERT_GE(bytes.size(), 8u);
    ASSERT_EQ(std::memcmp(bytes.data(), signature, 8), 0);
    const auto u32 = [&](size_t at) {
        return uint32_t(bytes[at]) << 24 | uint32_t(bytes[at + 1]) << 16 | uint32_t(bytes[at + 2]) << 8 | bytes[at + 3];
    };
    std::vector<std::string> types;
    std::vector<unsigned char> idat;
    for (size_t at = 8; at < bytes.size();) {
        ASSERT_LE(at + 12, bytes.size());
        const uint32_t length = u32(at);
        ASSERT_LE(at + 12 + length, bytes.size());
        types.emplace_back(reinterpret_cast<const char*>(&bytes[at + 4]), 4);
        EXPECT_EQ(u32(at + 8 + length), referenceCrc32(&bytes[at + 4], length + 4)) << types.back();
        if (types.back() == "IHDR") {
            EXPECT_EQ(length, 13u);
            EXPECT_EQ(u32(at + 8), uint32_t(w));
            EXPECT_EQ(u32(at + 12), uint32_t(h));
        }
        if (types.back() == "IDAT") idat.insert(idat.end(), &bytes[at + 8], &bytes[at + 8 + length]);
        at += 12 + length;
    }
    const std::vector<std::string> expected = {"IHDR", "sRGB", "gAMA", "cHRM", "tEXt", "IDAT", "IEND"};
    EXPECT_EQ(types, expected);
    // The image data inflates to the rows, each its filter byte (Sub) and the differences.
    std::vector<unsigned char> raw(size_t(h) * (1 + 3 * size_t(w)));
    libdeflate_decompressor* inflater = libdeflate_alloc_decompressor();
    ASSERT_NE(inflater, nullptr);
    size_t rawSize = 0;
    const libdeflate_result r =
        libdeflate_zlib_decompress(inflater, idat.data(), idat.size(), raw.data(), raw.size(), &rawSize);
    libdeflate_free_decompressor(inflater);
    ASSERT_EQ(r, LIBDEFLATE_SUCCESS);
    ASSERT_EQ(rawSize, raw.size());
    for (int y = 0; y < h; ++y) {
        const unsigned char* row = &raw[size_t(y) * (1 + 3 * size_t(w))];
        ASSERT_EQ(row[0], 1);
        for (int i = 0; i < 3 * w; ++i) {
            const uint8_t left = i >= 3 ? rgb[size_t(y) * 3 * w + i - 3] : 0;
            ASSERT_EQ(uint8_t(row[1 + i] + left), rgb[size_t(y) * 3 * w + i]) << y << "," << i;
        }
    }
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
