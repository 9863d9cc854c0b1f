// The environment light end to end through the penumbra command: closed forms
// (a Lambertian floor under a uniform environment reflects kd * L_env; a mirror
// and the sky show L_env), the image mapping's up direction, bad files and
// values, and the default light of scenes that have none.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <iterator>

#include "core/film.h"
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

// A Lambertian floor (kd 0.5, or a mirror) seen from straight above, nothing else.
fs::path floorScene(const fs::path& dir, const std::string& floorMaterial, const std::string& extra = "") {
    return test::writeFile(dir / "floor.json", R"({
  "camera": {"eye": [0, 2, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 40},
  "render": {"width": 16, "height": 16, "spp": 16, "light_samples": 16, "seed": 5},
  "materials": {"floor": )" + floorMaterial + R"(},
  "shapes": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "floor"}])" +
                                                  extra + "\n}\n");
}

// Mean of channel c over the image.
double meanOf(const ImageData& img, int c) {
    double s = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) s += img.at(x, y, c);
    return s / (img.width * img.height);
}

// A lat-long EXR: rows above the horizon `sky`, below it `ground`.
fs::path writeSkyImage(const fs::path& path, Rgb sky, Rgb ground) {
    const int w = 32, h = 16;
    Film film(w, h, false);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) film.addRadiance(film.index(x, y), y < h / 2 ? sky : ground);
    film.setSampleCount(1);
    writeImage(path, film, ImageWriteOptions{});
    return path;
}

std::string readText(const fs::path& p) {
    std::ifstream f(p);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

}  // namespace

TEST(Environment, LambertianFloorUnderAUniformEnvironmentReflectsKdTimesL) {
    const fs::path dir = test::tempDir();
    const fs::path scene = floorScene(dir, R"({"kd": 0.5})");
    const fs::path out = dir / "floor.exr";
    // Direct light only (whitted): the upper hemisphere lights the floor, the
    // lower one is cut off by the floor's own plane: E = pi L, Lo = kd/pi * E.
    const RunResult r = runPenumbra(scene.string() + " -q --env 1,0.5,2 -o " + out.string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output.find("no light"), std::string::npos) << r.output;
    const ImageData img = readImage(out);
    EXPECT_NEAR(meanOf(img, 0), 0.5 * 1.0, 0.01 * 0.5);
    EXPECT_NEAR(meanOf(img, 1), 0.5 * 0.5, 0.01 * 0.25);
    EXPECT_NEAR(meanOf(img, 2), 0.5 * 2.0, 0.01 * 1.0);
    // Every pixel, to the noise of 256 uniform light samples.
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) EXPECT_NEAR(img.at(x, y, 0), 0.5f, 0.15f) << x << "," << y;
}

// The path integrator sees the environment through next-event estimation and
// through BRDF-sampled rays that escape, weighed by MIS: alone under the sky,
// the floor has nothing to interreflect with, so it is kd * L_env again, with
// every light selection and sample count; an image environment renders
// identically for any thread count and tile size.
TEST(Environment, PathIntegratorLitFloorIsKdTimesTheEnvironment) {
    const fs::path dir = test::tempDir();
    const fs::path scene = floorScene(dir, R"({"kd": 0.5})");
    const fs::path out = dir / "floor.pfm";
    for (const char* args : {"", " --light-samples 1 --spp 64", " --light-selection power"}) {
        const RunResult r = runPenumbra(scene.string() + " -q --integrator path --env 1,0.5,2 -o " + out.string() + args);
        ASSERT_EQ(r.exitCode, 0) << r.output;
        const ImageData img = readImage(out);
        EXPECT_NEAR(meanOf(img, 0), 0.5 * 1.0, 0.01 * 0.5) << args;
        EXPECT_NEAR(meanOf(img, 1), 0.5 * 0.5, 0.01 * 0.25) << args;
        EXPECT_NEAR(meanOf(img, 2), 0.5 * 2.0, 0.01 * 1.0) << args;
    }
    const fs::path sky = writeSkyImage(dir / "sky.exr", Rgb{3.f, 2.f, 1.f}, Rgb(10.f));
    const std::string common = scene.string() + " -q --integrator path --env " + sky.string() + " --env-rotate 30";
    ASSERT_EQ(runPenumbra(common + " --threads 1 -o " + (dir / "a.exr").string()).exitCode, 0);
    ASSERT_EQ(runPenumbra(common + " --threads 2 --tile-size 5 -o " + (dir / "b.exr").string()).exitCode, 0);
    const ImageData a = readImage(dir / "a.exr"), b = readImage(dir / "b.exr");
    EXPECT_NEAR(meanOf(a, 0), 0.5 * 3.0, 0.03 * 1.5);  // the upper half only, as with whitted
    ASSERT_EQ(a.pixels.size(), b.pixels.size());
    EXPECT_TRUE(a.pixels == b.pixels);
}

TEST(Environment, JsonColourWithScaleAndAMirrorThatSeesIt) {
    const fs::path dir = test::tempDir();
    const fs::path out = dir / "img.exr";
    fs::path scene = floorScene(dir, R"({"kd": 0.5})", R"(,
  "environment": {"color": [0.2, 0.4, 0.6], "scale": 2})");
    RunResult r = runPenumbra(scene.string() + " -q -o " + out.string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    ImageData img = readImage(out);
    EXPECT_NEAR(meanOf(img, 0), 0.5 * 0.4, 0.01 * 0.2);
    EXPECT_NEAR(meanOf(img, 2), 0.5 * 1.2, 0.01 * 0.6);
    // A perfect mirror floor: every camera ray reflects up and escapes, seeing L_env * kr.
    scene = floorScene(dir, R"({"kd": 0, "kr": 0.5})", R"(,
  "environment": {"color": [0.2, 0.4, 0.6], "scale": 2})");
    r = runPenumbra(scene.string() + " -q -o " + out.string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    img = readImage(out);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            EXPECT_FLOAT_EQ(img.at(x, y, 0), 0.5f * 0.4f);
            EXPECT_FLOAT_EQ(img.at(x, y, 2), 0.5f * 1.2f);
        }
}

TEST(Environment, ImageTopIsUpAndLightsTheFloorFromAbove) {
    const fs::path dir = test::tempDir();
    const fs::path sky = writeSkyImage(dir / "sky.exr", Rgb{3.f, 2.f, 1.f}, Rgb(10.f));
    const fs::path scene = floorScene(dir, R"({"kd": 0.5})");
    const fs::path out = dir / "img.exr";
    // Only the upper half (the image's top rows) reaches the floor: kd * sky, not the bright ground.
    RunResult r = runPenumbra(scene.string() + " -q --env " + sky.string() + " --env-rotate 30 -o " + out.string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    ImageData img = readImage(out);
    EXPECT_NEAR(meanOf(img, 0), 0.5 * 3.0, 0.03 * 1.5);
    EXPECT_NEAR(meanOf(img, 2), 0.5 * 1.0, 0.03 * 0.5);
    // Looking up, the camera sees the sky itself (JSON image, relative to the scene file).
    const fs::path up = test::writeFile(dir / "up.json", R"({
  "camera": {"eye": [0, 0, 0], "look_at": [0, 1, 0], "up": [0, 0, -1], "fov": 60},
  "render": {"width": 8, "height": 8, "spp": 1},
  "environment": {"image": "sky.exr", "rotate": 10, "scale": 0.5}
})");
    r = runPenumbra(up.string() + " -q -o " + out.string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    img = readImage(out);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) EXPECT_FLOAT_EQ(img.at(x, y, 1), 1.f);
}

TEST(Environment, UnreadableImagesAreErrorsNamingTheFile) {
    const fs::path dir = test::tempDir();
    const fs::path scene = floorScene(dir, R"({"kd": 0.5})");
    const fs::path out = dir / "img.exr";
    RunResult r = runPenumbra(scene.string() + " -q --env " + (dir / "missing.exr").string() + " -o " + out.string());
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("missing.exr"), std::string::npos) << r.output;
    const fs::path bad = test::writeFile(dir / "bad.exr", "this is not an EXR file");
    r = runPenumbra(scene.string() + " -q --env " + bad.string() + " -o " + out.string());
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("bad.exr: cannot read image"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
    // The budget is checked against the header, before any pixel is decoded.
    const fs::path huge = test::writeFile(dir / "huge.pfm", "PF\n100000 100000\n-1.0\n0000000000000000");
    r = runPenumbra(scene.string() + " -q --env " + huge.string() + " -o " + out.string());
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("huge.pfm: cannot read image (its header says 100000x100000 pixels, more than the 1024 MiB"),
              std::string::npos)
        << r.output;
    const fs::path json = test::writeFile(dir / "env.json", R"({"environment": {"image": "nowhere.hdr"}})");
    r = runPenumbra(json.string() + " -q -o " + out.string());
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("nowhere.hdr"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("/environment/image"), std::string::npos) << r.output;
}

// A file name is a legal --env value even with commas in it: an existing file
// wins over the colour reading, and a value with a '/' is always a file.
TEST(Environment, FileNamesWithCommasAreFiles) {
    const fs::path dir = test::tempDir();
    floorScene(dir, R"({"kd": 0.5})");
    writeSkyImage(dir / "sky,v2.exr", Rgb(1.f, 0.5f, 2.f), Rgb(1.f, 0.5f, 2.f));
    const std::string inDir = "cd '" + dir.string() + "' && " + (test::binaryDir() / "penumbra").string();
    auto run = [&](const std::string& args) {
        const std::string cmd = inDir + " floor.json -q " + args + " 2>&1";
        FILE* p = ::popen(cmd.c_str(), "r");
        std::string out;
        std::array<char, 4096> buf{};
        for (size_t n; p && (n = std::fread(buf.data(), 1, buf.size(), p)) > 0;) out.append(buf.data(), n);
        const int status = p ? ::pclose(p) : -1;
        return RunResult{WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
    };
    RunResult r = run("--env sky,v2.exr -o bare.exr");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = run("--env ./sky,v2.exr -o dotted.exr");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = run("--env 1,0.5,2 -o colour.exr");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    // A uniform image of the colour lights the floor as the colour does.
    const ImageData colour = readImage(dir / "colour.exr");
    for (const char* name : {"bare.exr", "dotted.exr"}) {
        const ImageData img = readImage(dir / name);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(meanOf(img, c), meanOf(colour, c), 0.03 * meanOf(colour, c)) << name;
    }
    // No such file: with a '/', the file's own error (exit 1); without one, not a colour either (exit 2).
    r = run("--env ./nowhere,1.exr -o x.exr");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("nowhere,1.exr: file not found"), std::string::npos) << r.output;
    r = run("--env nowhere,1.exr -o x.exr");
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("--env: expected r,g,b"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("(no such file)"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "x.exr"));
}

// Whatever keeps an --env file from being read, it is a file error: exit code
// 1, one line naming the file, before the scene is loaded.
TEST(Environment, MissingFoldersAndFifosAreAllFileErrors) {
    const fs::path dir = test::tempDir();
    const fs::path scene = floorScene(dir, R"({"kd": 0.5})");
    const fs::path out = dir / "img.exr";
    fs::create_directories(dir / "folder.exr");
    ASSERT_EQ(::mkfifo((dir / "fifo.exr").c_str(), 0600), 0);
    const std::pair<const char*, const char*> cases[] = {
        {"missing.exr", "missing.exr: file not found"},
        {"folder.exr", "folder.exr: is not a regular file (it is a directory)"},
        {"fifo.exr", "fifo.exr: is not a regular file (it is a FIFO)"},
    };
    for (const auto& [name, message] : cases) {
        const RunResult r = runPenumbra(scene.string() + " -q --env " + (dir / name).string() + " -o " + out.string());
        EXPECT_EQ(r.exitCode, 1) << name << ": " << r.output;
        EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
        EXPECT_EQ(r.output.find("see --help"), std::string::npos) << r.output;
    }
    EXPECT_FALSE(fs::exists(out));
}

TEST(Environment, BadEnvValuesAreUsageErrors) {
    const fs::path dir = test::tempDir();
    const fs::path scene = floorScene(dir, R"({"kd": 0.5})");
    const std::string out = " -o " + (dir / "img.exr").string();
    for (const char* bad : {"--env 1,2", "--env 1,x,3", "--env -1,0,0", "--env 1,nan,1", "--env 1e39,1,1", "--env sky.txt", "--env ''",
                            "--env-rotate 30", "--env 1,1,1 --env-rotate 30", "--env sky.exr --env-rotate x"}) {
        const RunResult r = runPenumbra(scene.string() + " -q " + bad + out);
        EXPECT_EQ(r.exitCode, 2) << bad << ": " << r.output;
        EXPECT_NE(r.output.find("--env"), std::string::npos) << bad << ": " << r.output;
    }
}

TEST(Environment, AnUnlitSceneGetsTheDefaultLightAndOneWarning) {
    const fs::path dir = test::tempDir();
    const fs::path scene = floorScene(dir, R"({"kd": 0.5})");
    const fs::path out = dir / "img.exr";
    RunResult r = runPenumbra(scene.string() + " -q --stats-json " + (dir / "stats.json").string() + " -o " +
                              out.string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(readText(dir / "stats.json").find("\"default_light\": true"), std::string::npos);
    const std::string warning = "the scene has no light";
    const size_t at = r.output.find(warning);
    ASSERT_NE(at, std::string::npos) << r.output;
    EXPECT_EQ(r.output.find(warning, at + 1), std::string::npos) << "one warning: " << r.output;
    EXPECT_NE(r.output.find("uniform white environment of radiance 1"), std::string::npos) << r.output;
    // A white environment of radiance 1 under kd 0.5: 0.5, not black.
    const ImageData img = readImage(out);
    EXPECT_NEAR(meanOf(img, 1), 0.5, 0.005);
    // --env overrides it: no warning.
    r = runPenumbra(scene.string() + " -q --env 0.25,0.25,0.25 -o " + out.string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output.find(warning), std::string::npos) << r.output;
    EXPECT_NEAR(meanOf(readImage(out), 1), 0.125, 0.002);
}
