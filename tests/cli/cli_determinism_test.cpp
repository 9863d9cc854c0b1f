// Determinism end to end: the penumbra command, given the same scene and
// seed, writes bit-identical pixels whatever the thread count or tile size,
// and run after run. (The EXR's render_seconds metadata differs, so only the
// pixel data is compared.)
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "core/image_io.h"
#include "support/test_support.h"

using namespace penumbra;
namespace fs = std::filesystem;

namespace {

int runPenumbra(const std::string& args, std::string* output = nullptr) {
    std::string cmd = (test::binaryDir() / "penumbra").string() + " " + args + " 2>&1";
    FILE* p = ::popen(cmd.c_str(), "r");
    if (!p) return -1;
    std::string out;
    std::array<char, 4096> buf{};
    size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
    int status = ::pclose(p);
    if (output) *output = out;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// Everything that draws random numbers: area lights (a rectangle and a sphere)
// sampled several times per hit, a glossy and a mirror material, a thin lens,
// a point light, and both light-selection modes (chosen per test).
fs::path writeScene(const fs::path& dir) {
    return test::writeFile(dir / "scene.json", R"({
  "camera": {"eye": [0, 1.2, 4], "look_at": [0, 0.6, 0], "fov": 45, "aperture": 0.04, "focus_distance": 4},
  "render": {"width": 40, "height": 30, "spp": 9, "light_samples": 3, "max_depth": 4, "seed": 1234},
  "ambient": 0.02,
  "materials": {
    "floor": {"kd": 0.6, "ks": 0.2, "n": 30, "ka": 1},
    "red": {"kd": [0.7, 0.1, 0.1], "ks": 0.3, "n": 80, "model": "classic"},
    "mirror": {"kd": 0.05, "kr": 0.85},
    "lamp": {"kd": 0, "ke": 8}
  },
  "shapes": [
    {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"},
    {"type": "sphere", "center": [-0.6, 0.5, 0], "radius": 0.5, "material": "mirror"},
    {"type": "box", "min": [0.2, 0, -0.3], "max": [0.9, 0.8, 0.4], "material": "red",
     "transform": {"rotate": [20, 0, 1, 0]}},
    {"type": "rectangle", "p0": [-0.5, 2.5, -0.5], "a": [1, 0, 0], "b": [0, 0, 1], "material": "lamp"}
  ],
  "lights": [
    {"type": "point", "position": [1.5, 2, 1.5], "intensity": 2},
    {"type": "sphere", "center": [-1.5, 1.5, 1], "radius": 0.15, "radiance": 20}
  ]
})");
}

ImageData renderWith(const fs::path& scene, const fs::path& out, const std::string& options) {
    std::string log;
    int code = runPenumbra(scene.string() + " -q --aovs " + options + " -o " + out.string(), &log);
    EXPECT_EQ(code, 0) << options << "\n" << log;
    return readImage(out);
}

/// Bit-for-bit equality of all channels (radiance and AOVs).
void expectIdentical(const ImageData& a, const ImageData& b, const std::string& what) {
    ASSERT_EQ(a.width, b.width) << what;
    ASSERT_EQ(a.height, b.height) << what;
    ASSERT_EQ(a.channels, b.channels) << what;
    ASSERT_EQ(a.pixels.size(), b.pixels.size()) << what;
    size_t differing = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i)
        differing += std::memcmp(&a.pixels[i], &b.pixels[i], sizeof(float)) != 0;
    EXPECT_EQ(differing, 0u) << what << ": " << differing << " of " << a.pixels.size() << " values differ";
}

/// `thorough`: also the default thread count twice, odd tiles and another seed.
void checkAcrossThreadsAndRuns(const std::string& selection, bool thorough) {
    fs::path dir = test::tempDir();
    fs::path scene = writeScene(dir);
    const std::string common = "--light-selection " + selection + " ";
    ImageData reference = renderWith(scene, dir / "t1.exr", common + "--threads 1");
    ASSERT_EQ(reference.channels, 10);  // R G B, albedo, normal, depth
    double sum = 0;
    for (int y = 0; y < reference.height; ++y)
        for (int x = 0; x < reference.width; ++x) sum += reference.at(x, y, 0);
    EXPECT_GT(sum / (reference.width * reference.height), 0.02) << "the scene is lit";

    expectIdentical(reference, renderWith(scene, dir / "t2.exr", common + "--threads 2"), "2 threads");
    if (!thorough) return;
    expectIdentical(reference, renderWith(scene, dir / "t0.exr", common), "default threads");
    expectIdentical(reference, renderWith(scene, dir / "t0b.exr", common), "default threads, second run");
    expectIdentical(reference, renderWith(scene, dir / "t3.exr", common + "--threads 3 --tile-size 7"),
                    "3 threads, 7-pixel tiles");

    // A different seed gives a different image (the comparison above is not vacuous).
    ImageData other = renderWith(scene, dir / "seed.exr", common + "--threads 2 --seed 99");
    size_t differing = 0;
    for (size_t i = 0; i < other.pixels.size(); ++i) differing += other.pixels[i] != reference.pixels[i];
    EXPECT_GT(differing, other.pixels.size() / 10);
}

}  // namespace

TEST(CliDeterminism, SameSeedSamePixelsAcrossThreadsAndRunsAllLights) { checkAcrossThreadsAndRuns("all", true); }

TEST(CliDeterminism, SameSeedSamePixelsAcrossThreadsAndRunsPowerSelection) { checkAcrossThreadsAndRuns("power", false); }

TEST(CliDeterminism, SameSeedSamePixelsAcrossThreadsAndRunsTreeSelection) { checkAcrossThreadsAndRuns("tree", false); }

TEST(CliDeterminism, ObjSceneAcrossThreadCounts) {
    fs::path dir = test::tempDir();
    const fs::path scene = test::assetPath("cornell/cornell.obj");
    const std::string opts = "--width 32 --height 32 --spp 4 --seed 5 ";
    ImageData one = renderWith(scene, dir / "a.exr", opts + "--threads 1");
    expectIdentical(one, renderWith(scene, dir / "b.exr", opts + "--threads 2"), "cornell, 2 threads");
    expectIdentical(one, renderWith(scene, dir / "c.exr", opts), "cornell, default threads");
}
