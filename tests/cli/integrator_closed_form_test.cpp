// Both integrators against closed forms, end to end through the penumbra
// command (JSON scene in, PFM out), with both accelerators:
// - the furnace-style enclosure: an emitting, reflecting box (Ke = Le,
//   Kd = a, two-sided) around a small Lambertian ball of albedo b. The ball
//   reflects b Le with `whitted` (direct light only) and b Le / (1 - a) with
//   `path` (the enclosure's radiance is Le + a Le + a^2 Le + ...);
// - a clear glass slab at normal incidence in front of an emitter: it passes
//   (1 - R)^2 / (1 - R^2) of the light behind it (all internal reflections),
//   R = ((n - 1)/(n + 1))^2, with both integrators.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

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
    return {WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), out};
}

// Mean of the image's three channels over all pixels.
double meanRadiance(const fs::path& image) {
    const ImageData img = readImage(image);
    double sum = 0.0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < 3; ++c) sum += img.at(x, y, c);
    return sum / (3.0 * img.width * img.height);
}

double renderMean(const fs::path& scene, const std::string& args) {
    const fs::path out = scene.parent_path() / ("out" + std::to_string(std::hash<std::string>{}(args)) + ".pfm");
    const RunResult r = runPenumbra(scene.string() + " -q -o " + out.string() + " " + args);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return r.exitCode == 0 ? meanRadiance(out) : -1.0;
}

constexpr float kLe = 1.f, kA = 0.5f, kB = 0.6f;

// The ball (radius 0.5) fills the whole view (its angular radius is 9.6
// degrees, the field of view 8); the enclosure, an inward-facing cube of edge
// 20 (a mesh light), sees it under a small solid angle, so the walls' radiance
// stays Le / (1 - a) to 0.05%.
fs::path furnaceScene(const fs::path& dir) {
    return test::writeFile(dir / "furnace.json", R"({
  "camera": {"eye": [0, 0, 3], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 8},
  "render": {"width": 16, "height": 16, "spp": 64, "light_samples": 1, "max_depth": 40, "seed": 7},
  "materials": {
    "walls": {"kd": )" + std::to_string(kA) + R"(, "ke": )" + std::to_string(kLe) + R"(, "two_sided": true},
    "ball": {"kd": )" + std::to_string(kB) + R"(}
  },
  "shapes": [
    {"type": "mesh", "name": "enclosure", "material": "walls",
     "vertices": [[-10,-10,-10],[10,-10,-10],[10,10,-10],[-10,10,-10],[-10,-10,10],[10,-10,10],[10,10,10],[-10,10,10]],
     "indices": [[0,1,2],[0,2,3],[5,4,7],[5,7,6],[4,0,3],[4,3,7],[1,5,6],[1,6,2],[3,2,6],[3,6,7],[4,5,1],[4,1,0]]},
    {"type": "sphere", "center": [0, 0, 0], "radius": 0.5, "material": "ball"}
  ]
})");
}

// A 0.2-thick slab of glass (n = 1.5) between the camera and an emitter of
// radiance 1 that fills the view; nothing else, background black.
fs::path slabScene(const fs::path& dir) {
    return test::writeFile(dir / "slab.json", R"({
  "camera": {"eye": [0, 0, 5], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 2},
  "render": {"width": 16, "height": 16, "spp": 16, "light_samples": 1, "max_depth": 12, "seed": 3},
  "materials": {
    "glass": {"kd": 0, "kt": 1, "ior": 1.5},
    "lamp": {"kd": 0, "ke": 1}
  },
  "shapes": [
    {"type": "box", "min": [-2, -2, -0.1], "max": [2, 2, 0.1], "material": "glass"},
    {"type": "rectangle", "p0": [-5, -5, -3], "a": [10, 0, 0], "b": [0, 10, 0], "material": "lamp"}
  ]
})");
}

class ClosedForm : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(ClosedForm, FurnaceEnclosureWhittedSeesDirectLightOnly) {
    const fs::path scene = furnaceScene(test::tempDir());
    const double L = renderMean(scene, "--integrator whitted --light-samples 4 --accel " + GetParam());
    EXPECT_NEAR(L, kB * kLe, 0.02 * kB * kLe);
}

TEST_P(ClosedForm, FurnaceEnclosurePathAddsTheInterreflections) {
    const fs::path scene = furnaceScene(test::tempDir());
    const double L = renderMean(scene, "--integrator path --accel " + GetParam());
    const double expected = kB * kLe / (1.0 - kA);  // 1.2
    EXPECT_NEAR(L, expected, 0.02 * expected);
    // Two scattering events: the ball's direct light and one bounce off the walls, b Le (1 + a).
    EXPECT_NEAR(renderMean(scene, "--integrator path --max-depth 2 --accel " + GetParam()), kB * kLe * (1 + kA),
                0.02 * kB * kLe * (1 + kA));
    // Four light samples per vertex, or lights picked by power: other MIS weights, the same value.
    EXPECT_NEAR(renderMean(scene, "--integrator path --spp 16 --light-samples 4 --accel " + GetParam()), expected,
                0.02 * expected);
    EXPECT_NEAR(renderMean(scene, "--integrator path --light-selection power --accel " + GetParam()), expected,
                0.02 * expected);
}

TEST_P(ClosedForm, GlassSlabAtNormalIncidenceWhitted) {
    const fs::path scene = slabScene(test::tempDir());
    const double n = 1.5, R = (n - 1) * (n - 1) / ((n + 1) * (n + 1));
    const double expected = (1 - R) * (1 - R) / (1 - R * R);  // 0.9231
    // Deterministic: every branch is traced; the view is within 1 degree of normal.
    EXPECT_NEAR(renderMean(scene, "--integrator whitted --accel " + GetParam()), expected, 2e-4);
    // One refraction level less: only the straight pass, (1 - R)^2.
    EXPECT_NEAR(renderMean(scene, "--integrator whitted --max-depth 2 --accel " + GetParam()), (1 - R) * (1 - R), 2e-4);
}

TEST_P(ClosedForm, GlassSlabAtNormalIncidencePath) {
    const fs::path scene = slabScene(test::tempDir());
    const double n = 1.5, R = (n - 1) * (n - 1) / ((n + 1) * (n + 1));
    const double expected = (1 - R) * (1 - R) / (1 - R * R);
    EXPECT_NEAR(renderMean(scene, "--integrator path --spp 64 --accel " + GetParam()), expected, 0.015 * expected);
}

// The same furnace with an emitting sphere (radius 10) as the enclosure, and
// the box enclosure seen on its own wall: shading points that lie on the
// light itself, where the sphere's cone and the mesh light's solid-angle
// pick degenerate (both sample by area there). Before that rule the sphere
// furnace gave 1.152 and the wall 1.519 with light samples only.
TEST_P(ClosedForm, ShadingPointsOnTheLightItselfAreLitExactly) {
    const fs::path dir = test::tempDir();
    std::ifstream in(furnaceScene(dir));
    nlohmann::json j = nlohmann::json::parse(in);
    nlohmann::json sphere = j;
    sphere["shapes"][0] = {{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 10}, {"material", "walls"}};
    const fs::path sphereScene = test::writeFile(dir / "sphere_furnace.json", sphere.dump());
    const double expected = kB * kLe / (1.0 - kA);
    EXPECT_NEAR(renderMean(sphereScene, "--integrator path --light-samples 4 --spp 16 --accel " + GetParam()), expected,
                0.015 * expected);
    // The wall at z = -10 around (5, 5), on the diagonal its two triangles share: Le + a Le, less the
    // ball's shadow (the ball of radius 0.5 at distance 11.2 hides 0.2% of the hemisphere's cosine).
    nlohmann::json wall = j;
    wall["camera"]["eye"] = {5, 5, 0};
    wall["camera"]["look_at"] = {5, 5, -10};
    const fs::path wallScene = test::writeFile(dir / "wall.json", wall.dump());
    // (Uniform-area light samples, the benchmark tools' baseline: tests/render/direct_light_test.cpp.)
    for (const char* mode : {"light", "mis"})
        EXPECT_NEAR(renderMean(wallScene, std::string("--direct-light ") + mode + " --light-samples 4 --accel " + GetParam()),
                    kLe * (1 + kA), 0.006 * kLe * (1 + kA))
            << mode;
}

TEST(IntegratorStats, StatsJsonNamesTheIntegratorRayKindsAndPathLengths) {
    const fs::path dir = test::tempDir();
    const fs::path scene = slabScene(dir);
    for (const char* integrator : {"whitted", "path"}) {
        const fs::path stats = dir / (std::string(integrator) + ".json");
        const RunResult r = runPenumbra(scene.string() + " -q --spp 4 --integrator " + integrator + " -o " +
                                        (dir / "s.pfm").string() + " --stats-json " + stats.string());
        ASSERT_EQ(r.exitCode, 0) << r.output;
        std::ifstream in(stats);
        const nlohmann::json j = nlohmann::json::parse(in);
        EXPECT_EQ(j.at("integrator"), integrator);
        const nlohmann::json& rays = j.at("rays");
        EXPECT_GT(rays.at("transmission").get<uint64_t>(), 0u) << integrator;
        EXPECT_EQ(rays.at("total").get<uint64_t>(),
                  rays.at("camera").get<uint64_t>() + rays.at("shadow").get<uint64_t>() +
                      rays.at("reflection").get<uint64_t>() + rays.at("transmission").get<uint64_t>() +
                      rays.at("indirect").get<uint64_t>());
        // Camera ray, into the slab, out of it, (internal reflections,) to the lamp: at least 3 rays.
        EXPECT_GE(j.at("path_length").at("mean").get<double>(), 2.9) << integrator;
        EXPECT_GE(j.at("path_length").at("max").get<uint32_t>(), 3u) << integrator;
        EXPECT_LE(j.at("path_length").at("max").get<uint32_t>(), 13u) << integrator;  // max_depth 12 + 1
    }
}

INSTANTIATE_TEST_SUITE_P(BothAccelerators, ClosedForm, ::testing::Values(std::string("naive"), std::string("embree")),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });
