// Alpha cutouts (accel/alpha_test.h) seen through each accelerator: a
// checkerboard cuts out of a mesh, an instance and a rectangle exactly the
// checker's area, for single rays, batches, lanes and shadow rays alike; a
// cut-out screen passes half a light's irradiance and a Blend one 1 - alpha;
// a Blend render transmits 1 - alpha of its backdrop, bit-identically for any
// thread count and tile size; OBJ map_d and map_Kd alpha and glTF MASK/BLEND
// as loaded; the shared scenes (pine foliage, AlphaBlendModeTest) when present.
#include <gtest/gtest.h>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/io/scene_loader.h"
#include "core/log.h"
#include "core/multi_jitter.h"
#include "core/scene_edits.h"
#include "shading/renderer.h"
#include "shading/whitted_integrator.h"
#include "support/both_accelerators.h"
#include "support/gltf_builder.h"
#include "support/test_support.h"

using namespace penumbra;

namespace {
namespace fs = std::filesystem;

Logger quietLogger() { return Logger([](LogLevel, std::string_view) {}, LogLevel::Error); }

// An n x n checkerboard PNG, texel (0, 0) (top left) opaque: RGBA (white,
// alpha 255 or 0) with channels 4, grey 255 or 0 with channels 1.
std::string checkerPng(int n, int channels) {
    std::vector<unsigned char> px;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const unsigned char on = (x + y) % 2 == 0 ? 255 : 0;
            if (channels == 4) px.insert(px.end(), {255, 255, 255, on});
            else px.push_back(on);
        }
    OIIO::Filesystem::IOVecOutput memory;
    auto out = OIIO::ImageOutput::create("png");
    OIIO::ImageSpec spec(n, n, channels, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:UnassociatedAlpha", 1);
    if (!out || !out->set_ioproxy(&memory) || !out->open("memory.png", spec) ||
        !out->write_image(OIIO::TypeDesc::UINT8, px.data()))
        return {};
    out->close();
    return std::string(memory.buffer().begin(), memory.buffer().end());
}

fs::path writeBytes(const fs::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
}

// The quad x, y in [-h, h] at z, facing +z, uv (0, 0) at (-h, -h) to (1, 1) at (h, h).
TriangleMesh quad(float h, float z, uint32_t material) {
    TriangleMesh m;
    m.name = "quad";
    for (const Vec3f& p : {Vec3f{-h, -h, z}, Vec3f{h, -h, z}, Vec3f{h, h, z}, Vec3f{-h, h, z}}) m.positions.push_back(p);
    m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    m.indices = {0, 1, 2, 0, 2, 3};
    m.material = material;
    return m;
}

uint32_t addMaterial(Scene& s, Material m) {
    bindTextures(m, [&](std::string& path, TextureColorSpace space) {
        return s.addTexture(TextureSource{path, space});
    });
    s.materials.push_back(m);
    return uint32_t(s.materials.size() - 1);
}

Material maskWithTexture(const fs::path& png) {
    Material m;
    m.kd = Rgb(0.f);
    m.diffuseTexture = png.string();
    m.alphaMode = AlphaMode::Mask;
    return m;
}

Material emitter(float le, bool twoSided) {
    Material m;
    m.kd = Rgb(0.f);
    m.ke = Rgb(le);
    m.twoSidedEmission = twoSided;
    return m;
}

Material blend(float opacity) {
    Material m;
    m.kd = Rgb(0.f);
    m.opacity = opacity;
    m.alphaMode = AlphaMode::Blend;
    return m;
}

// Rays straight down -z through an n x n grid over [-1, 1]^2 (never on a texel edge).
std::vector<Ray> gridRays(int n, float z = 3.f) {
    std::vector<Ray> rays;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const float x = -1.f + 2.f * (float(i) + 0.5f) / float(n), y = -1.f + 2.f * (float(j) + 0.5f) / float(n);
            rays.push_back(Ray{{x, y, z}, {0.f, 0.f, -1.f}, 0.f, kInfinity});
        }
    return rays;
}

// The share of `rays` that hit something, with every query form checked to agree ray for ray.
double hitFraction(const Accelerator& acc, const std::vector<Ray>& rays) {
    size_t hits = 0, batchSame = 0, laneSame = 0, shadowSame = 0;
    std::vector<std::optional<PrimIntersection>> batch(rays.size());
    acc.intersectPrimBatch(rays, batch);
    std::vector<Ray> shadow = rays;
    for (Ray& r : shadow) r.tfar = 10.f;
    std::vector<uint8_t> occ(rays.size());
    acc.occludedBatch(shadow, occ);
    for (size_t b = 0; b < rays.size(); b += RayLanes::kWidth) {
        RayLanes lanes;
        for (int l = 0; l < RayLanes::kWidth; ++l) {
            lanes.active[l] = b + size_t(l) < rays.size();
            if (lanes.active[l]) lanes.set(l, rays[b + size_t(l)]);
        }
        std::optional<PrimIntersection> got[RayLanes::kWidth];
        acc.intersectPrimLanes(lanes, got);
        uint8_t blocked[RayLanes::kWidth];
        for (int l = 0; l < RayLanes::kWidth; ++l)
            if (lanes.active[l]) lanes.tfar[l] = 10.f;
        acc.occludedLanes(lanes, blocked);
        for (int l = 0; l < RayLanes::kWidth && b + size_t(l) < rays.size(); ++l) {
            const size_t i = b + size_t(l);
            const auto one = acc.intersectPrim(rays[i]);
            hits += one.has_value();
            batchSame += batch[i].has_value() == one.has_value() && (!one || batch[i]->ref == one->ref);
            laneSame += got[l].has_value() == one.has_value() && (!one || got[l]->ref == one->ref);
            shadowSame += (occ[i] != 0) == one.has_value() && (blocked[l] != 0) == one.has_value() &&
                          acc.occluded(shadow[i]) == one.has_value();
        }
    }
    EXPECT_EQ(batchSame, rays.size()) << acc.name() << ": batches answer as single rays";
    EXPECT_EQ(laneSame, rays.size()) << acc.name() << ": lanes answer as single rays";
    EXPECT_EQ(shadowSame, rays.size()) << acc.name() << ": shadow rays see the holes camera rays see";
    return double(hits) / double(rays.size());
}

class AlphaCutout : public test::ForBothAccelerators {
protected:
    PrepareOptions prep() const {
        PrepareOptions o;
        o.accelerator = GetParam();
        return o;
    }
    const char* name() const { return GetParam() == pnb::AcceleratorKind::Naive ? "naive" : "embree"; }
};

}  // namespace

TEST_P(AlphaCutout, CheckerCutsItsAreaOutOfAMeshAnInstanceAndARectangle) {
    const fs::path png = writeBytes(test::tempDir() / "checker.png", checkerPng(8, 4));
    for (int shape = 0; shape < 3; ++shape) {
        Scene s;
        const uint32_t cut = addMaterial(s, maskWithTexture(png));
        if (shape == 0) s.meshes.push_back(quad(1.f, 0.f, cut));
        if (shape == 1) {
            s.prototypes.push_back(Prototype{"quad", {quad(0.5f, 0.f, cut)}});
            s.instances.push_back(makeInstance(0, Transform::scale(Vec3f{2.f, 2.f, 1.f})));
        }
        if (shape == 2) s.rectangles.push_back(Rectangle{{-1.f, -1.f, 0.f}, {2.f, 0.f, 0.f}, {0.f, 2.f, 0.f}, cut});
        PreparedScene ps(std::move(s), prep(), quietLogger());
        const Accelerator& acc = ps.accelerator();
        ASSERT_TRUE(acc.alphaTest().any());
        const double f = hitFraction(acc, gridRays(256));
        std::cout << "[ measured ] " << acc.name() << " shape " << shape << ": " << f << " of the rays hit\n";
        EXPECT_NEAR(f, 0.5, 0.01) << "shape " << shape;
        // Texel (0, 0), the image's top left, is opaque; its right neighbour is cut out.
        EXPECT_TRUE(acc.intersect(Ray{{-0.875f, 0.875f, 3.f}, {0, 0, -1}, 0.f, kInfinity})) << "shape " << shape;
        EXPECT_FALSE(acc.intersect(Ray{{-0.625f, 0.875f, 3.f}, {0, 0, -1}, 0.f, kInfinity})) << "shape " << shape;
    }
}

// An edit that turns an opaque material into a Blend one (or back) is seen:
// the edited scene's accelerator cannot share geometries built without filters.
TEST_P(AlphaCutout, MaterialEditsStartAndStopCuttingOut) {
    Scene s;
    Material plain;
    plain.kd = Rgb(0.5f);
    const uint32_t m = addMaterial(s, plain);
    s.prototypes.push_back(Prototype{"quad", {quad(1.f, 0.f, m)}});
    s.instances.push_back(makeInstance(0, Transform()));
    s.meshes.push_back(quad(1.f, -1.f, m));
    PreparedScene base(std::move(s), prep(), quietLogger());
    EXPECT_DOUBLE_EQ(hitFraction(base.accelerator(), gridRays(64)), 1.0);
    SceneEdits toBlend;
    toBlend.materials = {{m, blend(0.3f)}};
    toBlend.transforms = {{0, Transform::translate(Vec3f{0.f, 0.f, 0.5f})}};
    PreparedScene edited(base, toBlend, quietLogger());
    // Two layers at opacity 0.3: 1 - 0.7^2 of the rays hit one.
    EXPECT_NEAR(hitFraction(edited.accelerator(), gridRays(256)), 1.0 - 0.49, 0.01);
    SceneEdits back;
    back.materials = {{m, plain}};
    PreparedScene restored(edited, back, quietLogger());
    EXPECT_DOUBLE_EQ(hitFraction(restored.accelerator(), gridRays(64)), 1.0);
}

TEST_P(AlphaCutout, OpaqueMaterialsAndFullAlphaNeedNoTest) {
    const fs::path opaque = writeBytes(test::tempDir() / "opaque.png", checkerPng(4, 1));  // grey: no alpha channel
    Scene s;
    const uint32_t a = addMaterial(s, maskWithTexture(opaque));
    const uint32_t b = addMaterial(s, blend(1.f));
    Material ignored = blend(0.2f);
    ignored.alphaMode = AlphaMode::Opaque;
    const uint32_t c = addMaterial(s, ignored);
    for (uint32_t m : {a, b, c}) s.meshes.push_back(quad(1.f, float(m), m));
    PreparedScene ps(std::move(s), prep(), quietLogger());
    EXPECT_FALSE(ps.accelerator().alphaTest().any());
    EXPECT_DOUBLE_EQ(hitFraction(ps.accelerator(), gridRays(32)), 1.0);
}

// A 1 x 1 light of radiance 3 at height 2 over a diffuse floor; a screen at
// height 1 between them: a fine checker halves the floor's irradiance, Blend
// at opacity 0.3 passes 0.7 of it.
TEST_P(AlphaCutout, ShadowRaysSeeThroughCutOutAndBlendedScreens) {
    const fs::path png = writeBytes(test::tempDir() / "fine.png", checkerPng(64, 4));
    auto floorRadiance = [&](int screen) {
        Scene s;
        Material floor;
        floor.kd = Rgb(0.5f);
        const uint32_t f = addMaterial(s, floor), l = addMaterial(s, emitter(3.f, false));
        s.planes.push_back(Plane{{0, 0, 0}, {0, 1, 0}, true, f});
        s.rectangles.push_back(Rectangle{{-0.5f, 2.f, -0.5f}, {1, 0, 0}, {0, 0, 1}, l});
        if (screen > 0) {
            const uint32_t m = addMaterial(s, screen == 1 ? maskWithTexture(png) : blend(0.3f));
            TriangleMesh q = quad(2.f, 0.f, m);  // 2 texels per 1/8 unit
            for (size_t i = 0; i < q.positions.size(); ++i) q.positions[i] = Vec3f{q.positions[i].x, 1.f, q.positions[i].y};
            s.meshes.push_back(q);
        }
        PreparedScene ps(std::move(s), prep(), quietLogger());
        RenderSettings st;
        st.lightSamples = 4096;
        WhittedIntegrator integ({ps.scene(), ps.accelerator(), ps.lights(), ps.textures(), st});
        RayCounts counts;
        const Ray ray{{0.05f, 0.5f, 0.f}, normalize(Vec3f{-0.05f, -0.5f, 0.f}), 0.f, kInfinity};
        return integ.Li(ray, SampleKey{pixelSampleKey(1, 0), 0}, counts, nullptr).r;
    };
    const float open = floorRadiance(0), checker = floorRadiance(1), blended = floorRadiance(2);
    std::cout << "[ measured ] " << name() << ": open " << open << ", checker screen " << checker / open
              << ", blend 0.3 screen " << blended / open << " of it\n";
    ASSERT_GT(open, 0.f);
    EXPECT_NEAR(checker / open, 0.5f, 0.02f);
    EXPECT_NEAR(blended / open, 0.7f, 0.02f);
}

// An emissive backdrop of radiance 1 behind a black Blend quad of opacity 0.3
// filling the view: the image averages 0.7, the same bits for any thread
// count and tile size.
TEST_P(AlphaCutout, BlendRenderTransmitsOneMinusAlphaDeterministically) {
    Scene s;
    const uint32_t b = addMaterial(s, emitter(1.f, true)), q = addMaterial(s, blend(0.3f));
    s.meshes.push_back(quad(5.f, -1.f, b));
    s.meshes.push_back(quad(2.f, 1.f, q));
    PreparedScene ps(std::move(s), prep(), quietLogger());
    CameraDesc cam;
    cam.eye = {0.f, 0.f, 3.f};
    cam.lookAt = {0.f, 0.f, 0.f};
    cam.vfovDegrees = 30.f;
    RenderSettings st;
    st.width = st.height = 32;
    st.spp = 16;
    st.seed = 3;
    st.integrator = IntegratorKind::Path;
    auto renderWith = [&](int threads, int tile) {
        st.threads = threads;
        st.tileSize = tile;
        Film f = makeFilm(st);
        render(ps, cam, st, f);
        return f.radianceBuffer();
    };
    const std::vector<float> a = renderWith(1, 8), c = renderWith(0, 16);
    ASSERT_EQ(a.size(), c.size());
    EXPECT_EQ(std::memcmp(a.data(), c.data(), a.size() * sizeof(float)), 0) << "bit-identical";
    double sum = 0;
    for (size_t i = 0; i < a.size(); i += 3) sum += a[i];
    const double mean = sum / double(a.size() / 3);
    std::cout << "[ measured ] " << name() << ": Blend 0.3 render mean " << mean << " (expected 0.7)\n";
    EXPECT_NEAR(mean, 0.7, 0.015);
}

TEST_P(AlphaCutout, ObjMapDAndMapKdAlphaCutOutAtOneHalf) {
    const fs::path dir = test::tempDir();
    writeBytes(dir / "grey.png", checkerPng(8, 1));
    writeBytes(dir / "rgba.png", checkerPng(8, 4));
    test::writeFile(dir / "m.mtl", "newmtl d\nKd 0.5 0.5 0.5\nmap_d grey.png\nnewmtl kd\nKd 1 1 1\nmap_Kd rgba.png\n");
    for (const std::string material : {"d", "kd"}) {
        const fs::path obj = test::writeFile(dir / (material + ".obj"),
                                             "mtllib m.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\n"
                                             "vt 1 1\nvt 0 1\nusemtl " + material + "\nf 1/1 2/2 3/3 4/4\n");
        LoadedScene loaded = loadScene(obj, {}, quietLogger());
        PreparedScene ps(std::move(loaded.scene), prep(), quietLogger());
        const double f = hitFraction(ps.accelerator(), gridRays(128));
        std::cout << "[ measured ] " << name() << " OBJ " << material << ": " << f << " of the rays hit\n";
        EXPECT_NEAR(f, 0.5, 0.01) << material;
    }
}

TEST_P(AlphaCutout, GltfMaskAndBlendAsLoaded) {
    const fs::path dir = test::tempDir();
    for (const std::string mode : {"MASK", "BLEND"}) {
        test::GltfBuilder g;
        test::GltfBuilder::Json prim = g.quad();
        test::GltfBuilder::Json m{{"alphaMode", mode}};
        if (mode == "MASK") m["pbrMetallicRoughness"] = {{"baseColorTexture", {{"index", g.textureBytes(checkerPng(8, 4))}}}};
        else m["pbrMetallicRoughness"] = {{"baseColorFactor", {1.0, 1.0, 1.0, 0.3}}};
        prim["material"] = g.material(m);
        g.node(test::GltfBuilder::Json::array({prim}));
        const fs::path file = test::writeFile(dir / (mode + ".gltf"), g.gltf());
        LoadedScene loaded = loadScene(file, {}, quietLogger());
        PreparedScene ps(std::move(loaded.scene), prep(), quietLogger());
        const double f = hitFraction(ps.accelerator(), gridRays(256));
        std::cout << "[ measured ] " << name() << " glTF " << mode << ": " << f << " of the rays hit\n";
        EXPECT_NEAR(f, mode == "MASK" ? 0.5 : 0.3, 0.01) << mode;
    }
}

PENUMBRA_FOR_BOTH_ACCELERATORS(AlphaCutout);

// McGuire's pine: its foliage cards (map_Kd's alpha) let most rays through
// that the opaque cards stopped. Skipped without ../shared.
TEST(AlphaCutoutSharedScenes, PineFoliageLetsLightThrough) {
    const fs::path obj = test::sharedScenePath("pine_mcguire/scrubPine.obj");
    if (obj.empty() || !fs::exists(obj)) GTEST_SKIP() << "../shared/scenes/pine_mcguire is absent";
    LoadedScene loaded = loadScene(obj, {}, quietLogger());
    Scene opaque = loaded.scene;
    for (Material& m : opaque.materials) m.alphaMode = AlphaMode::Opaque;
    PreparedScene cut(std::move(loaded.scene), {}, quietLogger()), solid(std::move(opaque), {}, quietLogger());
    ASSERT_TRUE(cut.accelerator().alphaTest().any());
    const Bounds3f b = cut.scene().bounds();
    const Vec3f c = 0.5f * (b.lo + b.hi), e = b.hi - b.lo;
    size_t hitsCut = 0, hitsSolid = 0;
    const int n = 200;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            // From the side, across the tree's silhouette.
            const Vec3f o{c.x + e.x * ((float(i) + 0.5f) / n - 0.5f), c.y + e.y * ((float(j) + 0.5f) / n - 0.5f),
                          b.hi.z + e.z};
            const Ray r{o, {0, 0, -1}, 0.f, kInfinity};
            hitsCut += cut.accelerator().occluded(r);
            hitsSolid += solid.accelerator().occluded(r);
        }
    std::cout << "[ measured ] pine: " << hitsCut << " of " << hitsSolid << " rays the opaque cards stop are stopped with cutouts\n";
    EXPECT_LT(double(hitsCut), 0.8 * double(hitsSolid));
    EXPECT_GT(hitsCut, 0u);
}

// Khronos' AlphaBlendModeTest: its MASK and BLEND materials cut out. Skipped without ../shared.
TEST(AlphaCutoutSharedScenes, AlphaBlendModeTestCutsOut) {
    const fs::path glb = test::sharedScenePath("khronos_gltf/AlphaBlendModeTest/glTF-Binary/AlphaBlendModeTest.glb");
    if (glb.empty() || !fs::exists(glb)) GTEST_SKIP() << "../shared/scenes/khronos_gltf/AlphaBlendModeTest is absent";
    LoadedScene loaded = loadScene(glb, {}, quietLogger());
    int mask = 0, blended = 0;
    for (const Material& m : loaded.scene.materials) {
        mask += m.alphaMode == AlphaMode::Mask;
        blended += m.alphaMode == AlphaMode::Blend;
    }
    EXPECT_GT(mask, 0);
    EXPECT_GT(blended, 0);
    PreparedScene ps(std::move(loaded.scene), {}, quietLogger());
    EXPECT_TRUE(ps.accelerator().alphaTest().any());
    size_t cutting = 0;
    for (uint32_t id = 0; id < ps.scene().materials.size(); ++id) cutting += ps.accelerator().alphaTest().cutsOut(id);
    std::cout << "[ measured ] AlphaBlendModeTest: " << cutting << " of " << ps.scene().materials.size()
              << " materials cut out\n";
    EXPECT_GE(cutting, size_t(mask > 1 ? 2 : 1));
}
