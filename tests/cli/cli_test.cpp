// End-to-end tests of the penumbra command: formats, crop stitching, errors.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/image_io.h"
#include "support/test_support.h"

using namespace penumbra;
namespace fs = std::filesystem;

namespace {

struct RunResult {
    int exitCode;
    std::string output;  // stdout + stderr
};

RunResult runPenumbra(const std::string& args) {
    std::string cmd = (test::binaryDir() / "penumbra").string() + " " + args + " 2>&1";
    FILE* p = ::popen(cmd.c_str(), "r");
    if (!p) return {-1, "popen failed"};
    std::string out;
    std::array<char, 4096> buf{};
    size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
    int status = ::pclose(p);
    int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return {code, out};
}

// A small JSON scene: floor, a sphere, a rectangle light; quick to render.
fs::path smallScene(const fs::path& dir) {
    return test::writeFile(dir / "small.json", R"({
  "camera": {"eye": [0, 1, 4], "look_at": [0, 0.5, 0], "up": [0, 1, 0], "fov": 40},
  "render": {"width": 32, "height": 24, "spp": 4, "light_samples": 2, "seed": 3},
  "materials": {
    "floor": {"kd": 0.7},
    "ball": {"kd": [0.8, 0.3, 0.2], "ks": 0.2, "n": 40},
    "lamp": {"kd": 0, "ke": 6}
  },
  "shapes": [
    {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"},
    {"type": "sphere", "center": [0, 0.5, 0], "radius": 0.5, "material": "ball"},
    {"type": "rectangle", "p0": [-0.5, 2, -0.5], "a": [1, 0, 0], "b": [0, 0, 1], "material": "lamp"}
  ]
})");
}

}  // namespace

TEST(Cli, RendersEveryOutputFormatAndTheValuesReadBack) {
    fs::path dir = test::tempDir();
    fs::path scene = smallScene(dir);
    ASSERT_EQ(runPenumbra(scene.string() + " -q -o " + (dir / "ref.exr").string()).exitCode, 0);
    ImageData ref = readImage(dir / "ref.exr");
    ASSERT_EQ(ref.width, 32);
    ASSERT_EQ(ref.height, 24);
    double sum = 0;
    for (float v : ref.pixels) sum += v;
    EXPECT_GT(sum / ref.pixels.size(), 0.01) << "the image is lit";
    for (const char* ext : {".hdr", ".pfm", ".png", ".jpg", ".tif"}) {
        fs::path out = dir / (std::string("img") + ext);
        RunResult r = runPenumbra(scene.string() + " -q -o " + out.string());
        ASSERT_EQ(r.exitCode, 0) << ext << ": " << r.output;
        ImageData img = readImage(out);
        ASSERT_EQ(img.width, 32) << ext;
        ASSERT_EQ(img.height, 24) << ext;
        // Compare a mid-grey pixel: float formats hold linear radiance, 8-bit ones sRGB.
        const int x = 16, y = 18;
        float linear = ref.at(x, y, 0);
        float got = img.at(x, y, 0);
        if (std::string(ext) == ".hdr") {
            EXPECT_NEAR(got, linear, 0.01f * linear + 1e-4f) << ext;  // RGBE: 8-bit mantissa
        } else if (std::string(ext) == ".pfm") {
            EXPECT_EQ(got, linear) << ext;
        } else {
            EXPECT_NEAR(got, linearToSrgb(linear), std::string(ext) == ".jpg" ? 0.05f : 1.f / 255.f + 1e-6f) << ext;
        }
    }
    // No temporary files are left behind.
    for (const auto& e : fs::directory_iterator(dir)) EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos);
}

TEST(Cli, ExrCarriesLinearRadianceMetadataAndAovs) {
    fs::path dir = test::tempDir();
    fs::path scene = smallScene(dir);
    RunResult r = runPenumbra(scene.string() + " -q --aovs --spp 1 -o " + (dir / "a.exr").string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    ImageData img = readImage(dir / "a.exr");
    ASSERT_EQ(img.channels, 10);
    EXPECT_EQ(img.channelNames[0], "R");
    bool hasSpp = false;
    for (auto& [k, v] : img.attributes)
        if (k == "penumbra:spp") hasSpp = (v == "1");
    EXPECT_TRUE(hasSpp);
    // Depth of the centre pixel: the sphere at distance ~ |(0,1,4) - sphere| - 0.5 > 3.
    int zc = -1;
    for (int c = 0; c < img.channels; ++c)
        if (img.channelNames[c] == "Z") zc = c;
    ASSERT_GE(zc, 0);
    EXPECT_GT(img.at(16, 12, zc), 3.0f);
    EXPECT_LT(img.at(16, 12, zc), 4.5f);
}

TEST(Cli, CropTilesStitchIntoTheFullFrameBitForBit) {
    fs::path dir = test::tempDir();
    fs::path scene = smallScene(dir);
    ASSERT_EQ(runPenumbra(scene.string() + " -q -o " + (dir / "full.exr").string()).exitCode, 0);
    ImageData full = readImage(dir / "full.exr");
    const std::array<std::array<int, 4>, 4> crops{{{0, 0, 16, 12}, {16, 0, 32, 12}, {0, 12, 16, 24}, {16, 12, 32, 24}}};
    for (const auto& c : crops) {
        fs::path out = dir / ("crop" + std::to_string(c[0]) + "_" + std::to_string(c[1]) + ".exr");
        std::string crop = std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]) + "," +
                           std::to_string(c[3]);
        RunResult r = runPenumbra(scene.string() + " -q --crop " + crop + " -o " + out.string());
        ASSERT_EQ(r.exitCode, 0) << r.output;
        ImageData part = readImage(out);
        ASSERT_EQ(part.width, c[2] - c[0]);
        for (int y = c[1]; y < c[3]; ++y)
            for (int x = c[0]; x < c[2]; ++x)
                for (int ch = 0; ch < 3; ++ch) ASSERT_EQ(part.at(x - c[0], y - c[1], ch), full.at(x, y, ch));
    }
}

TEST(Cli, StatsJsonCountsRays) {
    fs::path dir = test::tempDir();
    fs::path scene = smallScene(dir);
    RunResult r = runPenumbra(scene.string() + " -q -o " + (dir / "s.png").string() + " --stats-json " +
                              (dir / "stats.json").string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    std::ifstream in(dir / "stats.json");
    nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_EQ(j["rays"]["camera"].get<uint64_t>(), 32u * 24u * 4u);
    EXPECT_GT(j["rays"]["shadow"].get<uint64_t>(), 0u);
    uint64_t sum = 0;
    for (const char* kind : {"camera", "shadow", "reflection", "transmission", "indirect", "brdf"})
        sum += j["rays"][kind].get<uint64_t>();
    EXPECT_EQ(j["rays"]["total"].get<uint64_t>(), sum);
    EXPECT_EQ(j["width"].get<int>(), 32);
    EXPECT_GT(j["peak_memory_mib"].get<double>(), 1.0);
}

// More threads than the machine runs at once are not started: no raw TBB
// warning, one warning of the command's own, and the summary and statistics
// say how many threads rendered. The image is the same as on one thread.
TEST(Cli, ThreadsAboveTheMachineRunOnAllItsThreadsAndSaySo) {
    fs::path dir = test::tempDir();
    fs::path scene = smallScene(dir);
    RunResult r = runPenumbra(scene.string() + " --threads 4096 -o " + (dir / "many.exr").string() + " --stats-json " +
                              (dir / "stats.json").string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output.find("TBB"), std::string::npos) << r.output;
    std::ifstream in(dir / "stats.json");
    const int threads = nlohmann::json::parse(in)["threads"].get<int>();
    EXPECT_GE(threads, 1);
    EXPECT_LT(threads, 4096);
    EXPECT_NE(r.output.find("on " + std::to_string(threads) + " threads"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("penumbra: warning: --threads 4096: this machine runs " + std::to_string(threads) +
                            " threads at once"),
              std::string::npos)
        << r.output;
    ASSERT_EQ(runPenumbra(scene.string() + " -q --threads 1 -o " + (dir / "one.exr").string()).exitCode, 0);
    EXPECT_EQ(readImage(dir / "many.exr").pixels, readImage(dir / "one.exr").pixels);
}

TEST(Cli, CommandLineOverridesTheSceneFile) {
    fs::path dir = test::tempDir();
    fs::path scene = smallScene(dir);
    RunResult r = runPenumbra(scene.string() + " -q --width 20 --height 10 --spp 1 -o " + (dir / "o.exr").string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    ImageData img = readImage(dir / "o.exr");
    EXPECT_EQ(img.width, 20);
    EXPECT_EQ(img.height, 10);
}

TEST(Cli, BadOptionsFailBeforeAnyWorkWithAClearMessage) {
    fs::path dir = test::tempDir();
    fs::path scene = smallScene(dir);
    const std::string out = " -o " + (dir / "x.png").string();
    struct Case {
        std::string args, expect;
    } cases[] = {
        {scene.string() + out + " --width 0", "width"},
        {scene.string() + out + " --spp 0", "spp"},
        {scene.string() + out + " --threads -1", "threads"},
        {scene.string() + out + " --eye 1,2,3 --look-at 1,2,3", "same point"},
        {scene.string() + out + " --eye 0,0,5 --look-at 0,0,0 --up 0,0,1", "parallel"},
        {scene.string() + out + " --fov 180", "fov"},
        {scene.string() + out + " --accel kdtree", "unknown accelerator"},
        {scene.string() + " -o " + (dir / "x.bmpx").string(), "unknown image format"},
        {scene.string() + " -o " + (dir / "missing-folder" / "x.png").string(), "does not exist"},
        {scene.string() + out + " --eye 1,2", "--eye"},
        {(dir / "nope.json").string() + out, "nope.json"},
        {scene.string() + out + " --crop 0,0,100,100", "crop"},
    };
    for (const auto& c : cases) {
        RunResult r = runPenumbra(c.args);
        EXPECT_NE(r.exitCode, 0) << c.args;
        EXPECT_LT(r.exitCode, 128) << "died by a signal: " << c.args;
        EXPECT_NE(r.output.find(c.expect), std::string::npos) << c.args << "\n" << r.output;
    }
    EXPECT_FALSE(fs::exists(dir / "x.png"));
}

TEST(Cli, NaiveAndEmbreeRenderTheSameImage) {
    fs::path dir = test::tempDir();
    fs::path scene = smallScene(dir);
    ASSERT_EQ(runPenumbra(scene.string() + " -q --accel embree -o " + (dir / "e.exr").string()).exitCode, 0);
    ASSERT_EQ(runPenumbra(scene.string() + " -q --accel naive -o " + (dir / "n.exr").string()).exitCode, 0);
    ImageData e = readImage(dir / "e.exr"), n = readImage(dir / "n.exr");
    ASSERT_EQ(e.pixels.size(), n.pixels.size());
    double maxDiff = 0;
    for (size_t i = 0; i < e.pixels.size(); ++i) maxDiff = std::max(maxDiff, double(std::fabs(e.pixels[i] - n.pixels[i])));
    EXPECT_LT(maxDiff, 1e-3);
}

TEST(Cli, DefaultSceneRendersTheSameWithBothAccelerators) {
    fs::path dir = test::tempDir();
    const std::string scene = test::assetPath("cornell/cornell.obj").string();
    const std::string opts = " -q --width 96 --height 96 --spp 4 ";
    ASSERT_EQ(runPenumbra(scene + opts + "--accel embree -o " + (dir / "e.exr").string()).exitCode, 0);
    ASSERT_EQ(runPenumbra(scene + opts + "--accel naive -o " + (dir / "n.exr").string()).exitCode, 0);
    ImageData e = readImage(dir / "e.exr"), n = readImage(dir / "n.exr");
    ASSERT_EQ(e.pixels.size(), n.pixels.size());
    size_t differing = 0;
    double maxDiff = 0, sum = 0;
    for (size_t i = 0; i < e.pixels.size(); i += 3) {
        double d = 0;
        for (int c = 0; c < 3; ++c) d = std::max(d, double(std::fabs(e.pixels[i + c] - n.pixels[i + c])));
        if (d > 1e-6) ++differing;
        maxDiff = std::max(maxDiff, d);
        sum += e.pixels[i];
    }
    const size_t pixels = e.pixels.size() / 3;
    std::cout << "[ measured ] default scene, embree vs naive: " << differing << " of " << pixels
              << " pixels differ by more than 1e-6; max difference " << maxDiff << "\n";
    EXPECT_GT(sum / pixels, 0.01) << "the room is lit";
    EXPECT_LE(differing, pixels / 1000);  // at most 0.1% of the pixels (grazing rays along box edges)
    EXPECT_LT(maxDiff, 1e-2);
}

TEST(Cli, WarnsWhenTheImageIsBlackOrAllBackground) {
    const fs::path dir = test::tempDir();
    const std::string warning = "the camera may be outside a closed model; try --eye/--look-at";
    // The small scene seen as it is: no warning.
    const fs::path scene = smallScene(dir);
    RunResult r = runPenumbra(scene.string() + " -q -o " + (dir / "ok.pfm").string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output.find(warning), std::string::npos) << r.output;
    // Inside a closed box whose inside nothing lights: black.
    const fs::path box = test::writeFile(dir / "box.json", R"({
  "camera": {"eye": [0, 0, 0], "look_at": [0, 0, -1], "up": [0, 1, 0], "fov": 60},
  "render": {"width": 16, "height": 16, "spp": 1, "seed": 1},
  "materials": {"wall": {"kd": 0.5}},
  "shapes": [{"type": "box", "min": [-1, -1, -1], "max": [1, 1, 1], "material": "wall"}],
  "lights": [{"type": "point", "position": [0, 5, 0], "intensity": 10}]
})");
    r = runPenumbra(box.string() + " -q -o " + (dir / "box.pfm").string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("the image is black; " + warning), std::string::npos) << r.output;
    // Looking away from the scene under a grey background: nearly all background, though not black.
    r = runPenumbra(scene.string() + " -q --look-at 0,10,5 --background 0.5,0.5,0.5 -o " + (dir / "away.pfm").string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("nearly all background"), std::string::npos) << r.output;
}
