// The checked, all-or-nothing image writer (issue 13 items 1-2): for every
// format, a full disk (a 200 KiB tmpfs, root only: skipped otherwise) and a
// file-size limit (ulimit -f) give Error(IoError) naming the file, keep the
// old image byte for byte and leave no temporary file; the process survives
// (libjpeg would exit). Also: values read back, JPEG size limit.
#include <gtest/gtest.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/statvfs.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <functional>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/film.h"
#include "core/hash.h"
#include "core/image_io.h"
#include "support/test_support.h"

namespace penumbra {
namespace {
namespace fs = std::filesystem;

const char* const kFormats[] = {".exr", ".hdr", ".pfm", ".png", ".jpg", ".tif"};

// A film of uncorrelated values in [0, 1): no encoder can make it small.
Film noiseFilm(int w, int h, uint32_t seed) {
    Film film(w, h, false);
    uint32_t state = seed * 747796405u + 2891336453u;
    auto next = [&] {
        state = state * 1664525u + 1013904223u;
        return float(state >> 8) * (1.f / 16777216.f);
    };
    for (size_t i = 0; i < size_t(w) * size_t(h); ++i) film.addRadiance(i, Rgb(next(), next(), next()));
    film.setSampleCount(1);
    return film;
}

std::string readBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

std::vector<std::string> namesIn(const fs::path& dir) {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
}

ErrorCode codeOf(const std::function<void()>& f, std::string* message) {
    try {
        f();
    } catch (const Error& e) {
        *message = e.what();
        return e.code();
    }
    return ErrorCode(0);
}

// A small tmpfs mounted for one test (needs CAP_SYS_ADMIN).
class SmallDisk {
public:
    explicit SmallDisk(const fs::path& dir) : dir_(dir) {
        fs::create_directories(dir_);
        mounted_ = ::mount("tmpfs", dir_.c_str(), "tmpfs", 0, "size=200k") == 0;
        if (!mounted_) why_ = std::strerror(errno);
    }
    ~SmallDisk() {
        if (mounted_) ::umount2(dir_.c_str(), MNT_DETACH);
    }
    bool mounted() const { return mounted_; }
    const std::string& why() const { return why_; }
    /// Fills the disk with `filler` until at most `leave` bytes are free.
    void fill(const fs::path& filler, size_t leave) {
        struct statvfs st {};
        ASSERT_EQ(::statvfs(dir_.c_str(), &st), 0);
        const size_t avail = size_t(st.f_bavail) * st.f_frsize;
        std::ofstream out(filler, std::ios::binary);
        std::string block(avail > leave ? avail - leave : 0, 'x');
        out.write(block.data(), std::streamsize(block.size()));
    }

private:
    fs::path dir_;
    bool mounted_ = false;
    std::string why_;
};

class FullDisk : public ::testing::TestWithParam<const char*> {};

TEST_P(FullDisk, FailsWithIoErrorAndKeepsTheOldImage) {
    const std::string ext = GetParam();
    const fs::path dir = test::tempDir() / "disk";
    SmallDisk disk(dir);
    if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here (" << disk.why() << ")";
    const fs::path out = dir / ("render" + ext);

    writeImage(out, noiseFilm(8, 8, 1), {});
    const std::string good = readBytes(out);
    ASSERT_FALSE(good.empty());

    // 8 KiB left: a 128x128 noise image needs more in every format.
    disk.fill(dir / "filler", 8192);
    std::string msg;
    EXPECT_EQ(codeOf([&] { writeImage(out, noiseFilm(128, 128, 2), {}); }, &msg), ErrorCode::IoError) << ext;
    EXPECT_NE(msg.find(out.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("No space left on device"), std::string::npos) << msg;
    EXPECT_EQ(readBytes(out), good) << ext << ": the old image was changed";
    EXPECT_EQ(namesIn(dir), (std::vector<std::string>{"filler", "render" + ext})) << "a temporary file was left";

    // With room again the same write succeeds and reads back at the new size.
    fs::remove(dir / "filler");
    writeImage(out, noiseFilm(128, 128, 2), {});
    ImageData img = readImage(out);
    EXPECT_EQ(img.width, 128);
    EXPECT_EQ(img.height, 128);
}

TEST_P(FullDisk, AnAovSiblingIsWrittenOnlyWithTheImage) {
    const std::string ext = GetParam();
    if (ext == ".exr") GTEST_SKIP() << "EXR keeps its AOVs in its own channels";
    const fs::path dir = test::tempDir() / "disk";
    SmallDisk disk(dir);
    if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here (" << disk.why() << ")";
    Film film(96, 96, true);
    for (size_t i = 0; i < 96 * 96; ++i) film.addAov(i, Rgb(float(i % 7) / 7.f, 0.5f, float(i % 13) / 13.f), {0, 1, 0}, float(i));
    film.setSampleCount(1);
    disk.fill(dir / "filler", 8192);
    ImageWriteOptions options;
    options.aovs = true;
    std::string msg;
    EXPECT_EQ(codeOf([&] { writeImage(dir / ("render" + ext), film, options); }, &msg), ErrorCode::IoError) << ext;
    EXPECT_EQ(namesIn(dir), (std::vector<std::string>{"filler"}));
}

TEST_P(FullDisk, AFileSizeLimitIsAnErrorNotASignal) {
    // Without a check, a write past RLIMIT_FSIZE raises SIGXFSZ, which ends the process.
    const std::string ext = GetParam();
    const fs::path dir = test::tempDir();
    const fs::path out = dir / ("limited" + ext);
    writeImage(out, noiseFilm(4, 4, 3), {});
    const std::string good = readBytes(out);
    rlimit old{};
    ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
    rlimit small = old;
    small.rlim_cur = 4096;
    if (old.rlim_max != RLIM_INFINITY && old.rlim_max < small.rlim_cur) GTEST_SKIP() << "hard limit below 4 KiB";
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
    std::string msg;
    const ErrorCode code = codeOf([&] { writeImage(out, noiseFilm(128, 128, 4), {}); }, &msg);
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &old), 0);
    EXPECT_EQ(code, ErrorCode::IoError) << ext;
    EXPECT_NE(msg.find("file size limit"), std::string::npos) << msg;
    EXPECT_EQ(readBytes(out), good);
    EXPECT_EQ(namesIn(dir), (std::vector<std::string>{"limited" + ext}));
}

INSTANTIATE_TEST_SUITE_P(EveryFormat, FullDisk, ::testing::ValuesIn(kFormats),
                         [](const auto& info) { return std::string(info.param + 1); });

TEST(ImageWrite, EveryFormatReadsBackItsValues) {
    // A smooth image (JPEG is lossy on noise) with values over the whole 8-bit range.
    Film film(17, 9, false);
    for (int y = 0; y < 9; ++y)
        for (int x = 0; x < 17; ++x)
            film.addRadiance(film.index(x, y), Rgb(float(x) / 16.f, float(y) / 8.f, float(x + y) / 24.f));
    film.setSampleCount(1);
    const fs::path dir = test::tempDir();
    for (const char* ext : kFormats) {
        const fs::path out = dir / (std::string("values") + ext);
        writeImage(out, film, {});
        ImageData img = readImage(out);
        ASSERT_EQ(img.width, 17) << ext;
        ASSERT_EQ(img.height, 9) << ext;
        ASSERT_GE(img.channels, 3) << ext;
        const ImageFormat f = imageFormatFromPath(out);
        // Float formats keep the value (HDR to its 8-bit mantissa); 8-bit ones hold sRGB codes (JPEG: lossy).
        const float tol = f == ImageFormat::Hdr ? 0.01f : isFloatFormat(f) ? 0.f : 0.5f / 255.f;
        double jpegError = 0.0;
        for (int y = 0; y < 9; ++y)
            for (int x = 0; x < 17; ++x) {
                const Rgb L = film.radiance(film.index(x, y));
                const float want = isFloatFormat(f) ? L.r : linearToSrgb(L.r);
                if (f == ImageFormat::Jpg) jpegError += std::fabs(img.at(x, y, 0) - want) / (17.0 * 9.0);
                else ASSERT_NEAR(img.at(x, y, 0), want, tol + 1e-6f) << ext << " at " << x << "," << y;
            }
        EXPECT_LT(jpegError, 0.05) << "JPEG is lossy, but not that lossy";
    }
}

TEST(ImageWrite, JpegBeyondItsSizeLimitIsAnErrorNotAnExit) {
    // libjpeg calls exit(1) for a side over 65500 pixels; the writer must refuse first.
    Film film(65501, 1, false);
    const fs::path out = test::tempDir() / "wide.jpg";
    std::string msg;
    EXPECT_EQ(codeOf([&] { writeImage(out, film, {}); }, &msg), ErrorCode::IoError);
    EXPECT_NE(msg.find("65500"), std::string::npos) << msg;
    EXPECT_FALSE(fs::exists(out));
}

TEST(ImageWrite, MetadataIsKept) {
    ImageWriteOptions o;
    o.metadata.spp = 16;
    o.metadata.seed = 12345678901234ull;
    o.metadata.software = "test";
    const fs::path out = test::tempDir() / "meta.exr";
    writeImage(out, noiseFilm(4, 4, 6), o);
    ImageData img = readImage(out);
    auto attr = [&](const std::string& name) {
        for (const auto& [k, v] : img.attributes)
            if (k == name) return v;
        return std::string();
    };
    EXPECT_EQ(attr("penumbra:spp"), "16");
    EXPECT_EQ(attr("penumbra:seed"), "12345678901234");
    EXPECT_EQ(attr("Software"), "test");
}

}  // namespace
}  // namespace penumbra
