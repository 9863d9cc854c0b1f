// OpenImageIO lives in libpenumbra_oiio.so, loaded on the first image (issue
// 14): `penumbra --help` and a render to PFM never load it; an EXR render
// loads it once, from beside libpenumbra.so. Checked with the dynamic
// linker's own trace (LD_DEBUG=files).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

#include "support/test_support.h"

namespace {
using namespace penumbra;

std::string tracedRun(const std::string& args, int* exitCode) {
    const std::string cmd =
        "LD_DEBUG=files " + (test::binaryDir() / "penumbra").string() + " " + args + " 2>&1";
    FILE* p = ::popen(cmd.c_str(), "r");
    if (!p) return "popen failed";
    std::string out;
    std::array<char, 4096> buf{};
    size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
    const int status = ::pclose(p);
    *exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return out;
}

bool loads(const std::string& trace, const std::string& library) {
    return trace.find("file=" + library) != std::string::npos;
}

TEST(ImageModule, LoadedOnlyByProcessesThatTouchAnImage) {
    const auto dir = test::tempDir();
    const std::string scene = test::assetPath("cornell/cornell.obj").string() + " -q --width 8 --height 8 --spp 1";
    int code = -1;
    std::string help = tracedRun("--help", &code);
    EXPECT_EQ(code, 0);
    EXPECT_FALSE(loads(help, "libOpenImageIO")) << "--help loaded OpenImageIO";
    EXPECT_FALSE(loads(help, "libpenumbra_oiio"));

    std::string pfm = tracedRun(scene + " -o " + (dir / "a.pfm").string(), &code);
    EXPECT_EQ(code, 0) << pfm;
    EXPECT_FALSE(loads(pfm, "libOpenImageIO")) << "a PFM render loaded OpenImageIO";

    std::string exr = tracedRun(scene + " -o " + (dir / "a.exr").string(), &code);
    EXPECT_EQ(code, 0) << exr;
    EXPECT_TRUE(loads(exr, "libOpenImageIO")) << exr.substr(0, 2000);
    // Found by its full path (beside libpenumbra.so, or ../lib), not through the search path.
    EXPECT_NE(exr.find("file=" + (test::binaryDir().parent_path() / "lib" / "libpenumbra_oiio.so").string()),
              std::string::npos)
        << exr.substr(0, 2000);
}

}  // namespace
