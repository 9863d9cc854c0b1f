// TextureCache inputs (issue 13 items 3, 6, 9): the pixel budget is checked
// from the header before decoding (a decompression bomb is refused at once),
// a truncated tiled EXR is refused with a warning instead of rendering white,
// and a texture handed over as an open descriptor is read from it, never
// reopened by path (a symlink swapped in after the loader's check is not followed).
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
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

struct Warnings {
    std::vector<std::string> lines;
    Logger logger{[this](LogLevel level, std::string_view m) {
        if (level == LogLevel::Warning) lines.emplace_back(m);
    }};
    Warnings() = default;
    Warnings(const Warnings&) = delete;
};

bool writeSolid(const fs::path& path, int w, int h, unsigned char r, unsigned char g, unsigned char b) {
    std::vector<unsigned char> px(size_t(w) * size_t(h) * 3);
    for (size_t i = 0; i < px.size(); i += 3) px[i] = r, px[i + 1] = g, px[i + 2] = b;
    auto out = OIIO::ImageOutput::create(path.string());
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
    return out && out->open(path.string(), spec) && out->write_image(OIIO::TypeDesc::UINT8, px.data()) && out->close();
}

uint32_t crc32(const std::string& bytes) {
    uint32_t c = 0xffffffffu;
    for (unsigned char b : bytes) {
        c ^= b;
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return ~c;
}

std::string be32(uint32_t v) {
    return {char(v >> 24), char((v >> 16) & 0xff), char((v >> 8) & 0xff), char(v & 0xff)};
}

std::string pngChunk(const std::string& type, const std::string& data) {
    return be32(uint32_t(data.size())) + type + data + be32(crc32(type + data));
}

// The head of a 25000 x 25000 RGB PNG (1.75 GiB decoded): what a 1.8 MB
// decompression bomb shows before its pixels are inflated.
fs::path writeBombHeader(const fs::path& path) {
    std::string ihdr = be32(25000) + be32(25000) + std::string("\x08\x02\x00\x00\x00", 5);
    std::string png = std::string("\x89PNG\r\n\x1a\n", 8) + pngChunk("IHDR", ihdr) +
                      pngChunk("IDAT", std::string(64, '\x78')) + pngChunk("IEND", "");
    std::ofstream(path, std::ios::binary) << png;
    return path;
}

TEST(TextureInput, ADecompressionBombIsRefusedFromItsHeader) {
    const fs::path png = writeBombHeader(test::tempDir() / "bomb.png");
    Warnings w;
    const auto start = std::chrono::steady_clock::now();
    TextureCache cache(files({png.string()}), w.logger);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_FALSE(cache.enabled(0));
    ASSERT_EQ(w.lines.size(), 1u);
    EXPECT_NE(w.lines[0].find("bomb.png"), std::string::npos) << w.lines[0];
    EXPECT_NE(w.lines[0].find("25000x25000"), std::string::npos) << w.lines[0];
    EXPECT_NE(w.lines[0].find("texture budget"), std::string::npos) << w.lines[0];
    EXPECT_EQ(cache.memoryBytes(), 0u);
    EXPECT_LT(seconds, 1.0);  // the header alone decides
}

TEST(TextureInput, TheBudgetCoversAllTexturesOfACache) {
    const fs::path dir = test::tempDir();
    ASSERT_TRUE(writeSolid(dir / "a.png", 256, 256, 255, 0, 0));
    ASSERT_TRUE(writeSolid(dir / "b.png", 256, 256, 0, 255, 0));
    Warnings w;
    // a.png takes 256*256*3 bytes plus a third for its MIP levels (~256 KiB); b.png no longer fits.
    TextureCache cache(files({(dir / "a.png").string(), (dir / "b.png").string()}), w.logger, TextureBudget{300u << 10});
    EXPECT_TRUE(cache.enabled(0));
    EXPECT_FALSE(cache.enabled(1));
    ASSERT_EQ(w.lines.size(), 1u);
    EXPECT_NE(w.lines[0].find("b.png"), std::string::npos) << w.lines[0];
    EXPECT_NE(w.lines[0].find("texture budget"), std::string::npos) << w.lines[0];
    EXPECT_LE(cache.memoryBytes(), uint64_t(300u << 10));
    EXPECT_GE(cache.memoryBytes(), uint64_t(256 * 256 * 3));
}

TEST(TextureInput, ATruncatedTiledExrIsRefusedNotWhite) {
    const fs::path dir = test::tempDir();
    const fs::path exr = dir / "tiled.exr";
    const int n = 64;
    std::vector<float> px(size_t(n) * n * 3, 0.25f);
    {
        auto out = OIIO::ImageOutput::create(exr.string());
        ASSERT_TRUE(out);
        OIIO::ImageSpec spec(n, n, 3, OIIO::TypeDesc::FLOAT);
        spec.tile_width = spec.tile_height = 16;
        spec.attribute("compression", "none");
        ASSERT_TRUE(out->open(exr.string(), spec));
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
        ASSERT_TRUE(out->close());
    }
    {
        Warnings w;
        TextureCache whole(files({exr.string()}), w.logger);
        ASSERT_TRUE(whole.enabled(0));
        EXPECT_NEAR(whole.lookup(0, {0.9f, 0.1f}, 0.f).r, 0.25f, 1e-6f);
    }
    fs::resize_file(exr, fs::file_size(exr) * 6 / 10);
    Warnings w;
    TextureCache cut(files({exr.string()}), w.logger);
    EXPECT_FALSE(cut.enabled(0));
    ASSERT_EQ(w.lines.size(), 1u);
    EXPECT_NE(w.lines[0].find("tiled.exr: cannot read texture"), std::string::npos) << w.lines[0];
}

TEST(TextureInput, AnOpenDescriptorIsReadNotThePathAgain) {
    const fs::path dir = test::tempDir();
    fs::create_directories(dir / "root");
    fs::create_directories(dir / "outside");
    ASSERT_TRUE(writeSolid(dir / "root" / "inside.png", 2, 2, 255, 0, 0));
    ASSERT_TRUE(writeSolid(dir / "outside" / "secret.png", 2, 2, 0, 0, 255));
    const fs::path link = dir / "root" / "tex.png";
    fs::create_symlink("inside.png", link);

    // The loader checks the path and opens it: the descriptor is the inside file.
    const int fd = ::open(link.c_str(), O_RDONLY | O_CLOEXEC);
    ASSERT_GE(fd, 0);
    // Between load and prepare, the link is swapped for one pointing outside.
    fs::remove(link);
    fs::create_symlink("../outside/secret.png", link);

    Warnings w;
    TextureCache handedOver(files({link.string()}, {fd}), w.logger);
    ASSERT_TRUE(handedOver.enabled(0));
    const Rgb c = handedOver.lookup(0, {0.5f, 0.5f}, 0.f);
    EXPECT_NEAR(c.r, 1.f, 1e-5f);
    EXPECT_NEAR(c.b, 0.f, 1e-5f);
    // The descriptor stays the caller's: still open, offset untouched.
    EXPECT_EQ(::lseek(fd, 0, SEEK_CUR), 0);
    EXPECT_EQ(::close(fd), 0);

    // Control: by path, the swapped link is followed (what the descriptor prevents).
    TextureCache byPath(files({link.string()}), w.logger);
    EXPECT_NEAR(byPath.lookup(0, {0.5f, 0.5f}, 0.f).b, 1.f, 1e-5f);
    EXPECT_TRUE(w.lines.empty());
}

TEST(TextureInput, NonRegularFilesAreRefusedWithoutBlocking) {
    const fs::path dir = test::tempDir();
    const fs::path fifo = dir / "fifo.png";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    Warnings w;
    TextureCache cache(files({fifo.string(), dir.string()}), w.logger);
    EXPECT_FALSE(cache.enabled(0));
    EXPECT_FALSE(cache.enabled(1));
    ASSERT_EQ(w.lines.size(), 2u);
    EXPECT_NE(w.lines[0].find("not a regular file"), std::string::npos) << w.lines[0];
}

}  // namespace
}  // namespace penumbra
