// Model formats and the command line's conventions, end to end (issue 17):
// the Stanford bunny PLY from the command line and from JSON, a glTF file
// written here rendering with its materials, an STL, unknown formats, usage
// errors (exit code 2), the last of a repeated option, --model classic.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "core/image_io.h"
#include "support/test_support.h"

using namespace penumbra;
namespace fs = std::filesystem;

namespace {

struct RunResult {
    int exitCode;
    std::string output;  // stdout + stderr
};

std::string quote(const fs::path& p) {
    std::string q = "'";
    for (char c : p.string()) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

RunResult runPenumbra(const std::string& args) {
    const std::string cmd = quote(test::binaryDir() / "penumbra") + " " + args + " 2>&1";
    FILE* p = ::popen(cmd.c_str(), "r");
    if (!p) return {-1, "popen failed"};
    std::string out;
    std::array<char, 4096> buf{};
    size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
    const int status = ::pclose(p);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), out};
}

std::vector<std::string> errorLines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("penumbra: error: ", 0) == 0) out.push_back(line);
    return out;
}

nlohmann::json readJson(const fs::path& p) {
    std::ifstream f(p);
    return nlohmann::json::parse(f);
}

/// Expects exit code `code` and exactly one error line holding every needle.
void expectError(const RunResult& r, int code, std::initializer_list<std::string> needles) {
    EXPECT_EQ(r.exitCode, code) << r.output;
    const auto lines = errorLines(r.output);
    ASSERT_EQ(lines.size(), 1u) << r.output;
    for (const auto& n : needles) EXPECT_NE(lines[0].find(n), std::string::npos) << "missing '" << n << "' in " << lines[0];
}

void expectColour(const ImageData& img, int x, int y, float r, float g, float b, float tolerance) {
    SCOPED_TRACE("pixel " + std::to_string(x) + "," + std::to_string(y));
    EXPECT_NEAR(img.at(x, y, 0), r, tolerance * r);
    EXPECT_NEAR(img.at(x, y, 1), g, tolerance * g);
    EXPECT_NEAR(img.at(x, y, 2), b, tolerance * b);
}

// ------------------------------------------------------------------ the Stanford bunny

TEST(Formats, StanfordBunnyPlyFromTheCommandLineAndFromJson) {
    const fs::path ply = test::sharedScenePath("bunny_stanford/bun_zipper.ply");
    if (ply.empty()) GTEST_SKIP() << "../shared/scenes not present";
    const fs::path dir = test::tempDir();
    RunResult r = runPenumbra(quote(ply) + " -q --width 16 --height 16 --spp 1 --stats-json " + quote(dir / "cli.json") +
                              " -o " + quote(dir / "cli.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(readJson(dir / "cli.json")["triangles"].get<int>(), 69451);

    // From JSON, lit by a point light in front: the bunny fills the middle of the frame.
    test::writeFile(dir / "bunny.json", R"({
      "camera": {"eye": [-0.017, 0.11, 0.5], "look_at": [-0.017, 0.11, 0], "up": [0, 1, 0], "fov": 30},
      "shapes": [{"type": "mesh", "file": ")" + ply.string() + R"("}],
      "lights": [{"type": "point", "position": [0, 0.3, 0.5], "intensity": 0.5}]
    })");
    r = runPenumbra(quote(dir / "bunny.json") + " -q --width 16 --height 16 --spp 1 --stats-json " +
                    quote(dir / "json.json") + " -o " + quote(dir / "json.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(readJson(dir / "json.json")["triangles"].get<int>(), 69451);
    const ImageData img = readImage(dir / "json.exr");
    EXPECT_GT(img.at(8, 8, 0), 0.05f) << "the lit bunny";
    EXPECT_EQ(img.at(0, 0, 0), 0.f) << "the black background";
}

// ------------------------------------------------------------------ glTF and STL written here

// tests/support: a quad emitting (1, 0.5, 0.25) centred at x = -1.25 and a
// dielectric metal-roughness one (base colour 0.8, 0.4, 0.2, roughness 1) at
// x = +1.25, a point light of intensity 4 at (1.25, 0, 2), the camera at
// (0, 0, 5) with a 0.8 rad fov. At 64 x 64, pixel (13, 32) sees the emitter,
// (51, 32) the other quad near its centre: x = 1.287, y = -0.033, where the
// light arrives with E = 4 / 4.0025 * 0.9997 along n.wi = 0.9997, seen along
// n.wo = 0.9684 (wo.h = 0.9931). The BSDF (docs/rendering.md): the base
// 0.96 base / pi (both Fresnel weights T are 0.96 this near the normal) plus
// GGX at alpha 1, F D G2 / (4 n.wo n.wi) = 0.04 (1/pi) 0.9838 / 3.8724.
TEST(Formats, GltfRendersWithItsMaterialsAndCamera) {
    const fs::path dir = test::tempDir();
    const fs::path gltf = test::writeFile(dir / "quads.gltf", test::twoQuadsGltf());
    const std::string common = " -q --width 64 --height 64 --spp 4 --stats-json " + quote(dir / "s.json");
    RunResult r = runPenumbra(quote(gltf) + common + " -o " + quote(dir / "normalized.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(readJson(dir / "s.json")["triangles"].get<int>(), 4);
    EXPECT_EQ(readJson(dir / "s.json")["lights"].get<int>(), 2) << "the point light and the emitting quad";
    const ImageData n = readImage(dir / "normalized.exr");

    const float e = 4.f / 4.0025f * 0.9997f;
    const float base[3] = {0.96f * 0.8f, 0.96f * 0.4f, 0.96f * 0.2f};
    const float spec = 0.04f / 3.14159265f * 0.9838f / 3.8724f;
    expectColour(n, 51, 32, (base[0] / 3.14159265f + spec) * e, (base[1] / 3.14159265f + spec) * e,
                 (base[2] / 3.14159265f + spec) * e, 0.01f);
    expectColour(n, 13, 32, 1.f, 0.5f, 0.25f, 0.03f);
    EXPECT_EQ(n.at(32, 32, 0), 0.f) << "the gap between the quads";
    EXPECT_EQ(n.at(32, 2, 0), 0.f) << "above them";

    // --model sets the Phong model; a metal-roughness material is not Phong and keeps its image.
    r = runPenumbra(quote(gltf) + common + " --model classic -o " + quote(dir / "classic.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const ImageData c = readImage(dir / "classic.exr");
    for (int ch = 0; ch < 3; ++ch) EXPECT_EQ(c.at(51, 32, ch), n.at(51, 32, ch));

    // The same model from JSON: the file's camera and light come along.
    test::writeFile(dir / "quads.json", R"({"shapes": [{"type": "mesh", "file": "quads.gltf", "model": "classic"}]})");
    r = runPenumbra(quote(dir / "quads.json") + common + " -o " + quote(dir / "json.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const ImageData j = readImage(dir / "json.exr");
    for (int ch = 0; ch < 3; ++ch) EXPECT_EQ(j.at(51, 32, ch), n.at(51, 32, ch));
}

TEST(Formats, StlWrittenHereRenders) {
    const fs::path dir = test::tempDir();
    std::string stl = "solid quad\n";
    const char* tris[2][3] = {{"-1 -1 0", "1 -1 0", "1 1 0"}, {"-1 -1 0", "1 1 0", "-1 1 0"}};
    for (const auto& t : tris) {
        stl += "facet normal 0 0 1\n outer loop\n";
        for (const char* v : t) stl += "  vertex " + std::string(v) + "\n";
        stl += " endloop\nendfacet\n";
    }
    stl += "endsolid quad\n";
    test::writeFile(dir / "quad.stl", stl);
    test::writeFile(dir / "lit.json", R"({
      "camera": {"eye": [0, 0, 3], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 40},
      "shapes": [{"type": "mesh", "file": "quad.stl"}],
      "lights": [{"type": "point", "position": [0, 0, 2], "intensity": 4}]
    })");
    RunResult r = runPenumbra(quote(dir / "lit.json") + " -q --width 8 --height 8 --spp 1 --stats-json " +
                              quote(dir / "s.json") + " -o " + quote(dir / "stl.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(readJson(dir / "s.json")["triangles"].get<int>(), 2);
    const ImageData img = readImage(dir / "stl.exr");
    EXPECT_GT(img.at(4, 4, 0), 0.05f);
    EXPECT_EQ(img.at(4, 4, 0), img.at(4, 4, 1)) << "a grey default material";
    // On its own, from the command line.
    r = runPenumbra(quote(dir / "quad.stl") + " -q --width 8 --height 8 --spp 1 -o " + quote(dir / "alone.exr"));
    EXPECT_EQ(r.exitCode, 0) << r.output;
}

// A sphere-like OBJ without normals: smooth (the default 30 degrees) shading
// varies continuously across a facet; --smooth-angle 0 shades each facet flat.
TEST(Formats, SmoothAngleSmoothsAFacetedSphereAndZeroKeepsItFaceted) {
    const fs::path dir = test::tempDir();
    std::string obj;
    const int rings = 8, segments = 16;
    auto index = [&](int i, int j) { return 2 + (i - 1) * segments + (j % segments); };
    obj += "v 0 1 0\nv 0 -1 0\n";
    for (int i = 1; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const double theta = M_PI * i / rings, phi = 2 * M_PI * j / segments;
            obj += "v " + std::to_string(std::sin(theta) * std::cos(phi)) + " " + std::to_string(std::cos(theta)) + " " +
                   std::to_string(-std::sin(theta) * std::sin(phi)) + "\n";
        }
    for (int j = 0; j < segments; ++j) {
        obj += "f 1 " + std::to_string(index(1, j)) + " " + std::to_string(index(1, j + 1)) + "\n";
        obj += "f 2 " + std::to_string(index(rings - 1, j + 1)) + " " + std::to_string(index(rings - 1, j)) + "\n";
        for (int i = 1; i + 1 < rings; ++i)
            obj += "f " + std::to_string(index(i, j)) + " " + std::to_string(index(i + 1, j)) + " " +
                   std::to_string(index(i + 1, j + 1)) + " " + std::to_string(index(i, j + 1)) + "\n";
    }
    test::writeFile(dir / "ball.obj", obj);
    test::writeFile(dir / "ball.json", R"({
      "camera": {"eye": [0, 0, 4], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 35},
      "shapes": [{"type": "mesh", "file": "ball.obj"}],
      "lights": [{"type": "directional", "direction": [0, 0, -1], "irradiance": 3}]
    })");
    const std::string common = " -q --width 48 --height 48 --spp 1 -o ";
    ASSERT_EQ(runPenumbra(quote(dir / "ball.json") + common + quote(dir / "smooth.exr")).exitCode, 0);
    ASSERT_EQ(runPenumbra(quote(dir / "ball.json") + " --smooth-angle 0" + common + quote(dir / "flat.exr")).exitCode, 0);
    const ImageData smooth = readImage(dir / "smooth.exr"), flat = readImage(dir / "flat.exr");
    // Along the middle row: count the distinct values (a flat facet repeats its value
    // across its pixels; smooth normals change from pixel to pixel).
    auto distinct = [](const ImageData& img) {
        std::vector<float> v;
        for (int x = 0; x < img.width; ++x)
            if (img.at(x, 24, 0) > 0.f) v.push_back(img.at(x, 24, 0));
        std::sort(v.begin(), v.end());
        return size_t(std::unique(v.begin(), v.end()) - v.begin());
    };
    EXPECT_LE(distinct(flat), 10u) << "at most one value per facet crossed";
    EXPECT_GE(distinct(smooth), 20u);
    // The centre faces the light either way.
    EXPECT_NEAR(smooth.at(24, 24, 0), flat.at(24, 24, 0), 0.05f * flat.at(24, 24, 0));
}

// ------------------------------------------------------------------ errors

TEST(Formats, UnknownOrBrokenFormatsAreErrorsNamingTheFile) {
    const fs::path dir = test::tempDir();
    test::writeFile(dir / "scene.xyz", "v 0 0 0\n");
    expectError(runPenumbra(quote(dir / "scene.xyz") + " -o " + quote(dir / "x.exr")), 1,
                {"scene.xyz", "unknown scene format '.xyz'", ".json", ".obj", ".ply", ".gltf", ".stl"});
    // Inside JSON alike (a .ply used to be read as OBJ, and an empty scene rendered).
    test::writeFile(dir / "mesh.json", R"({"shapes": [{"type": "mesh", "file": "scene.xyz"}]})");
    expectError(runPenumbra(quote(dir / "mesh.json") + " -o " + quote(dir / "x.exr")), 1,
                {"mesh.json", "/shapes/0/file", "scene.xyz", "unknown mesh format '.xyz'", ".ply"});
    test::writeFile(dir / "broken.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n");
    test::writeFile(dir / "broken.json", R"({"shapes": [{"type": "mesh", "file": "broken.ply"}]})");
    expectError(runPenumbra(quote(dir / "broken.ply") + " -o " + quote(dir / "x.exr")), 1, {"broken.ply"});
    expectError(runPenumbra(quote(dir / "broken.json") + " -o " + quote(dir / "x.exr")), 1, {"broken.json", "broken.ply"});
    // Nothing to render.
    test::writeFile(dir / "empty.json", "{}");
    expectError(runPenumbra(quote(dir / "empty.json") + " -o " + quote(dir / "x.exr")), 1, {"empty.json", "nothing to render"});
    EXPECT_FALSE(fs::exists(dir / "x.exr"));
}

TEST(Formats, UsageErrorsAndBadOptionValuesExitWithTwo) {
    const fs::path dir = test::tempDir();
    const fs::path gltf = test::writeFile(dir / "quads.gltf", test::twoQuadsGltf());
    const std::string scene = quote(gltf) + " -q --spp 1 --width 8 --height 8 ";
    const std::string out = " -o " + quote(dir / "x.exr");
    struct Case {
        std::string args;
        std::string needle;
    };
    const Case cases[] = {
        {"--model phong" + out, "--model: expected classic or normalized, got 'phong'"},
        {"--smooth-angle 200" + out, "--smooth-angle: must lie in [0, 180]"},
        {"--smooth-angle abc" + out, "--smooth-angle"},
        {"--width 0" + out, "width must be in [1, 65536], got 0"},
        {"--width abc" + out, "--width"},
        {"--fov 180" + out, "fov must lie in (0, 180)"},
        {"--accel kdtree" + out, "--accel"},
        {"--ambient -1,0,0" + out, "--ambient"},
        {"--crop 0,0,99,99" + out, "crop"},
        {"--frobnicate" + out, "--frobnicate"},
        {"", "--output"},
        {"-o " + quote(dir / "x.bmp"), "unknown image format '.bmp'"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.args);
        const RunResult r = runPenumbra(scene + c.args);
        expectError(r, 2, {c.needle, "(see --help)"});
    }
    EXPECT_FALSE(fs::exists(dir / "x.exr"));
}

TEST(Formats, TheLastOfARepeatedOptionWins) {
    const fs::path dir = test::tempDir();
    const fs::path gltf = test::writeFile(dir / "quads.gltf", test::twoQuadsGltf());
    RunResult r = runPenumbra(quote(gltf) + " -q -q --spp 1 --width 10 --height 8 --width 20 --height 12 --model classic "
                                            "--model normalized -o " + quote(dir / "first.exr") + " -o " + quote(dir / "last.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_FALSE(fs::exists(dir / "first.exr"));
    const ImageData img = readImage(dir / "last.exr");
    EXPECT_EQ(img.width, 20);
    EXPECT_EQ(img.height, 12);
}

}  // namespace
