// The installed package, used the way a host project uses it: `cmake --install`
// of this build tree into a temporary prefix, then the tiny project in
// tests/api/external and the examples in apps/examples configured with
// find_package(Penumbra) against that prefix, built, run, and their images
// checked; and the same C host built with the flags pkg-config gives.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <vector>

#include "core/image_io.h"
#include "support/test_support.h"

namespace {

namespace fs = std::filesystem;

// A library built with AddressSanitizer only loads into programs linked with
// its runtime, so the host programs get the same link flag.
#if defined(__SANITIZE_ADDRESS__)
#define PENUMBRA_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PENUMBRA_TEST_ASAN 1
#endif
#endif
#ifdef PENUMBRA_TEST_ASAN
const std::string kHostLinkFlags = "-fsanitize=address";
#else
const std::string kHostLinkFlags;
#endif

std::string shellQuoted(const fs::path& p) {
    // Appended, not "'" + ...: GCC 12 warns falsely (-Wrestrict) on that form.
    std::string s(1, '\'');
    s += p.string();
    s += '\'';
    return s;
}

std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Runs a shell command with its output in `log`; true on exit status 0.
bool run(const std::string& command, const fs::path& log) {
    return std::system((command + " > " + shellQuoted(log) + " 2>&1").c_str()) == 0;
}

fs::path findFile(const fs::path& root, const std::string& name) {
    for (const auto& e : fs::recursive_directory_iterator(root))
        if (e.is_regular_file() && e.path().filename() == name) return e.path();
    return {};
}

// The targets of the #include lines of a header.
std::vector<std::string> includesOf(const fs::path& header) {
    std::vector<std::string> out;
    std::istringstream text(slurp(header));
    for (std::string line; std::getline(text, line);) {
        const size_t hash = line.find_first_not_of(" \t");
        if (hash == std::string::npos || line[hash] != '#') continue;
        const size_t word = line.find_first_not_of(" \t", hash + 1);
        if (word == std::string::npos || line.compare(word, 7, "include") != 0) continue;
        const size_t open = line.find_first_of("<\"", word + 7);
        const size_t close = open == std::string::npos ? open : line.find_first_of(">\"", open + 1);
        if (close != std::string::npos) out.push_back(line.substr(open + 1, close - open - 1));
    }
    return out;
}

// The value of the first whitespace-separated flag starting with `prefix` ("-I", "-L").
std::string flagValue(const std::string& flags, const std::string& prefix) {
    std::istringstream words(flags);
    for (std::string w; words >> w;)
        if (w.rfind(prefix, 0) == 0) return w.substr(prefix.size());
    return {};
}

std::string trim(std::string s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
    return s;
}

// The centre of the external hosts' image is the sphere lit head-on:
// kd/pi * I/d^2 = 0.8/pi * 20/16, sRGB-encoded in the PNG; the corners are background (black).
void checkHostImage(const fs::path& png) {
    const penumbra::ImageData img = penumbra::readImage(png);
    ASSERT_EQ(img.width, 33);
    ASSERT_EQ(img.height, 33);
    const float expected = penumbra::linearToSrgb(0.8f / 3.14159265f * 20.f / 16.f);
    EXPECT_NEAR(img.at(16, 16, 0), expected, 2.f / 255.f) << png;
    EXPECT_NEAR(img.at(16, 16, 2), expected, 2.f / 255.f) << png;
    EXPECT_EQ(img.at(0, 0, 0), 0.f) << png;
}

TEST(Install, HostProjectsBuildAgainstTheInstalledPackage) {
    const fs::path tmp = penumbra::test::tempDir();
    const fs::path prefix = tmp / "prefix";
    const fs::path log = tmp / "log.txt";
    ASSERT_TRUE(run("cmake --install " + shellQuoted(PENUMBRA_BINARY_DIR) + " --prefix " + shellQuoted(prefix), log))
        << slurp(log);

    // Exactly the public headers, which include only each other and standard headers.
    std::set<std::string> headers;
    for (const auto& e : fs::recursive_directory_iterator(prefix / "include"))
        if (e.is_regular_file()) headers.insert(fs::relative(e.path(), prefix / "include").string());
    EXPECT_EQ(headers, (std::set<std::string>{"penumbra/names.hpp", "penumbra/penumbra.h", "penumbra/penumbra.hpp", "penumbra/types.hpp",
                                              "penumbra/version.h"}));
    const std::vector<std::string> hppIncludes = includesOf(prefix / "include" / "penumbra" / "penumbra.hpp");
    EXPECT_NE(std::find(hppIncludes.begin(), hppIncludes.end(), "penumbra/version.h"), hppIncludes.end());
    EXPECT_NE(std::find(hppIncludes.begin(), hppIncludes.end(), "functional"), hppIncludes.end());
    for (const std::string& h : headers) {
        for (const std::string& inc : includesOf(prefix / "include" / h)) {
            const bool own = inc.rfind("penumbra/", 0) == 0;
            const bool standard = inc.find('/') == std::string::npos &&
                                  (inc.find('.') == std::string::npos || inc == "stddef.h" || inc == "stdint.h");
            EXPECT_TRUE(own || standard) << h << " includes " << inc;
        }
    }
    const fs::path config = findFile(prefix, "PenumbraConfig.cmake");
    ASSERT_FALSE(config.empty());
    EXPECT_FALSE(findFile(prefix, "PenumbraConfigVersion.cmake").empty());
    const fs::path pc = findFile(prefix, "penumbra.pc");
    ASSERT_FALSE(pc.empty());
    const fs::path libdir = pc.parent_path().parent_path();
    EXPECT_TRUE(fs::exists(libdir / "libpenumbra.so"));

    // The installed command starts from its prefix (install RPATH $ORIGIN/../lib), without
    // LD_LIBRARY_PATH, and renders the default scene exactly as the build tree's command does.
    const fs::path installed = prefix / "bin" / "penumbra";
    ASSERT_TRUE(fs::exists(installed));
    const std::string cornell = shellQuoted(fs::path(PENUMBRA_SOURCE_DIR) / "assets/cornell/cornell.obj");
    const std::string renderArgs = " -q --width 40 --height 30 --spp 2 -o ";
    ASSERT_TRUE(run("env -u LD_LIBRARY_PATH " + shellQuoted(installed) + " " + cornell + renderArgs +
                        shellQuoted(tmp / "installed.exr"),
                    log))
        << slurp(log);
    ASSERT_TRUE(run(shellQuoted(fs::path(PENUMBRA_BINARY_DIR) / "bin" / "penumbra") + " " + cornell + renderArgs +
                        shellQuoted(tmp / "built.exr"),
                    log))
        << slurp(log);
    {
        const penumbra::ImageData got = penumbra::readImage(tmp / "installed.exr");
        const penumbra::ImageData want = penumbra::readImage(tmp / "built.exr");
        ASSERT_EQ(got.width, 40);
        ASSERT_EQ(got.height, 30);
        double sum = 0;
        for (float v : got.pixels) {
            ASSERT_TRUE(std::isfinite(v));
            sum += v;
        }
        EXPECT_GT(sum / double(got.pixels.size()), 0.01) << "the Cornell box is lit";
        EXPECT_EQ(got.pixels, want.pixels) << "the installed command renders what the built one does";
    }

    // find_package(Penumbra) from a separate project, strict C99 and C++17 with -Werror.
    const fs::path build = tmp / "external-build";
    ASSERT_TRUE(run("cmake -S " + shellQuoted(fs::path(PENUMBRA_SOURCE_DIR) / "tests/api/external") + " -B " +
                        shellQuoted(build) + " -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=" + shellQuoted(prefix) +
                        " -DCMAKE_EXE_LINKER_FLAGS=" + shellQuoted(kHostLinkFlags),
                    log))
        << slurp(log);
    EXPECT_NE(slurp(log).find("Penumbra 0.1.0 headers in " + (prefix / "include").string()), std::string::npos)
        << slurp(log);
    ASSERT_TRUE(run("cmake --build " + shellQuoted(build) + " -j2", log)) << slurp(log);
    for (const std::string host : {"host_c", "host_cpp"}) {
        const fs::path png = tmp / (host + ".png");
        ASSERT_TRUE(run(shellQuoted(build / host) + " " + shellQuoted(png), log)) << slurp(log);
        EXPECT_NE(slurp(log).find(host + " 0.1.0 centre 0.31"), std::string::npos) << slurp(log);
        checkHostImage(png);
    }

    // The example hosts of apps/examples, built on their own against the package.
    const fs::path examples = tmp / "examples-build";
    ASSERT_TRUE(run("cmake -S " + shellQuoted(fs::path(PENUMBRA_SOURCE_DIR) / "apps/examples") + " -B " +
                        shellQuoted(examples) + " -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=" +
                        shellQuoted(prefix) + " -DCMAKE_EXE_LINKER_FLAGS=" + shellQuoted(kHostLinkFlags),
                    log))
        << slurp(log);
    ASSERT_TRUE(run("cmake --build " + shellQuoted(examples) + " -j2", log)) << slurp(log);
    for (const std::string example : {"embed_cpp", "embed_c"}) {
        const fs::path png = tmp / (example + ".png");
        ASSERT_TRUE(run(shellQuoted(examples / example) + " " + shellQuoted(png), log)) << slurp(log);
        EXPECT_NE(slurp(log).find(example + ": wrote"), std::string::npos) << slurp(log);
        const penumbra::ImageData img = penumbra::readImage(png);
        ASSERT_EQ(img.width, 320);
        ASSERT_EQ(img.height, 240);
        // The centre shows the lit sphere: red in the C++ example, blue in the C one.
        const float r = img.at(160, 120, 0), b = img.at(160, 120, 2);
        if (example == "embed_cpp") {
            EXPECT_GT(r, 0.3f);
            EXPECT_GT(r, 2.f * b);
        } else {
            EXPECT_GT(b, 0.3f);
            EXPECT_GT(b, 2.f * r);
        }
    }

    // pkg-config, where it is installed.
    if (!run("pkg-config --version", log)) {
        std::cout << "pkg-config not found: skipping the pkg-config checks\n";
        return;
    }
    const std::string env = "PKG_CONFIG_PATH=" + shellQuoted(pc.parent_path()) + " ";
    ASSERT_TRUE(run(env + "pkg-config --modversion penumbra", log)) << slurp(log);
    EXPECT_EQ(trim(slurp(log)), "0.1.0");
    ASSERT_TRUE(run(env + "pkg-config --cflags --libs penumbra", log)) << slurp(log);
    const std::string flags = trim(slurp(log));
    EXPECT_NE(flags.find("-lpenumbra"), std::string::npos) << flags;
    const std::string includeDir = flagValue(flags, "-I"), linkDir = flagValue(flags, "-L");
    ASSERT_FALSE(includeDir.empty()) << flags;
    EXPECT_TRUE(fs::exists(fs::path(includeDir) / "penumbra" / "penumbra.h")) << flags;
    ASSERT_FALSE(linkDir.empty()) << flags;
    EXPECT_TRUE(fs::equivalent(fs::path(linkDir), libdir)) << flags;

    const fs::path exe = tmp / "host_c_pkgconfig";
    ASSERT_TRUE(run("cc -std=c99 -Wall -Wextra -Wpedantic -Werror " +
                        shellQuoted(fs::path(PENUMBRA_SOURCE_DIR) / "tests/api/external/host_c.c") + " -o " +
                        shellQuoted(exe) +
                        " " + flags + " " + kHostLinkFlags + " -Wl,-rpath," + libdir.string(),
                    log))
        << slurp(log);
    const fs::path png = tmp / "host_c_pkgconfig.png";
    ASSERT_TRUE(run(shellQuoted(exe) + " " + shellQuoted(png), log)) << slurp(log);
    checkHostImage(png);
}

}  // namespace
