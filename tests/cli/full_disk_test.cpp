// The penumbra command on a full disk (issue 13 items 1-2): for every output
// format it exits non-zero with a message naming the file, the image that was
// there is unchanged, and no temporary file is left. Needs root for the small
// tmpfs; skipped otherwise. The same through the C API: PNB_ERROR_IO, and the
// host process lives on (libjpeg's exit(1) used to end it).
#include <gtest/gtest.h>
#include <sys/mount.h>
#include <sys/statvfs.h>
#include <sys/wait.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "penumbra/penumbra.h"
#include "support/test_support.h"

namespace {
namespace fs = std::filesystem;
using namespace penumbra;

struct CliRun {
    int exitCode;
    std::string output;
};

CliRun penumbra(const std::string& args) {
    const std::string cmd = (test::binaryDir() / "penumbra").string() + " " + args + " 2>&1";
    FILE* p = ::popen(cmd.c_str(), "r");
    if (!p) return {-1, "popen failed"};
    std::string out;
    std::array<char, 4096> buf{};
    size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
    const int status = ::pclose(p);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), out};
}

std::string readBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(CliFullDisk, EveryFormatFailsCleanlyAndKeepsTheOldImage) {
    const fs::path dir = test::tempDir() / "disk";
    fs::create_directories(dir);
    if (::mount("tmpfs", dir.c_str(), "tmpfs", 0, "size=200k") != 0)
        GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno) << ")";
    struct Unmount {
        fs::path d;
        ~Unmount() { ::umount2(d.c_str(), MNT_DETACH); }
    } unmount{dir};
    const std::string scene = test::assetPath("cornell/cornell.obj").string();

    for (const char* ext : {".exr", ".hdr", ".pfm", ".png", ".jpg", ".tif"}) {
        SCOPED_TRACE(ext);
        const fs::path out = dir / (std::string("render") + ext);
        CliRun first = penumbra(scene + " -q --width 8 --height 8 --spp 1 -o " + out.string());
        ASSERT_EQ(first.exitCode, 0) << first.output;
        const std::string good = readBytes(out);

        // Fill the disk to the last few KiB, then ask for a larger image.
        struct statvfs st {};
        ASSERT_EQ(::statvfs(dir.c_str(), &st), 0);
        const size_t avail = size_t(st.f_bavail) * st.f_frsize;
        {
            std::ofstream filler(dir / "filler", std::ios::binary);
            const std::string block(avail > 4096 ? avail - 4096 : 0, 'x');
            filler.write(block.data(), std::streamsize(block.size()));
        }
        CliRun full = penumbra(scene + " -q --width 96 --height 96 --spp 1 -o " + out.string());
        EXPECT_NE(full.exitCode, 0) << full.output;
        EXPECT_LT(full.exitCode, 128) << "killed by a signal: " << full.output;
        EXPECT_NE(full.output.find(out.string()), std::string::npos) << full.output;
        EXPECT_NE(full.output.find("No space left on device"), std::string::npos) << full.output;
        EXPECT_EQ(readBytes(out), good) << "the old image was changed";
        for (const auto& e : fs::directory_iterator(dir))
            EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
        fs::remove(dir / "filler");
        fs::remove(out);
    }
}

// --stats-json on a full disk: an error naming the file, and the statistics of
// the previous run stay as they were (the file is replaced only when complete).
TEST(CliFullDisk, StatisticsAreWrittenWholeOrNotAtAll) {
    const fs::path root = test::tempDir(), dir = root / "statsdisk";
    fs::create_directories(dir);
    if (::mount("tmpfs", dir.c_str(), "tmpfs", 0, "size=64k") != 0)
        GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno) << ")";
    struct Unmount {
        fs::path d;
        ~Unmount() { ::umount2(d.c_str(), MNT_DETACH); }
    } unmount{dir};
    const std::string scene = test::assetPath("cornell/cornell.obj").string();
    const fs::path image = root / "stats_image.pfm", stats = dir / "stats.json";
    const std::string args = scene + " -q --width 8 --height 8 --spp 1 -o " + image.string() + " --stats-json " + stats.string();
    CliRun first = penumbra(args);
    ASSERT_EQ(first.exitCode, 0) << first.output;
    const std::string good = readBytes(stats);
    ASSERT_NE(good.find("\"render_seconds\""), std::string::npos) << good;
    {
        struct statvfs st {};
        ASSERT_EQ(::statvfs(dir.c_str(), &st), 0);
        std::ofstream filler(dir / "filler", std::ios::binary);
        const std::string block(size_t(st.f_bavail) * st.f_frsize, 'x');
        filler.write(block.data(), std::streamsize(block.size()));
    }
    CliRun full = penumbra(args);
    EXPECT_EQ(full.exitCode, 1) << full.output;
    EXPECT_NE(full.output.find(stats.string() + ": cannot write statistics"), std::string::npos) << full.output;
    EXPECT_EQ(readBytes(stats), good) << "the old statistics were changed";
    for (const auto& e : fs::directory_iterator(dir))
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
}

TEST(CApiFullDisk, WriteImageReturnsIoErrorAndKeepsTheOldImage) {
    const fs::path dir = test::tempDir() / "disk";
    fs::create_directories(dir);
    if (::mount("tmpfs", dir.c_str(), "tmpfs", 0, "size=200k") != 0)
        GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno) << ")";
    struct Unmount {
        fs::path d;
        ~Unmount() { ::umount2(d.c_str(), MNT_DETACH); }
    } unmount{dir};
    pnb_render_settings settings;
    pnb_render_settings_init(&settings);
    settings.width = 200;
    settings.height = 200;
    pnb_framebuffer* image = nullptr;
    ASSERT_EQ(pnb_framebuffer_create(&settings, &image), PNB_OK) << pnb_last_error();
    for (const char* ext : {".png", ".jpg", ".exr"}) {
        SCOPED_TRACE(ext);
        const fs::path out = dir / (std::string("host") + ext);
        // A good old file, then the disk filled up to its last KiB.
        { std::ofstream(out, std::ios::binary) << "the old image"; }
        struct statvfs st {};
        ASSERT_EQ(::statvfs(dir.c_str(), &st), 0);
        const size_t avail = size_t(st.f_bavail) * st.f_frsize;
        {
            std::ofstream filler(dir / "filler", std::ios::binary);
            const std::string block(avail > 1024 ? avail - 1024 : 0, 'x');
            filler.write(block.data(), std::streamsize(block.size()));
        }
        EXPECT_EQ(pnb_framebuffer_write_image(image, out.c_str(), nullptr), PNB_ERROR_IO);
        EXPECT_NE(std::string(pnb_last_error()).find(out.string()), std::string::npos) << pnb_last_error();
        EXPECT_EQ(readBytes(out), "the old image");
        size_t files = 0;
        for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++files;
        EXPECT_EQ(files, 2u) << "a temporary file was left";
        fs::remove(dir / "filler");
        fs::remove(out);
    }
    pnb_framebuffer_destroy(image);
}

}  // namespace
