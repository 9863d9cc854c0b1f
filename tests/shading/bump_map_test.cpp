// Height-map bump shading (SurfaceShading through TextureCache::sampleHeightNormal,
// docs/mtl-mapping.md): an OBJ plane whose MTL gives `bump -bm s` a ramp
// written here tilts the shading normal by the ramp's slope per texel times s,
// against the rise, along the tangent frame; a constant height, or -bm 0,
// leaves the normal as it was; the reversed ramp tilts the other way; seen
// from behind, the normal is the same one turned to the viewer; JSON's
// rectangle, sphere and box tilt along their own uv directions; on Sponza
// (../shared, skipped when absent) the floor's joints tilt and its stones stay level.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "accel/accelerator.h"
#include "core/io/scene_loader.h"
#include "core/texture_cache.h"
#include "shading/surface_shading.h"
#include "support/test_support.h"
#include "support/warning_log.h"

namespace penumbra {
namespace {
namespace fs = std::filesystem;

constexpr int kSize = 64;
constexpr float kStep = 1000.f / 65535.f;  // the ramps' rise per texel (16-bit codes)

/// A kSize x kSize 16-bit grey PNG whose texel in column x, row y (top first) holds code(x, y).
fs::path writeHeights(const fs::path& path, const std::function<int(int x, int y)>& code) {
    std::vector<uint16_t> px;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) px.push_back(uint16_t(code(x, y)));
    auto out = OIIO::ImageOutput::create(path.string());
    const OIIO::ImageSpec spec(kSize, kSize, 1, OIIO::TypeDesc::UINT16);
    if (!out || !out->open(path.string(), spec) || !out->write_image(OIIO::TypeDesc::UINT16, px.data())) return {};
    out->close();
    return path;
}

struct Shaded {
    Vec3f ns;  // the shading normal, turned to the viewer
    Vec3f ng;
};

/// Shades the point (0.6, 0.3, 0) of the unit quad in z = 0 (uv = xy, facing
/// +z) with material `mtl` (bump maps reading height.png), seen from +z or from -z.
Shaded shadeQuad(const fs::path& dir, const std::string& mtl, bool fromBehind = false) {
    test::writeFile(dir / "m.mtl", "newmtl m\nKd 0.5 0.5 0.5\n" + mtl + "\n");
    const fs::path obj = test::writeFile(dir / "m.obj",
                                         "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                         "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nusemtl m\nf 1/1/1 2/2/1 3/3/1 4/4/1\n");
    test::WarningLog log;
    const LoadedScene s = loadScene(obj, {}, log.logger);
    EXPECT_TRUE(log.warnings.empty()) << log.warnings.front();
    const TextureCache cache(s.scene.textures, log.logger);
    EXPECT_TRUE(log.warnings.empty()) << log.warnings.front();
    const SurfaceShading shading(s.scene, &cache, 0.f);
    const Ray ray{Vec3f{0.6f, 0.3f, fromBehind ? -1.f : 1.f}, Vec3f{0.f, 0.f, fromBehind ? 1.f : -1.f}};
    const std::optional<Hit> hit = makeNaiveAccelerator(s.scene)->intersect(ray);
    EXPECT_TRUE(hit.has_value());
    if (!hit) return {};
    ShadingPoint sp;
    shading.shade(*hit, ray, hit->t, sp);
    return {sp.ns, sp.ng};
}

void expectNear(const Vec3f& got, const Vec3f& want, float eps = 2e-5f) {
    EXPECT_NEAR(got.x, want.x, eps) << "got (" << got.x << ", " << got.y << ", " << got.z << ")";
    EXPECT_NEAR(got.y, want.y, eps) << "got (" << got.x << ", " << got.y << ", " << got.z << ")";
    EXPECT_NEAR(got.z, want.z, eps) << "got (" << got.x << ", " << got.y << ", " << got.z << ")";
}

TEST(BumpMaps, ARampAlongUTiltsTheNormalAgainstTheRise) {
    const fs::path dir = test::tempDir();
    ASSERT_FALSE(writeHeights(dir / "height.png", [](int x, int) { return 1000 * x; }).empty());
    // Height rises by kStep per texel along +u (+x here): the surface's slope
    // is 20 kStep, so its normal is (-20 kStep, 0, 1), normalised.
    const Shaded s = shadeQuad(dir, "bump -bm 20 height.png");
    expectNear(s.ns, normalize(Vec3f{-20.f * kStep, 0.f, 1.f}));
    expectNear(s.ng, Vec3f{0.f, 0.f, 1.f}, 0.f);
    // The same map reversed: the same tilt the other way.
    ASSERT_FALSE(writeHeights(dir / "height.png", [](int x, int) { return 1000 * (kSize - 1 - x); }).empty());
    expectNear(shadeQuad(dir, "bump -bm 20 height.png").ns, normalize(Vec3f{20.f * kStep, 0.f, 1.f}));
    // A negative -bm reads the heights as depths.
    expectNear(shadeQuad(dir, "bump -bm -20 height.png").ns, normalize(Vec3f{-20.f * kStep, 0.f, 1.f}));
}

TEST(BumpMaps, ARampUpTheImageTiltsAlongTheBitangent) {
    const fs::path dir = test::tempDir();
    // Row 0 is the top of the image, v = 1: heights rising up the image rise with v (+y here).
    ASSERT_FALSE(writeHeights(dir / "height.png", [](int, int y) { return 1000 * (kSize - 1 - y); }).empty());
    expectNear(shadeQuad(dir, "map_Bump -bm 8 height.png").ns, normalize(Vec3f{0.f, -8.f * kStep, 1.f}));
}

TEST(BumpMaps, AConstantHeightOrAZeroScaleLeavesTheNormal) {
    const fs::path dir = test::tempDir();
    ASSERT_FALSE(writeHeights(dir / "height.png", [](int, int) { return 30000; }).empty());
    expectNear(shadeQuad(dir, "bump -bm 50 height.png").ns, Vec3f{0.f, 0.f, 1.f}, 1e-6f);
    ASSERT_FALSE(writeHeights(dir / "height.png", [](int x, int y) { return 900 * x + 100 * y; }).empty());
    expectNear(shadeQuad(dir, "bump -bm 0 height.png").ns, Vec3f{0.f, 0.f, 1.f}, 1e-6f);
}

TEST(BumpMaps, SeenFromBehindTheBumpedNormalTurnsToTheViewer) {
    const fs::path dir = test::tempDir();
    ASSERT_FALSE(writeHeights(dir / "height.png", [](int x, int) { return 1000 * x; }).empty());
    const Shaded s = shadeQuad(dir, "bump -bm 20 height.png", true);
    expectNear(s.ns, -normalize(Vec3f{-20.f * kStep, 0.f, 1.f}));
    expectNear(s.ng, Vec3f{0.f, 0.f, -1.f}, 0.f);
}

/// The shading normal where a ray from `eye` along `dir` meets the JSON scene of `shape` with a bump-mapped material.
Vec3f shadeJsonShape(const fs::path& dir, const std::string& shape, const Vec3f& eye, const Vec3f& d) {
    const fs::path json = test::writeFile(
        dir / "s.json", R"({"materials": {"m": {"kd": 0.5, "bump_texture": "height.png", "normal_scale": 20}},
                            "shapes": [)" + shape + "]}");
    test::WarningLog log;
    const LoadedScene s = loadScene(json, {}, log.logger);
    const TextureCache cache(s.scene.textures, log.logger);
    EXPECT_TRUE(log.warnings.empty()) << log.warnings.front();
    const Ray ray{eye, d};
    const std::optional<Hit> hit = makeNaiveAccelerator(s.scene)->intersect(ray);
    EXPECT_TRUE(hit.has_value());
    if (!hit) return {};
    ShadingPoint sp;
    SurfaceShading(s.scene, &cache, 0.f).shade(*hit, ray, hit->t, sp);
    return sp.ns;
}

TEST(BumpMaps, AnalyticShapesTiltAlongTheirUv) {
    // The u ramp on a rectangle whose a runs along +x (u) and b along +y (v):
    // as on the OBJ quad. On a sphere seen along -z, +u turns towards -x
    // (u = atan2(z, x) / 2 pi + 1/2), so the tilt against the rise is +x.
    const fs::path dir = test::tempDir();
    ASSERT_FALSE(writeHeights(dir / "height.png", [](int x, int) { return 1000 * x; }).empty());
    const Vec3f down{0.f, 0.f, -1.f};
    expectNear(shadeJsonShape(dir, R"({"type": "rectangle", "p0": [0, 0, 0], "a": [1, 0, 0], "b": [0, 1, 0], "material": "m"})",
                              Vec3f{0.6f, 0.3f, 1.f}, down),
               normalize(Vec3f{-20.f * kStep, 0.f, 1.f}));
    expectNear(shadeJsonShape(dir, R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"})",
                              Vec3f{0.f, 0.f, 5.f}, down),
               normalize(Vec3f{20.f * kStep, 0.f, 1.f}));
    // A box's +z face: u along x, v along y (the axes after z).
    expectNear(shadeJsonShape(dir, R"({"type": "box", "min": [-1, -1, -1], "max": [1, 1, 0], "material": "m"})",
                              Vec3f{0.2f, 0.1f, 5.f}, down),
               normalize(Vec3f{-20.f * kStep, 0.f, 1.f}));
}

TEST(BumpMaps, EachShapesUvGrowsAlongItsUvDerivatives) {
    // A step along the tangent from a hit raises u and leaves v; one along the
    // bitangent raises v (and leaves u where the uv axes are perpendicular):
    // on every analytic shape, a turned box and a skewed rectangle included.
    Scene s;
    Material textured;
    textured.textureIndex = 0;  // so that hits carry uv
    s.materials = {textured};
    s.spheres.push_back(Sphere{Vec3f{0.f, 0.f, 0.f}, 1.f, 0});
    s.planes.push_back(Plane{Vec3f{0.f, -3.f, 0.f}, normalize(Vec3f{0.2f, 1.f, 0.1f}), 0});
    s.boxes.push_back(makeBox(Vec3f{-1.f, -1.f, -1.f}, Vec3f{1.f, 1.f, 1.f},
                              Transform::translate(Vec3f{5.f, 0.f, 0.f}) * Transform::rotate(30.f, Vec3f{0.f, 0.f, 1.f})));
    s.rectangles.push_back(Rectangle{Vec3f{-6.f, -1.f, 0.f}, Vec3f{2.f, 0.5f, 0.f}, Vec3f{0.f, 1.f, 0.5f}, 0});
    s.disks.push_back(Disk{Vec3f{0.f, 5.f, 0.f}, normalize(Vec3f{0.3f, -1.f, 0.2f}), 1.f, 0});
    const std::unique_ptr<Accelerator> accel = makeNaiveAccelerator(s);
    const Vec3f targets[] = {{0.3f, 0.2f, 0.9f}, {0.5f, -3.f, 0.5f}, {5.2f, 0.3f, 1.f}, {-4.8f, -0.2f, 0.4f}, {0.2f, 5.f, 0.1f}};
    const ShapeKind kinds[] = {ShapeKind::Sphere, ShapeKind::Plane, ShapeKind::Box, ShapeKind::Rectangle, ShapeKind::Disk};
    const Vec3f approach[] = {{0.f, 0.f, 1.f}, {0.f, 1.f, 0.f}, {0.f, 0.f, 1.f}, {0.f, 0.f, 1.f}, {0.f, -1.f, 0.f}};
    for (int k = 0; k < 5; ++k) {
        SCOPED_TRACE(k);
        // Hits from 2 units off the surface along its normal, near the target.
        const auto hitNear = [&](const Vec3f& p, const Vec3f& n) { return accel->intersect(Ray{p + 2.f * n, -n}); };
        const std::optional<Hit> h = hitNear(targets[k], approach[k]);
        ASSERT_TRUE(h.has_value());
        ASSERT_EQ(h->ref.kind, kinds[k]);
        const Tangent t = s.tangentAt(*h);
        const Vec3f bitangent = t.sign * cross(h->ns, t.direction);
        constexpr float eps = 1e-2f;
        const std::optional<Hit> hu = hitNear(h->p + eps * t.direction, h->ns);
        const std::optional<Hit> hv = hitNear(h->p + eps * bitangent, h->ns);
        ASSERT_TRUE(hu && hv);
        const Vec2f du{hu->uv.x - h->uv.x, hu->uv.y - h->uv.y}, dv{hv->uv.x - h->uv.x, hv->uv.y - h->uv.y};
        EXPECT_GT(du.x, 0.f);
        EXPECT_LT(std::fabs(du.y), 0.05f * du.x);
        EXPECT_GT(dv.y, 0.f);
        // The bitangent is perpendicular to the tangent: on the skewed rectangle it moves u too.
        if (kinds[k] != ShapeKind::Rectangle) {
            EXPECT_LT(std::fabs(dv.x), 0.05f * dv.y);
        }
    }
}

TEST(BumpMaps, SponzasFloorShowsItsJointsAndStaysLevel) {
    // Dabrovic's Sponza: the floor's `bump KAMEN-bump.jpg` (stones between
    // darker joints) tilts the normals along the joints, where the height
    // drops, and leaves the stones level.
    const fs::path obj = test::sharedScenePath("sponza_dabrovic/sponza.obj");
    if (obj.empty() || !fs::exists(obj)) GTEST_SKIP() << "../shared/scenes/sponza_dabrovic is absent";
    test::WarningLog log;
    const LoadedScene s = loadScene(obj, {}, log.logger);
    const TextureCache cache(s.scene.textures, log.logger);
    const SurfaceShading shading(s.scene, &cache, 0.f);
    const std::unique_ptr<Accelerator> accel = makeAccelerator(AcceleratorKind::Embree, s.scene);
    int floor = 0, tilted = 0;
    double maxTilt = 0.0, sumTilt = 0.0;
    for (int i = 0; i < 60; ++i)
        for (int k = 0; k < 30; ++k) {
            const Ray ray{Vec3f{-12.f + 0.4f * float(i), 1.f, -3.f + 0.2f * float(k)}, Vec3f{0.f, -1.f, 0.f}};
            const std::optional<Hit> hit = accel->intersect(ray);
            if (!hit || s.scene.material(hit->material).name != "sp_00_pod") continue;
            ShadingPoint sp;
            shading.shade(*hit, ray, hit->t, sp);
            const double tilt = std::acos(std::min(1.0, double(dot(sp.ns, sp.ng)))) * 180.0 / 3.14159265358979;
            ++floor;
            tilted += tilt > 2.0;
            maxTilt = std::max(maxTilt, tilt);
            sumTilt += tilt;
        }
    std::printf("Sponza floor: %d hits, %d tilted past 2 degrees, mean tilt %.2f, max %.2f degrees\n", floor, tilted,
                sumTilt / std::max(floor, 1), maxTilt);
    ASSERT_GT(floor, 1000);
    EXPECT_GT(tilted, floor / 50) << "the joints tilt the normals";
    EXPECT_LT(tilted, floor / 2) << "the stones stay level";
    EXPECT_GT(maxTilt, 4.0);
    EXPECT_LT(maxTilt, 45.0);
    EXPECT_LT(sumTilt / floor, 5.0);
}

}  // namespace
}  // namespace penumbra
