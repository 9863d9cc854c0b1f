// OpenImageIO lives in libpenumbra_oiio.so, loaded on the first image:
// `penumbra --help` and a render to PFM never load it; an EXR render loads it
// once, from beside libpenumbra.so, in the rendering process itself (no helper
// process). Checked with the dynamic linker's own trace (LD_DEBUG=files).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
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

// The process id that the trace's first line naming `library` starts with ("  PID:\tfile=...").
long loaderOf(const std::string& trace, const std::string& library) {
    const size_t at = trace.find("file=" + library);
    if (at == std::string::npos) return -1;
    const size_t line = trace.rfind('\n', at) + 1;  // npos + 1 == 0: the first line
    return std::strtol(trace.c_str() + line, nullptr, 10);
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
    // By the renderer itself: the command starts no other process.
    const long renderer = loaderOf(exr, "libembree3"), loader = loaderOf(exr, "libOpenImageIO");
    EXPECT_GT(renderer, 0) << exr.substr(0, 2000);
    EXPECT_EQ(loader, renderer) << "OpenImageIO was loaded by another process";
    // Found by its full path (beside libpenumbra.so, or ../lib), not through the search path, and loaded once.
    const std::string module = "file=" + (test::binaryDir().parent_path() / "lib" / "libpenumbra_oiio.so").string() +
                               " [0];  dynamically loaded by";
    const size_t first = exr.find(module);
    EXPECT_NE(first, std::string::npos) << exr.substr(0, 2000);
    EXPECT_EQ(first, exr.rfind(module)) << "loaded more than once";
}

}  // namespace
