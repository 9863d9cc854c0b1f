// Input files end to end through the penumbra command (issue 13 items 3, 8, 9,
// 10): what is not a regular file, loops, /dev/zero, deep duplicate keys and
// geometry beyond the accelerators' range each fail fast and cleanly with one
// short error line that gives the reason, and nothing is written.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <initializer_list>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_support.h"

namespace {

namespace fs = std::filesystem;

struct RunResult {
    int exitCode;
    std::string output;  // stdout + stderr
    double seconds;
};

std::string quote(const fs::path& p) {
    std::string q = "'";
    for (char c : p.string()) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

/// Runs penumbra with a time limit (a blocking read would otherwise hang the suite).
RunResult run(const std::string& args) {
    std::string cmd = "timeout -s KILL 60 " + quote(penumbra::test::binaryDir() / "penumbra") + " " + args + " 2>&1";
    auto t0 = std::chrono::steady_clock::now();
    FILE* p = ::popen(cmd.c_str(), "r");
    if (!p) return {-1, "popen failed", 0.0};
    std::string out;
    std::array<char, 4096> buf{};
    size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
    int status = ::pclose(p);
    int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return {code, out, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()};
}

class InputFiles : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = penumbra::test::tempDir();
        fs::create_directories(dir_ / "out");
    }
    fs::path write(const std::string& name, const std::string& text) const {
        return penumbra::test::writeFile(dir_ / name, text);
    }
    std::string args(const std::string& scene) const {
        return quote(dir_ / scene) + " -q --width 8 --height 8 --spp 1 -o " + quote(dir_ / "out" / "img.exr");
    }

    /// Exit 1 within a few seconds, exactly one short error line holding every needle, no output file.
    void expectRefused(const std::string& scene, std::initializer_list<std::string> needles) const {
        RunResult r = run(args(scene));
        EXPECT_EQ(r.exitCode, 1) << r.output;
        EXPECT_LT(r.seconds, 20.0) << scene;
        std::vector<std::string> errors;
        std::istringstream in(r.output);
        for (std::string line; std::getline(in, line);)
            if (line.rfind("penumbra: error: ", 0) == 0) errors.push_back(line);
        ASSERT_EQ(errors.size(), 1u) << r.output.substr(0, 2000);
        for (const auto& n : needles) EXPECT_NE(errors[0].find(n), std::string::npos) << "'" << n << "' not in: " << errors[0];
        EXPECT_LT(errors[0].size(), 600u) << errors[0].substr(0, 600);
        EXPECT_TRUE(fs::is_empty(dir_ / "out"));
    }

    fs::path dir_;
};

constexpr const char* kQuad = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n";

TEST_F(InputFiles, FifoSceneFailsAtOnce) {
    ASSERT_EQ(::mkfifo((dir_ / "fifo.json").c_str(), 0600), 0);
    ASSERT_EQ(::mkfifo((dir_ / "fifo.obj").c_str(), 0600), 0);
    expectRefused("fifo.json", {"fifo.json", "is not a regular file", "FIFO"});
    expectRefused("fifo.obj", {"fifo.obj", "is not a regular file", "FIFO"});
}

TEST_F(InputFiles, SceneLinkedToDevZeroIsRefused) {
    fs::create_symlink("/dev/zero", dir_ / "zero.json");
    fs::create_symlink("/dev/zero", dir_ / "zero.obj");
    expectRefused("zero.json", {"zero.json", "is not a regular file", "character device"});
    expectRefused("zero.obj", {"zero.obj", "is not a regular file", "character device"});
}

TEST_F(InputFiles, SceneSymlinkLoopSaysSo) {
    fs::create_symlink(dir_ / "b.json", dir_ / "a.json");
    fs::create_symlink(dir_ / "a.json", dir_ / "b.json");
    expectRefused("a.json", {"a.json", "symlink loop"});
}

TEST_F(InputFiles, MeshThatIsAFifoOrDirectoryGetsItsReason) {
    ASSERT_EQ(::mkfifo((dir_ / "mesh.obj").c_str(), 0600), 0);
    fs::create_directories(dir_ / "folder.obj");
    write("a.json", R"({"shapes": [{"type": "mesh", "file": "mesh.obj"}]})");
    write("b.json", R"({"shapes": [{"type": "mesh", "file": "folder.obj"}]})");
    expectRefused("a.json", {"a.json", "/shapes/0/file", "mesh.obj", "is not a regular file", "FIFO"});
    expectRefused("b.json", {"b.json", "/shapes/0/file", "folder.obj", "is a directory"});
}

TEST_F(InputFiles, MtlThatIsAFifoIsSkippedWithItsReason) {
    ASSERT_EQ(::mkfifo((dir_ / "lib.mtl").c_str(), 0600), 0);
    write("scene.obj", "mtllib lib.mtl\n" + std::string(kQuad));
    RunResult r = run(args("scene.obj"));
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_LT(r.seconds, 20.0);
    EXPECT_NE(r.output.find("lib.mtl: is not a regular file (it is a FIFO)"), std::string::npos) << r.output;
}

TEST_F(InputFiles, DuplicateKeyFiftyThousandLevelsDeepIsOneShortLine) {
    std::string json;
    for (int i = 0; i < 50000; ++i) json += "{\"a\": ";
    json += "{\"k\": 1, \"k\": 2}";
    for (int i = 0; i < 50000; ++i) json += "}";
    write("deep.json", json);
    expectRefused("deep.json", {"deep.json", "levels", "/a/k: duplicate key"});
}

TEST_F(InputFiles, DiskLightBeyondTheAcceleratorRangeIsRefusedForBoth) {
    write("big.json", R"({"camera": {"eye": [0, 0, 5], "look_at": [0, 0, 0]},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1}],
        "lights": [{"type": "disk", "center": [0, 5, 0], "normal": [0, -1, 0], "radius": 1e19, "radiance": 1}]})");
    expectRefused("big.json", {"big.json", "/lights/0", "beyond", "1.8e18"});
    RunResult naive = run(args("big.json") + " --accel naive");
    EXPECT_EQ(naive.exitCode, 1) << naive.output;
    EXPECT_NE(naive.output.find("beyond"), std::string::npos) << naive.output;
}

TEST_F(InputFiles, FloatingPointSeedTooLargeToBeExactIsAnError) {
    write("seed.json", R"({"render": {"seed": 9223372036854775807.0},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1}]})");
    expectRefused("seed.json", {"seed.json", "/render/seed", "too large to be exact"});
}

}  // namespace
