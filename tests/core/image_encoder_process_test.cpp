// The image encoder process (core/image_encoder_process.h): what it encodes
// is what this process encodes, byte for byte, in every format it serves; the
// module's errors come back as the module's messages; and a helper that died
// leaves the work to this process, which writes the same file.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>
#include <vector>

#include "core/film.h"
#include "core/image_encoder_process.h"
#include "core/image_io.h"
#include "core/oiio_library.h"
#include "support/test_support.h"

namespace penumbra {
namespace {
namespace fs = std::filesystem;

std::string readBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// The file's bytes with the time of writing (EXR capDate, TIFF DateTime:
// "YYYY:MM:DD hh:mm:ss", to the second) blanked: two writes a moment apart
// may fall in different seconds.
std::string bytesButTheDate(const fs::path& p) {
    static const std::regex kDate(R"(\d{4}:\d\d:\d\d \d\d:\d\d:\d\d)");
    return std::regex_replace(readBytes(p), kDate, "YYYY:MM:DD hh:mm:ss");
}

Film gradientFilm(int w, int h, bool aovs) {
    Film film(w, h, aovs);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t i = film.index(x, y);
            film.addRadiance(i, Rgb(float(x) / float(w), float(y) / float(h), 0.25f + float(x * y) / float(w * h)));
            if (aovs) film.addAov(i, Rgb(0.5f, float(x) / float(w), 0.1f), Vec3f{0, 1, 0}, float(x + y));
        }
    film.setSampleCount(1);
    return film;
}

ImageWriteOptions writeOptions() {
    ImageWriteOptions o;
    o.exposure = 0.5f;
    o.metadata.spp = 4;
    o.metadata.seed = 77;
    o.metadata.software = "test";
    // A crop's place in the full frame (EXRs record it).
    o.dataOriginX = 3;
    o.dataOriginY = 2;
    o.fullWidth = 40;
    o.fullHeight = 30;
    return o;
}

TEST(ImageEncoderProcess, EncodesWhatThisProcessEncodesByteForByte) {
    auto encoder = ImageEncoderProcess::start();
    ASSERT_NE(encoder, nullptr);
    const fs::path dir = test::tempDir();
    for (const bool aovs : {false, true}) {
        const Film film = gradientFilm(23, 11, aovs);
        for (const char* ext : {".exr", ".hdr", ".png", ".jpg", ".tif"}) {
            ImageWriteOptions o = writeOptions();
            o.aovs = aovs;
            const std::string stem = std::string(aovs ? "aovs" : "plain") + (ext + 1);
            writeImage(dir / (stem + "_here" + ext), film, o);
            o.encoder = encoder.get();
            writeImage(dir / (stem + "_helper" + ext), film, o);
            const std::string here = bytesButTheDate(dir / (stem + "_here" + ext));
            EXPECT_GT(here.size(), 100u) << ext;
            EXPECT_EQ(bytesButTheDate(dir / (stem + "_helper" + ext)), here) << ext << (aovs ? " with AOVs" : "");
            if (aovs && std::string(ext) != ".exr") {  // the AOVs' EXR sibling
                EXPECT_EQ(bytesButTheDate(dir / (stem + "_helper.aovs.exr")),
                          bytesButTheDate(dir / (stem + "_here.aovs.exr")))
                    << ext;
            }
        }
    }
    EXPECT_GT(encoder->pid(), 0) << "the helper answered every request";
}

TEST(ImageEncoderProcess, TheModulesErrorComesBackAsItsMessage) {
    auto encoder = ImageEncoderProcess::start();
    ASSERT_NE(encoder, nullptr);
    const float pixels[3] = {0.5f, 0.5f, 0.5f};
    oiio::EncodeRequest rq;
    rq.format = "no-such-format";
    rq.width = rq.height = 1;
    rq.channels = 3;
    rq.pixels = pixels;
    std::vector<unsigned char> out;
    std::string helperError;
    const std::optional<bool> answer = encoder->encode(rq, out, helperError);
    ASSERT_TRUE(answer.has_value());
    EXPECT_FALSE(*answer);
    std::string hereError;
    EXPECT_FALSE(oiioLibrary().encode(rq, out, hereError));
    EXPECT_FALSE(helperError.empty());
    EXPECT_EQ(helperError, hereError);
    // It still answers after an error.
    rq.format = "png";
    std::string error;
    EXPECT_EQ(encoder->encode(rq, out, error), std::optional<bool>(true)) << error;
    EXPECT_GT(out.size(), 8u);
}

TEST(ImageEncoderProcess, ALargeImageIsLeftToThisProcessAndTheHelperStays) {
    auto encoder = ImageEncoderProcess::start();
    ASSERT_NE(encoder, nullptr);
    oiio::EncodeRequest rq;  // 1.2 GB of pixels: never sent, so none are needed here
    rq.format = "exr";
    rq.width = rq.height = 10000;
    rq.channels = 3;
    std::vector<unsigned char> out;
    std::string error;
    EXPECT_EQ(encoder->encode(rq, out, error), std::nullopt);
    EXPECT_GT(encoder->pid(), 0);
    const float pixel[3] = {0.25f, 0.5f, 1.f};
    rq.width = rq.height = 1;
    rq.format = "png";
    rq.pixels = pixel;
    EXPECT_EQ(encoder->encode(rq, out, error), std::optional<bool>(true)) << error;
}

TEST(ImageEncoderProcess, AHelperThatDiedLeavesTheWorkToThisProcess) {
    auto encoder = ImageEncoderProcess::start();
    ASSERT_NE(encoder, nullptr);
    const pid_t pid = encoder->pid();
    ASSERT_EQ(::kill(pid, SIGKILL), 0);
    const fs::path dir = test::tempDir();
    const Film film = gradientFilm(9, 7, false);
    ImageWriteOptions o = writeOptions();
    writeImage(dir / "here.png", film, o);
    o.encoder = encoder.get();
    writeImage(dir / "after.png", film, o);  // the helper is gone: encoded here, no error
    EXPECT_EQ(readBytes(dir / "after.png"), readBytes(dir / "here.png"));
    EXPECT_EQ(encoder->pid(), -1) << "a helper that did not answer is not asked again";
    EXPECT_EQ(::waitpid(pid, nullptr, WNOHANG), -1) << "and it was reaped";
    std::vector<unsigned char> out;
    std::string error;
    EXPECT_EQ(encoder->encode(oiio::EncodeRequest{}, out, error), std::nullopt);
}

}  // namespace
}  // namespace penumbra
