// The C++ embedding API: scenes built in code, progressive passes, progress,
// cancellation, asynchronous jobs, concurrent renderers, errors and logging.
// Only the public header is used here, as a host would.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <new>
#include <penumbra/penumbra.hpp>
#include <thread>

#include "support/test_support.h"

namespace {

using Clock = std::chrono::steady_clock;

pnb::Renderer quietRenderer() {
    return pnb::Renderer([](pnb::LogLevel, std::string_view) {}, pnb::LogLevel::Error);
}

// A small room: floor, back wall, mirror sphere, rotated box, a mesh, an area
// light and a point light; every shape kind the API offers.
pnb::Scene roomScene(float lightPower = 8.f) {
    pnb::Scene s;
    pnb::Material white;
    white.kd = pnb::gray(0.7f);
    pnb::Material red;
    red.kd = {0.7f, 0.1f, 0.1f};
    red.ks = pnb::gray(0.2f);
    red.exponent = 30.f;
    pnb::Material mirror;
    mirror.kd = pnb::gray(0.f);
    mirror.kr = pnb::gray(0.9f);
    pnb::Material lamp;
    lamp.kd = pnb::gray(0.f);
    lamp.ke = pnb::gray(lightPower);
    pnb::Material classic;
    classic.model = pnb::PhongModel::Classic;
    classic.kd = {0.2f, 0.5f, 0.2f};
    classic.ka = pnb::gray(0.3f);
    const auto w = s.addMaterial(white), r = s.addMaterial(red), m = s.addMaterial(mirror), l = s.addMaterial(lamp),
               c = s.addMaterial(classic);
    s.addPlane({0, 0, 0}, {0, 1, 0}, w);
    s.addRectangle({-2, 0, -2}, {4, 0, 0}, {0, 3, 0}, r);
    s.addSphere({-0.6f, 0.5f, 0}, 0.5f, m);
    s.addBox({0.2f, 0, -0.3f}, {0.9f, 0.8f, 0.4f}, pnb::Matrix3x4::rotate(20.f, {0, 1, 0}), w);
    s.addDisk({0.8f, 0.01f, 1.0f}, {0, 1, 0}, 0.3f, c);
    const std::vector<float> pos = {-1.5f, 0, 0.8f, -0.9f, 0, 0.8f, -1.2f, 0.6f, 0.8f};
    const std::vector<uint32_t> idx = {0, 1, 2};
    s.addMesh(pos, idx, c);
    s.addRectangle({-0.5f, 2.5f, -0.5f}, {1, 0, 0}, {0, 0, 1}, l);
    s.addPointLight({1.5f, 2.f, 1.5f}, pnb::gray(1.f));
    s.addDirectionalLight({0.3f, -1.f, -0.2f}, pnb::gray(0.3f));
    s.setAmbient(pnb::gray(0.05f));
    s.setBackground({0.1f, 0.2f, 0.3f});
    return s;
}

pnb::Camera roomCamera() {
    pnb::Camera c;
    c.eye = {0, 1.2f, 4.f};
    c.lookAt = {0, 0.8f, 0};
    c.vfovDegrees = 45.f;
    return c;
}

pnb::RenderSettings smallSettings() {
    pnb::RenderSettings s;
    s.width = 48;
    s.height = 36;
    s.spp = 8;
    s.lightSamples = 2;
    s.seed = 7;
    return s;
}

// A white sphere of radius 1 at the origin, lit head-on by a point light at z = 5.
pnb::Scene litSphere() {
    pnb::Scene s;
    pnb::Material white;
    white.kd = pnb::gray(0.8f);
    s.addSphere({0, 0, 0}, 1.f, s.addMaterial(white));
    s.addPointLight({0, 0, 5}, pnb::gray(20.f));
    s.setBackground({0.1f, 0.2f, 0.3f});
    return s;
}

pnb::Camera sphereCamera() {
    pnb::Camera c;
    c.eye = {0, 0, 4};
    c.lookAt = {0, 0, 0};
    return c;
}

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

template <class F>
pnb::ErrorCode codeOf(F&& f, std::string* message = nullptr) {
    try {
        f();
    } catch (const pnb::Error& e) {
        if (message) *message = e.what();
        return e.code();
    }
    ADD_FAILURE() << "no pnb::Error thrown";
    return pnb::ErrorCode::Internal;
}

// ---------------------------------------------------------------- rendering

TEST(ApiRender, SphereLitHeadOnHasTheExpectedRadiance) {
    const pnb::Renderer renderer = quietRenderer();
    const pnb::PreparedScene prepared = renderer.prepare(litSphere());
    EXPECT_EQ(prepared.primitiveCount(), 1u);
    EXPECT_EQ(prepared.lightCount(), 1u);
    pnb::RenderSettings st;
    st.width = st.height = 33;  // odd: pixel 16 is centred on the sphere
    st.spp = 4;
    const pnb::Framebuffer image = renderer.render(prepared, sphereCamera(), st);
    ASSERT_EQ(image.width(), 33);
    ASSERT_EQ(image.sampleCount(), 4u);
    // Normalized Phong: kd/pi * I/d^2 with d = 4 at the front of the sphere.
    const float expected = 0.8f / 3.14159265f * 20.f / 16.f;
    const pnb::Color c = image.pixel(16, 16);
    EXPECT_NEAR(c.r, expected, 0.005f * expected);
    EXPECT_FLOAT_EQ(c.r, c.g);
    // Corners see the background exactly.
    const pnb::Color bg = image.pixel(0, 0);
    EXPECT_FLOAT_EQ(bg.r, 0.1f);
    EXPECT_FLOAT_EQ(bg.g, 0.2f);
    EXPECT_FLOAT_EQ(bg.b, 0.3f);
    const std::vector<float> rgba = image.rgba();
    ASSERT_EQ(rgba.size(), 33u * 33u * 4u);
    EXPECT_EQ(rgba[4 * (16 * 33 + 16)], c.r);
    EXPECT_EQ(rgba[3], 1.f);
}

TEST(ApiRender, AovsGiveDepthNormalAndAlbedoOfTheFirstHit) {
    const pnb::Renderer renderer = quietRenderer();
    const pnb::PreparedScene prepared = renderer.prepare(litSphere());
    pnb::RenderSettings st;
    st.width = st.height = 33;
    st.spp = 4;
    st.aovs = true;
    const pnb::Framebuffer image = renderer.render(prepared, sphereCamera(), st);
    ASSERT_TRUE(image.hasAovs());
    const size_t centre = 16 * 33 + 16;
    EXPECT_NEAR(image.depth()[centre], 3.f, 0.01f);  // eye at z = 4, surface at z = 1
    EXPECT_NEAR(image.normals()[3 * centre + 2], 1.f, 0.01f);
    EXPECT_NEAR(image.albedo()[3 * centre], 0.8f, 1e-5f);
    EXPECT_EQ(image.depth()[0], 0.f);  // a miss
    std::vector<float> host(33 * 33);
    image.readDepth(host.data(), host.size());
    EXPECT_TRUE(sameBits(host, image.depth()));
    // Without AOVs there is nothing to read.
    st.aovs = false;
    const pnb::Framebuffer plain = renderer.render(prepared, sphereCamera(), st);
    std::string msg;
    EXPECT_EQ(codeOf([&] { (void)plain.albedo(); }, &msg), pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("no AOVs"), std::string::npos) << msg;
}

TEST(ApiRender, ProgressivePassesAreBitIdenticalToOneShot) {
    const pnb::Renderer renderer = quietRenderer();
    const pnb::PreparedScene prepared = renderer.prepare(roomScene());
    pnb::RenderSettings st = smallSettings();
    st.spp = 16;
    st.aovs = true;
    const pnb::Framebuffer oneShot = renderer.render(prepared, roomCamera(), st);

    pnb::Framebuffer passes(st);
    const uint32_t splits[] = {0, 3, 4, 9, 16};
    std::vector<float> previous;
    for (int i = 0; i + 1 < 5; ++i) {
        const pnb::RenderStats stats =
            renderer.renderPass(prepared, roomCamera(), st, passes, splits[i], splits[i + 1] - splits[i]);
        EXPECT_EQ(stats.samplesPerPixel, splits[i + 1]);
        EXPECT_GT(stats.cameraRays, 0u);
        // The host reads the image between passes; it changes as samples arrive.
        const std::vector<float> now = passes.rgba();
        EXPECT_FALSE(sameBits(now, previous));
        previous = now;
    }
    EXPECT_EQ(passes.sampleCount(), 16u);
    EXPECT_TRUE(sameBits(passes.rgba(), oneShot.rgba()));
    EXPECT_TRUE(sameBits(passes.albedo(), oneShot.albedo()));
    EXPECT_TRUE(sameBits(passes.normals(), oneShot.normals()));
    EXPECT_TRUE(sameBits(passes.depth(), oneShot.depth()));

    // The same with another thread count and tile size.
    pnb::RenderSettings other = st;
    other.threads = 1;
    other.tileSize = 7;
    EXPECT_TRUE(sameBits(renderer.render(prepared, roomCamera(), other).rgba(), oneShot.rgba()));
}

TEST(ApiRender, PassesMustContinueWhereTheFramebufferStands) {
    const pnb::Renderer renderer = quietRenderer();
    const pnb::PreparedScene prepared = renderer.prepare(litSphere());
    const pnb::RenderSettings st = smallSettings();
    pnb::Framebuffer image(st);
    std::string msg;
    EXPECT_EQ(codeOf([&] { renderer.renderPass(prepared, sphereCamera(), st, image, 2, 2); }, &msg),
              pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("holds 0 samples"), std::string::npos) << msg;
    EXPECT_EQ(codeOf([&] { renderer.renderPass(prepared, sphereCamera(), st, image, 0, 9); }, &msg),
              pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("exceed spp = 8"), std::string::npos) << msg;
    pnb::RenderSettings bigger = st;
    bigger.width = 64;
    EXPECT_EQ(codeOf([&] { renderer.renderPass(prepared, sphereCamera(), bigger, image, 0, 1); }, &msg),
              pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("does not match the render settings"), std::string::npos) << msg;
    EXPECT_EQ(image.sampleCount(), 0u);
    EXPECT_FALSE(image.incomplete());
}

TEST(ApiRender, ProgressRisesToExactlyOne) {
    const pnb::Renderer renderer = quietRenderer();
    const pnb::PreparedScene prepared = renderer.prepare(roomScene());
    std::vector<double> seen;
    pnb::RenderControl control;
    control.progress = [&](double f) { seen.push_back(f); };  // never concurrent with itself
    pnb::RenderSettings st = smallSettings();
    st.tileSize = 8;
    renderer.render(prepared, roomCamera(), st, control);
    ASSERT_EQ(seen.size(), size_t(6 * 5));  // 48x36 in 8x8 tiles
    for (size_t i = 1; i < seen.size(); ++i) EXPECT_GT(seen[i], seen[i - 1]);
    EXPECT_GT(seen.front(), 0.0);
    EXPECT_EQ(seen.back(), 1.0);
}

TEST(ApiRender, RenderIntoHostMemoryEqualsTheFramebuffer) {
    const pnb::Renderer renderer = quietRenderer();
    const pnb::PreparedScene prepared = renderer.prepare(roomScene());
    const pnb::RenderSettings st = smallSettings();
    std::vector<float> host(size_t(st.width) * st.height * 4, -1.f);
    const pnb::RenderStats stats = renderer.render(prepared, roomCamera(), st, host.data(), host.size());
    EXPECT_EQ(stats.samplesPerPixel, 8u);
    EXPECT_TRUE(sameBits(host, renderer.render(prepared, roomCamera(), st).rgba()));
    std::string msg;
    EXPECT_EQ(codeOf([&] { renderer.render(prepared, roomCamera(), st, host.data(), host.size() - 1); }, &msg),
              pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("needs 6912"), std::string::npos) << msg;
}

TEST(ApiRender, CropWindowsTileIntoTheFullFrame) {
    const pnb::Renderer renderer = quietRenderer();
    const pnb::PreparedScene prepared = renderer.prepare(roomScene());
    const pnb::RenderSettings st = smallSettings();
    const pnb::Framebuffer full = renderer.render(prepared, roomCamera(), st);
    pnb::RenderSettings cropped = st;
    cropped.crop = pnb::CropWindow{10, 5, 30, 20};
    const pnb::Framebuffer part = renderer.render(prepared, roomCamera(), cropped);
    ASSERT_EQ(part.width(), 20);
    ASSERT_EQ(part.height(), 15);
    EXPECT_EQ(part.fullWidth(), 48);
    for (int y = 0; y < 15; ++y)
        for (int x = 0; x < 20; ++x) {
            const pnb::Color a = part.pixel(x, y), b = full.pixel(x + 10, y + 5);
            ASSERT_EQ(a.r, b.r);
            ASSERT_EQ(a.b, b.b);
        }
}

TEST(ApiRender, PreparedScenesRenderManyViewsAndKeepTheSceneUsable) {
    const pnb::Renderer renderer = quietRenderer();
    pnb::Scene scene = roomScene();
    const size_t prims = scene.primitiveCount();
    const pnb::PreparedScene prepared = renderer.prepare(scene);  // copies
    EXPECT_EQ(scene.primitiveCount(), prims);
    EXPECT_EQ(prepared.primitiveCount(), prims);
    EXPECT_EQ(prepared.lightCount(), 3u);  // point, directional, the emissive rectangle
    pnb::Camera left = roomCamera(), right = roomCamera();
    left.eye.x = -1.f;
    right.eye.x = 1.f;
    const auto a = renderer.render(prepared, left, smallSettings()).rgba();
    const auto b = renderer.render(prepared, right, smallSettings()).rgba();
    EXPECT_FALSE(sameBits(a, b));
    // A copy of the handle shares the data; a moved scene leaves an empty one.
    const pnb::PreparedScene copy = prepared;
    EXPECT_TRUE(sameBits(renderer.render(copy, left, smallSettings()).rgba(), a));
    const pnb::PreparedScene moved = renderer.prepare(std::move(scene));
    EXPECT_EQ(moved.primitiveCount(), prims);
    EXPECT_EQ(scene.primitiveCount(), 0u);  // NOLINT(bugprone-use-after-move): documented as empty
}

// The lit sphere rendered size x size at spp samples per pixel.
pnb::Framebuffer litSphereImage(int size, int spp) {
    const pnb::Renderer renderer = quietRenderer();
    pnb::RenderSettings st;
    st.width = st.height = size;
    st.spp = spp;
    return renderer.render(renderer.prepare(litSphere()), sphereCamera(), st);
}

TEST(ApiRender, WritesImagesThroughTheLibrary) {
    const pnb::Framebuffer image = litSphereImage(33, 4);
    const auto dir = penumbra::test::tempDir();
    image.writeImage((dir / "sphere.png").string());
    image.writeImage((dir / "sphere.pfm").string());
    EXPECT_GT(std::filesystem::file_size(dir / "sphere.png"), 0u);
    const size_t pfmHeader = std::string("PF\n33 33\n-1.0\n").size();
    EXPECT_EQ(std::filesystem::file_size(dir / "sphere.pfm"), 33u * 33u * 12u + pfmHeader);
    std::string msg;
    EXPECT_EQ(codeOf([&] { image.writeImage((dir / "missing" / "x.png").string()); }, &msg), pnb::ErrorCode::IoError);
    EXPECT_NE(msg.find("x.png"), std::string::npos) << msg;
    EXPECT_EQ(codeOf([&] { image.writeImage((dir / "x.bmp").string()); }, &msg), pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("unknown image format"), std::string::npos) << msg;
}

std::string fileBytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(ApiRender, EncodesInMemoryTheBytesWriteImageWrites) {
    const pnb::Framebuffer image = litSphereImage(33, 4);
    const auto dir = penumbra::test::tempDir();
    pnb::ImageOptions options;
    options.exposure = 0.5f;
    for (const char* format : {"png", "jpg", "exr", "pfm", "hdr", "tif"}) {
        const std::filesystem::path path = dir / (std::string("sphere.") + format);
        image.writeImage(path.string(), options);
        const std::vector<std::uint8_t> bytes = image.encodeImage(format, options);
        EXPECT_EQ(std::string(bytes.begin(), bytes.end()), fileBytes(path)) << format;
    }
    // Any case, with or without the dot.
    EXPECT_EQ(image.encodeImage(".PNG", options), image.encodeImage("png", options));
    std::string msg;
    EXPECT_EQ(codeOf([&] { (void)image.encodeImage("bmp"); }, &msg), pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("unknown image format 'bmp'"), std::string::npos) << msg;
    EXPECT_EQ(codeOf([&] { (void)pnb::Framebuffer().encodeImage("png"); }, &msg), pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("empty framebuffer"), std::string::npos) << msg;
}

TEST(ApiRender, EncodesAovsOnlyAsExrChannels) {
    const pnb::Renderer renderer = quietRenderer();
    pnb::RenderSettings st;
    st.width = st.height = 17;
    st.spp = 2;
    st.aovs = true;
    const pnb::Framebuffer image = renderer.render(renderer.prepare(litSphere()), sphereCamera(), st);
    pnb::ImageOptions options;
    options.aovs = true;
    const auto dir = penumbra::test::tempDir();
    image.writeImage((dir / "aovs.exr").string(), options);
    const std::vector<std::uint8_t> exr = image.encodeImage("exr", options);
    EXPECT_EQ(std::string(exr.begin(), exr.end()), fileBytes(dir / "aovs.exr"));
    std::string msg;
    EXPECT_EQ(codeOf([&] { (void)image.encodeImage("png", options); }, &msg), pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("only as the channels of an EXR"), std::string::npos) << msg;
}

// A texture for the tests below, written into dir as texture.png: a render
// of its own, a lit sphere (the brighter texels) on a blue background.
std::string writeSphereTexture(const pnb::Renderer& renderer, const std::filesystem::path& dir) {
    pnb::RenderSettings texSettings;
    texSettings.width = texSettings.height = 33;
    texSettings.spp = 1;
    const std::string path = (dir / "texture.png").string();
    renderer.render(renderer.prepare(litSphere()), sphereCamera(), texSettings).writeImage(path);
    return path;
}

TEST(ApiRender, MaterialsCanCarryADiffuseTexture) {
    const pnb::Renderer renderer = quietRenderer();
    const auto dir = penumbra::test::tempDir();
    const std::string texturePath = writeSphereTexture(renderer, dir);

    auto quad = [&](const std::string& texture) {
        pnb::Scene s;
        pnb::Material m;
        m.kd = pnb::gray(0.9f);
        m.diffuseTexture = texture;
        pnb::MeshDesc mesh;
        mesh.material = s.addMaterial(m);
        const float pos[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
        const float uvs[] = {0, 0, 1, 0, 1, 1, 0, 1};
        const uint32_t idx[] = {0, 1, 2, 0, 2, 3};
        mesh.positions = pos;
        mesh.vertexCount = 4;
        mesh.uvs = uvs;
        mesh.indices = idx;
        mesh.triangleCount = 2;
        s.addMesh(mesh);
        s.addPointLight({0, 0, 3}, pnb::gray(10.f));
        pnb::RenderSettings st;
        st.width = st.height = 16;
        st.spp = 1;
        pnb::Camera cam;
        cam.eye = {0, 0, 2.4f};
        cam.lookAt = {0, 0, 0};
        return renderer.render(renderer.prepare(s), cam, st);
    };
    const pnb::Framebuffer plain = quad(""), textured = quad(texturePath);
    // Corners show the texture's background (0.1, 0.2, 0.3): blue outweighs red there.
    const pnb::Color p = plain.pixel(1, 1), t = textured.pixel(1, 1);
    EXPECT_FLOAT_EQ(p.r, p.b);
    EXPECT_GT(t.b, 2.f * t.r);
    EXPECT_LT(t.b, p.b);
    // A missing texture is a warning, and the surface is drawn untextured.
    std::vector<std::string> warnings;
    const pnb::Renderer logging([&](pnb::LogLevel, std::string_view m) { warnings.emplace_back(m); });
    pnb::Scene s;
    pnb::Material m;
    m.diffuseTexture = (dir / "missing.png").string();
    s.addSphere({0, 0, 0}, 1.f, s.addMaterial(m));
    s.setDefaultLight(false);  // only the texture's warning
    logging.prepare(s);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("missing.png: cannot read texture"), std::string::npos) << warnings[0];
}

// A sphere's, a plane's and a box's hits take texture coordinates only for a
// textured material (Scene::completeHit): the texture must still follow them
// there, in both integrators. Per pixel, textured / plain is the texture's
// value at the pixel's uv (the light is a point at the eye and nothing else
// is lit, so the rest cancels); uv left at (0, 0) would make it one value
// over the whole shape.
TEST(ApiRender, AnalyticShapesCarryTheirTexture) {
    const pnb::Renderer renderer = quietRenderer();
    const auto dir = penumbra::test::tempDir();
    const std::string texturePath = writeSphereTexture(renderer, dir);
    for (int run = 0; run < 6; ++run) {
        const int shape = run % 3;
        const pnb::IntegratorKind integrator = run < 3 ? pnb::IntegratorKind::Whitted : pnb::IntegratorKind::Path;
        auto render = [&](const std::string& texture) {
            pnb::Scene s;
            pnb::Material m;
            m.kd = pnb::gray(0.9f);
            m.diffuseTexture = texture;
            const pnb::MaterialId id = s.addMaterial(m);
            if (shape == 0) s.addPlane({0, 0, 0}, {0, 0, 1}, id);
            if (shape == 1) s.addSphere({0, 0, 0}, 1.f, id);
            if (shape == 2) s.addBox({-1, -1, -1}, {1, 1, 1}, id);
            s.addPointLight({0.3f, 0.4f, 4.f}, pnb::gray(20.f));  // at the eye: every visible point lit
            s.setBackground({0, 0, 0});
            pnb::RenderSettings st;
            st.width = st.height = 24;
            st.spp = 1;
            st.integrator = integrator;
            pnb::Camera cam;
            cam.eye = {0.3f, 0.4f, 4.f};
            cam.lookAt = {0, 0, 0};
            return renderer.render(renderer.prepare(s), cam, st);
        };
        const pnb::Framebuffer plain = render(""), textured = render(texturePath);
        float lo = 1e30f, hi = 0.f;
        int covered = 0;
        for (int y = 0; y < 24; ++y)
            for (int x = 0; x < 24; ++x) {
                const float p = plain.pixel(x, y).g, t = textured.pixel(x, y).g;
                if (!(p > 1e-3f)) continue;  // the background (black)
                ++covered;
                lo = std::min(lo, t / p);
                hi = std::max(hi, t / p);
            }
        EXPECT_GT(covered, 40) << "run " << run;
        EXPECT_GT(hi, 2.f * lo) << "run " << run << ": the texture does not vary over the surface";
    }
}

// Whether this process has mapped OpenImageIO (read from /proc/self/maps).
bool imageLibraryMapped() {
    std::ifstream maps("/proc/self/maps");
    for (std::string line; std::getline(maps, line);)
        if (line.find("libOpenImageIO") != std::string::npos) return true;
    return false;
}

TEST(ApiRender, TheImageLibraryLoadsInThisProcessOnTheFirstImageOnly) {
    if (imageLibraryMapped()) GTEST_SKIP() << "an earlier test in this process loaded it (ctest runs each test alone)";
    // Rendering into memory and writing a PFM or a PNG (Penumbra's own encoders) need no image library.
    const pnb::Framebuffer image = litSphereImage(21, 2);
    const auto dir = penumbra::test::tempDir();
    pnb::ImageOptions options;
    options.exposure = 1.f;
    image.writeImage((dir / "a.pfm").string());
    image.writeImage((dir / "a.png").string(), options);
    EXPECT_FALSE(imageLibraryMapped()) << "a render to memory, PFM and PNG loaded OpenImageIO";
    // The first JPEG loads it here, in this process (no helper process), and it stays.
    image.writeImage((dir / "a.jpg").string(), options);
    EXPECT_TRUE(imageLibraryMapped());
    image.writeImage((dir / "b.jpg").string(), options);
    const auto bytes = [&](const char* name) {
        std::ifstream in(dir / name, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    EXPECT_GT(bytes("a.jpg").size(), 100u);
    EXPECT_EQ(bytes("a.jpg"), bytes("b.jpg"));
    EXPECT_GT(bytes("a.png").size(), 100u);
    std::string msg;
    EXPECT_EQ(codeOf([&] { image.writeImage((dir / "missing" / "x.png").string(), options); }, &msg),
              pnb::ErrorCode::IoError);
    EXPECT_NE(msg.find("x.png"), std::string::npos) << msg;
}

// ---------------------------------------------------------------- cancellation and jobs

// 1024x1024 at 256 spp: minutes of work, so it is always cancelled mid-way.
pnb::RenderSettings longSettings() {
    pnb::RenderSettings st;
    st.width = 1024;
    st.height = 1024;
    st.spp = 256;
    st.lightSamples = 4;
    return st;
}

TEST(ApiCancel, SynchronousRenderStopsAndThrowsCancelled) {
    const pnb::Renderer renderer = quietRenderer();
    const pnb::PreparedScene prepared = renderer.prepare(roomScene());
    std::atomic<bool> cancel{false};
    std::atomic<int> ticks{0};
    pnb::RenderControl control;
    control.cancel = &cancel;
    control.progress = [&](double) { ++ticks; };
    std::thread canceller([&] {
        while (ticks.load() < 3) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        cancel.store(true);
    });
    const pnb::RenderSettings st = longSettings();
    pnb::Framebuffer image(st);
    std::string msg;
    const auto t0 = Clock::now();
    EXPECT_EQ(codeOf([&] { renderer.render(prepared, roomCamera(), st, image, control); }, &msg),
              pnb::ErrorCode::Cancelled);
    canceller.join();
    EXPECT_LT(std::chrono::duration<double>(Clock::now() - t0).count(), 20.0);
    EXPECT_NE(msg.find("cancelled"), std::string::npos) << msg;
    // The partial pass cannot be continued by mistake; after clear() it renders again.
    EXPECT_TRUE(image.incomplete());
    EXPECT_EQ(codeOf([&] { renderer.renderPass(prepared, roomCamera(), st, image, 0, 1); }, &msg),
              pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("clear()"), std::string::npos) << msg;
    image.clear();
    EXPECT_FALSE(image.incomplete());
}

TEST(ApiCancel, AsynchronousCancelTakesEffectWithin200ms) {
    const pnb::Renderer renderer = quietRenderer();
    const pnb::PreparedScene prepared = renderer.prepare(roomScene());
    std::atomic<int> completions{0};
    std::atomic<int> completedStatus{-1};
    pnb::AsyncOptions options;
    options.onComplete = [&](const pnb::JobResult& r) {
        completedStatus = int(r.status);
        ++completions;
        EXPECT_EQ(r.framebuffer, nullptr);
        ASSERT_TRUE(r.error.has_value());
        EXPECT_EQ(r.error->code(), pnb::ErrorCode::Cancelled);
    };
    pnb::RenderJob job = renderer.renderAsync(prepared, roomCamera(), longSettings(), options);
    // Let it get going.
    const auto start = Clock::now();
    while (job.progress() == 0.0 && Clock::now() - start < std::chrono::seconds(10))
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ASSERT_FALSE(job.done());
    EXPECT_GT(job.progress(), 0.0);
    EXPECT_LT(job.progress(), 0.5);

    const auto t0 = Clock::now();
    job.cancel();
    job.wait();
    const double latency = std::chrono::duration<double>(Clock::now() - t0).count();
    EXPECT_LT(latency, 0.2) << "cancel() to wait() returning took " << latency << " s";

    EXPECT_TRUE(job.done());
    EXPECT_EQ(job.status(), pnb::JobStatus::Cancelled);
    EXPECT_EQ(completions.load(), 1);
    EXPECT_EQ(completedStatus.load(), int(pnb::JobStatus::Cancelled));
    ASSERT_TRUE(job.error().has_value());
    EXPECT_EQ(job.error()->code(), pnb::ErrorCode::Cancelled);
    EXPECT_EQ(codeOf([&] { (void)job.framebuffer(); }), pnb::ErrorCode::Cancelled);
}

TEST(ApiAsync, JobsReportPassesProgressAndCompletion) {
    const pnb::Renderer renderer = quietRenderer();
    const pnb::PreparedScene prepared = renderer.prepare(roomScene());
    pnb::RenderSettings st = smallSettings();
    st.spp = 12;
    std::mutex m;
    std::vector<uint32_t> passes;
    std::vector<std::vector<float>> snapshots;
    double lastProgress = 0.0;
    int completions = 0;
    std::vector<float> completed;
    pnb::AsyncOptions options;
    options.passSamples = 5;  // passes of 5, 5 and 2 samples
    options.progress = [&](double f) {
        std::lock_guard<std::mutex> lock(m);
        EXPECT_GE(f, lastProgress);
        lastProgress = f;
    };
    options.onPass = [&](const pnb::Framebuffer& image, uint32_t done) {
        std::lock_guard<std::mutex> lock(m);
        passes.push_back(done);
        EXPECT_EQ(image.sampleCount(), done);
        snapshots.push_back(image.rgba());
    };
    options.onComplete = [&](const pnb::JobResult& r) {
        std::lock_guard<std::mutex> lock(m);
        ++completions;
        EXPECT_EQ(r.status, pnb::JobStatus::Finished);
        EXPECT_FALSE(r.error.has_value());
        EXPECT_EQ(r.stats.samplesPerPixel, 12u);
        ASSERT_NE(r.framebuffer, nullptr);
        completed = r.framebuffer->rgba();
    };
    pnb::RenderJob job = renderer.renderAsync(prepared, roomCamera(), st, options);
    EXPECT_TRUE(job.waitFor(std::chrono::seconds(30)));
    EXPECT_EQ(job.status(), pnb::JobStatus::Finished);
    EXPECT_EQ(job.progress(), 1.0);
    EXPECT_EQ(lastProgress, 1.0);
    EXPECT_EQ(completions, 1);
    EXPECT_EQ(passes, (std::vector<uint32_t>{5, 10, 12}));
    EXPECT_FALSE(job.error().has_value());
    EXPECT_GT(job.stats().cameraRays, 0u);

    const std::vector<float> oneShot = renderer.render(prepared, roomCamera(), st).rgba();
    EXPECT_TRUE(sameBits(job.framebuffer().rgba(), oneShot));
    EXPECT_TRUE(sameBits(completed, oneShot));
    EXPECT_TRUE(sameBits(snapshots.back(), oneShot));
    EXPECT_FALSE(sameBits(snapshots.front(), oneShot));
    const pnb::Framebuffer taken = job.takeFramebuffer();
    EXPECT_TRUE(sameBits(taken.rgba(), oneShot));
}

// A job drops its copies of the callbacks (and of the scene) before wait()
// returns, not when its thread ends a moment later: the caller may tear down
// what they capture right after (the Python module does so at interpreter
// exit, where a thread that still held a Python callable would be stopped
// while it releases it).
TEST(ApiAsync, CallbacksAreReleasedBeforeWaitReturns) {
    // Counts its live copies; releasing one takes a while, so a copy the job's
    // thread dropped only after wait() returned would still be counted.
    struct SlowToRelease {
        std::shared_ptr<std::atomic<int>> live;
        explicit SlowToRelease(std::shared_ptr<std::atomic<int>> l) : live(std::move(l)) { ++*live; }
        SlowToRelease(const SlowToRelease& o) : live(o.live) { ++*live; }
        SlowToRelease& operator=(const SlowToRelease&) = delete;
        ~SlowToRelease() {
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
            --*live;
        }
    };
    const pnb::Renderer renderer = quietRenderer();
    const pnb::PreparedScene prepared = renderer.prepare(roomScene());
    for (int round = 0; round < 3; ++round) {
        auto live = std::make_shared<std::atomic<int>>(0);
        pnb::RenderJob job;
        {
            pnb::AsyncOptions options;
            options.onComplete = [hold = SlowToRelease(live)](const pnb::JobResult&) {};
            job = renderer.renderAsync(prepared, roomCamera(), smallSettings(), std::move(options));
        }
        job.wait();
        EXPECT_EQ(live->load(), 0) << "round " << round;
    }
}

TEST(ApiAsync, DestroyingARunningJobCancelsIt) {
    const pnb::Renderer renderer = quietRenderer();
    const auto t0 = Clock::now();
    {
        pnb::RenderJob job = renderer.renderAsync(renderer.prepare(roomScene()), roomCamera(), longSettings());
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }  // the job, and the last handle to its scene, go here
    EXPECT_LT(std::chrono::duration<double>(Clock::now() - t0).count(), 5.0);
    pnb::RenderJob empty;
    EXPECT_TRUE(empty.done());
    EXPECT_EQ(codeOf([&] { (void)empty.framebuffer(); }), pnb::ErrorCode::InvalidArgument);
}

// ---------------------------------------------------------------- no global state

TEST(ApiConcurrency, TwoRenderersAtOnceGiveTheirSequentialImages) {
    // Different scenes, settings and thread counts per renderer.
    pnb::RenderSettings stA = smallSettings();
    stA.width = 96;
    stA.height = 72;
    stA.spp = 16;
    stA.threads = 2;
    pnb::RenderSettings stB = smallSettings();
    stB.width = 80;
    stB.height = 80;
    stB.spp = 16;
    stB.seed = 99;
    stB.threads = 1;
    stB.aovs = true;
    const pnb::Camera camB = sphereCamera();

    auto renderA = [&] {
        const pnb::Renderer r = quietRenderer();
        return r.render(r.prepare(roomScene()), roomCamera(), stA).rgba();
    };
    auto renderB = [&] {
        const pnb::Renderer r = quietRenderer();
        const pnb::Framebuffer f = r.render(r.prepare(roomScene(3.f)), camB, stB);
        std::vector<float> v = f.rgba();
        const std::vector<float> d = f.depth();
        v.insert(v.end(), d.begin(), d.end());
        return v;
    };
    const std::vector<float> aAlone = renderA(), bAlone = renderB();
    std::vector<float> aTogether, bTogether;
    for (int round = 0; round < 2; ++round) {
        std::thread ta([&] { aTogether = renderA(); });
        std::thread tb([&] { bTogether = renderB(); });
        ta.join();
        tb.join();
        EXPECT_TRUE(sameBits(aTogether, aAlone)) << "round " << round;
        EXPECT_TRUE(sameBits(bTogether, bAlone)) << "round " << round;
    }
    EXPECT_FALSE(sameBits(aAlone, bAlone));
}

TEST(ApiConcurrency, OnePreparedSceneRendersFromTwoThreadsAtOnce) {
    const pnb::Renderer renderer = quietRenderer();
    const pnb::PreparedScene prepared = renderer.prepare(roomScene());
    const pnb::RenderSettings st = smallSettings();
    const std::vector<float> alone = renderer.render(prepared, roomCamera(), st).rgba();
    std::vector<float> a, b;
    std::thread ta([&] { a = renderer.render(prepared, roomCamera(), st).rgba(); });
    std::thread tb([&] { b = renderer.render(prepared, roomCamera(), st).rgba(); });
    ta.join();
    tb.join();
    EXPECT_TRUE(sameBits(a, alone));
    EXPECT_TRUE(sameBits(b, alone));
}

// ---------------------------------------------------------------- errors

TEST(ApiErrors, SceneBuildingRejectsBadInputWithNamedProblems) {
    pnb::Scene s;
    std::string msg;
    EXPECT_EQ(codeOf([&] { s.addSphere({0, 0, 0}, 1.f, 3); }, &msg), pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("material id 3 does not exist"), std::string::npos) << msg;
    s.addSphere({0, 0, 0}, 1.f, 0);  // the default material
    EXPECT_EQ(codeOf([&] { s.addSphere({0, 0, 0}, -1.f, 0); }, &msg), pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("sphere radius"), std::string::npos) << msg;
    EXPECT_EQ(codeOf([&] { s.addSphere({NAN, 0, 0}, 1.f, 0); }, &msg), pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("sphere centre must be finite"), std::string::npos) << msg;
    EXPECT_EQ(codeOf([&] { s.addPlane({0, 0, 0}, {0, 0, 0}, 0); }, &msg), pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("plane normal"), std::string::npos) << msg;
    EXPECT_EQ(codeOf([&] { s.addBox({1, 0, 0}, {0, 1, 1}, 0); }, &msg), pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("box lo"), std::string::npos) << msg;
    EXPECT_EQ(codeOf([&] { s.addBox({0, 0, 0}, {1, 1, 1}, pnb::Matrix3x4::scale({1, 0, 1}), 0); }, &msg),
              pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("singular"), std::string::npos) << msg;
    EXPECT_EQ(codeOf([&] { s.addRectangle({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, 0); }, &msg),
              pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("parallel"), std::string::npos) << msg;
    pnb::Material bad;
    bad.name = "glow";
    bad.ke = {-1.f, 0.f, 0.f};
    EXPECT_EQ(codeOf([&] { s.addMaterial(bad); }, &msg), pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("material 'glow': ke"), std::string::npos) << msg;

    const float pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint32_t idx[] = {0, 1, 3};
    pnb::MeshDesc mesh;
    mesh.name = "tri";
    mesh.positions = pos;
    mesh.vertexCount = 3;
    mesh.indices = idx;
    mesh.triangleCount = 1;
    EXPECT_EQ(codeOf([&] { s.addMesh(mesh); }, &msg), pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("mesh 'tri': triangle 0 uses vertex 3, but the mesh has 3 vertices"), std::string::npos)
        << msg;
    const uint32_t ok[] = {0, 1, 2};
    const uint32_t faceMat[] = {4};
    mesh.indices = ok;
    mesh.faceMaterials = faceMat;
    EXPECT_EQ(codeOf([&] { s.addMesh(mesh); }, &msg), pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("triangle 0: material id 4"), std::string::npos) << msg;
    mesh.faceMaterials = nullptr;
    mesh.positions = nullptr;
    EXPECT_EQ(codeOf([&] { s.addMesh(mesh); }, &msg), pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("positions are null"), std::string::npos) << msg;
    EXPECT_EQ(codeOf([&] { s.addMesh({0, 0, 0, 1}, {0, 1, 2}, 0); }, &msg), pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("multiple of 3"), std::string::npos) << msg;
    EXPECT_EQ(s.primitiveCount(), 1u);  // only the one good sphere went in
}

TEST(ApiErrors, BadSettingsCamerasAndHandlesAreInvalidArguments) {
    const pnb::Renderer renderer = quietRenderer();
    const pnb::PreparedScene prepared = renderer.prepare(litSphere());
    std::string msg;
    pnb::RenderSettings st = smallSettings();
    st.width = 0;
    EXPECT_EQ(codeOf([&] { renderer.render(prepared, sphereCamera(), st); }, &msg), pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("width must be in [1, 65536], got 0"), std::string::npos) << msg;
    st = smallSettings();
    st.crop = pnb::CropWindow{0, 0, 100, 10};
    EXPECT_EQ(codeOf([&] { pnb::validate(st); }, &msg), pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("crop window"), std::string::npos) << msg;
    pnb::Camera cam = sphereCamera();
    cam.lookAt = cam.eye;
    EXPECT_EQ(codeOf([&] { renderer.render(prepared, cam, smallSettings()); }, &msg), pnb::ErrorCode::InvalidArgument);
    const pnb::PreparedScene empty;
    EXPECT_FALSE(empty.valid());
    EXPECT_EQ(codeOf([&] { renderer.render(empty, sphereCamera(), smallSettings()); }, &msg),
              pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("prepared scene is empty"), std::string::npos) << msg;
    EXPECT_EQ(codeOf([&] { renderer.renderAsync(empty, sphereCamera(), smallSettings()); }),
              pnb::ErrorCode::InvalidArgument);
    pnb::PrepareOptions po;
    po.accelerator = static_cast<pnb::AcceleratorKind>(7);
    EXPECT_EQ(codeOf([&] { renderer.prepare(litSphere(), po); }, &msg), pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("accelerator 7 is not an AcceleratorKind"), std::string::npos) << msg;
}

TEST(ApiErrors, HugeFramebuffersAreOutOfMemoryNotACrash) {
    pnb::RenderSettings st;
    st.width = st.height = 65536;
    std::string msg;
    EXPECT_EQ(codeOf([&] { pnb::Framebuffer f(st); }, &msg), pnb::ErrorCode::OutOfMemory);
    EXPECT_NE(msg.find("65536x65536 framebuffer needs"), std::string::npos) << msg;
}

TEST(ApiErrors, ExceptionsFromHostCallbacksAreTranslated) {
    const pnb::Renderer renderer = quietRenderer();
    const pnb::PreparedScene prepared = renderer.prepare(litSphere());
    pnb::RenderControl control;
    control.progress = [](double) { throw std::bad_alloc(); };
    EXPECT_EQ(codeOf([&] { renderer.render(prepared, sphereCamera(), smallSettings(), control); }),
              pnb::ErrorCode::OutOfMemory);
    control.progress = [](double) { throw pnb::Error(pnb::ErrorCode::IoError, "host says no"); };
    std::string msg;
    EXPECT_EQ(codeOf([&] { renderer.render(prepared, sphereCamera(), smallSettings(), control); }, &msg),
              pnb::ErrorCode::IoError);
    EXPECT_EQ(msg, "host says no");
    // An async job reports a throwing callback as a failure instead of terminating.
    pnb::AsyncOptions options;
    options.progress = [](double) { throw std::runtime_error("callback broke"); };
    pnb::RenderJob job = renderer.renderAsync(prepared, sphereCamera(), smallSettings(), options);
    job.wait();
    EXPECT_EQ(job.status(), pnb::JobStatus::Failed);
    ASSERT_TRUE(job.error().has_value());
    EXPECT_EQ(job.error()->code(), pnb::ErrorCode::Internal);
    EXPECT_STREQ(job.error()->what(), "callback broke");
}

// ---------------------------------------------------------------- files, paths and logging

TEST(ApiLoad, JsonSceneBringsItsCameraAndSettings) {
    const pnb::Renderer renderer = quietRenderer();
    const pnb::Scene scene = renderer.loadScene(penumbra::test::assetPath("scenes/lecture_area_light.json").string());
    ASSERT_TRUE(scene.camera().has_value());
    EXPECT_EQ(scene.camera()->eye.x, -20.f);
    EXPECT_EQ(scene.camera()->vfovDegrees, 25.f);
    const pnb::RenderSettings fileSettings = scene.settings();
    EXPECT_EQ(fileSettings.width, 600);
    EXPECT_EQ(fileSettings.lightSamples, 16);
    EXPECT_EQ(fileSettings.seed, 1u);
    EXPECT_EQ(scene.primitiveCount(), 6u);  // plane, 3 spheres, box, light rectangle

    const pnb::PreparedScene prepared = renderer.prepare(scene);
    pnb::RenderSettings st = prepared.settings();
    st.width = 60;
    st.height = 40;
    st.spp = 4;
    st.lightSamples = 4;
    const pnb::Framebuffer image = renderer.render(prepared, *prepared.camera(), st);
    const pnb::Color lit = image.pixel(30, 15);  // the upper, lit half of the red sphere
    EXPECT_GT(lit.r, 0.2f);
    EXPECT_GT(lit.r, 3.f * lit.b);
    const pnb::Color below = image.pixel(30, 20);  // its lower half: no ambient light, in its own shadow
    EXPECT_EQ(below.r, 0.f);
}

TEST(ApiLoad, FileErrorsCarryCodeFileAndPosition) {
    const pnb::Renderer renderer = quietRenderer();
    const auto dir = penumbra::test::tempDir();
    std::string msg;
    EXPECT_EQ(codeOf([&] { renderer.loadScene((dir / "nope.json").string()); }, &msg), pnb::ErrorCode::FileNotFound);
    EXPECT_NE(msg.find("nope.json"), std::string::npos) << msg;
    const auto bad = penumbra::test::writeFile(dir / "bad.json", "{\n  \"shapes\": [ oops ]\n}\n");
    EXPECT_EQ(codeOf([&] { renderer.loadScene(bad.string()); }, &msg), pnb::ErrorCode::ParseError);
    EXPECT_NE(msg.find("bad.json:2:"), std::string::npos) << msg;
    const auto badRadius = penumbra::test::writeFile(
        dir / "radius.json", R"({"shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": -1}]})");
    EXPECT_EQ(codeOf([&] { renderer.loadScene(badRadius.string()); }, &msg), pnb::ErrorCode::InvalidScene);
    EXPECT_NE(msg.find("/shapes/0/radius"), std::string::npos) << msg;
    EXPECT_EQ(codeOf([&] { renderer.loadScene((dir / "scene.txt").string()); }, &msg),
              pnb::ErrorCode::InvalidArgument);
}

TEST(ApiLoad, PathsAreRestrictedToTheSceneFolderUnlessTheHostWidensThem) {
    const pnb::Renderer renderer = quietRenderer();
    const auto dir = penumbra::test::tempDir();
    penumbra::test::writeFile(dir / "meshes" / "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const auto scene = penumbra::test::writeFile(
        dir / "scenes" / "s.json", R"({"shapes": [{"type": "mesh", "file": "../meshes/tri.obj"}]})");
    std::string msg;
    EXPECT_EQ(codeOf([&] { renderer.loadScene(scene.string()); }, &msg), pnb::ErrorCode::InvalidArgument);
    EXPECT_NE(msg.find("outside the allowed directories"), std::string::npos) << msg;
    EXPECT_NE(msg.find("tri.obj"), std::string::npos) << msg;

    pnb::LoadOptions widened;
    widened.allowedRoots = {(dir / "meshes").string()};
    EXPECT_EQ(renderer.loadScene(scene.string(), widened).triangleCount(), 1u);
    pnb::LoadOptions open;
    open.restrictPaths = false;
    EXPECT_EQ(renderer.loadScene(scene.string(), open).triangleCount(), 1u);
}

// A texture checked when the scene is loaded is read from the file opened then:
// swapping in a symlink to a file outside the scene's folder before prepare
// (the render's texture read) changes nothing.
TEST(ApiLoad, ATextureSwappedForASymlinkAfterLoadingIsNotReadThroughIt) {
    const pnb::Renderer renderer = quietRenderer();
    const auto dir = penumbra::test::tempDir();
    std::filesystem::create_directories(dir / "scene");
    std::filesystem::create_directories(dir / "outside");
    // Two one-colour images: red inside the scene's folder, blue outside it.
    auto flat = [&](pnb::Color c, const std::filesystem::path& path) {
        pnb::Scene s;
        s.addSphere({0, 0, -100}, 1.f, s.addMaterial(pnb::Material{}));
        s.setBackground(c);
        pnb::RenderSettings st;
        st.width = st.height = 4;
        st.spp = 1;
        renderer.render(renderer.prepare(s), sphereCamera(), st).writeImage(path.string());
    };
    flat({1, 0, 0}, dir / "scene" / "tex.png");
    flat({0, 0, 1}, dir / "outside" / "tex.png");
    const auto scene = penumbra::test::writeFile(dir / "scene" / "s.json", R"({
        "camera": { "eye": [0, 0, 3], "look_at": [0, 0, 0], "fov": 30 },
        "materials": { "tex": { "kd": 1, "texture": "tex.png" } },
        "shapes": [ { "type": "rectangle", "p0": [-1, -1, 0], "a": [2, 0, 0], "b": [0, 2, 0], "material": "tex" } ],
        "lights": [ { "type": "point", "position": [0, 0, 3], "intensity": 9 } ]
    })");
    const pnb::Scene loaded = renderer.loadScene(scene.string());  // paths restricted (the default)
    std::filesystem::remove(dir / "scene" / "tex.png");
    std::filesystem::create_symlink(dir / "outside" / "tex.png", dir / "scene" / "tex.png");
    pnb::RenderSettings st;
    st.width = st.height = 8;
    st.spp = 1;
    const pnb::Framebuffer fb = renderer.render(renderer.prepare(loaded), *loaded.camera(), st);
    const pnb::Color c = fb.pixel(4, 4);
    EXPECT_GT(c.r, 0.1f);
    EXPECT_EQ(c.b, 0.f) << "the render read the file outside the scene's folder";
}

TEST(ApiLog, MessagesGoToTheHostCallback) {
    std::mutex m;
    std::vector<std::pair<pnb::LogLevel, std::string>> messages;
    const pnb::Renderer renderer(
        [&](pnb::LogLevel level, std::string_view text) {
            std::lock_guard<std::mutex> lock(m);
            messages.emplace_back(level, std::string(text));
        },
        pnb::LogLevel::Info);
    pnb::Scene s;
    // A zero-area triangle passes the API's checks and is dropped (with a warning) when preparing.
    const float pos[] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0};
    const uint32_t idx[] = {0, 1, 2, 0, 1, 3};
    pnb::MeshDesc mesh;
    mesh.positions = pos;
    mesh.vertexCount = 4;
    mesh.indices = idx;
    mesh.triangleCount = 2;
    s.addMesh(mesh);
    const pnb::PreparedScene prepared = renderer.prepare(s);
    EXPECT_EQ(prepared.droppedTriangles(), 1u);
    EXPECT_EQ(prepared.triangleCount(), 1u);
    bool found = false;
    for (const auto& [level, text] : messages)
        if (level == pnb::LogLevel::Warning && text.find("dropped 1 triangle") != std::string::npos) found = true;
    EXPECT_TRUE(found);
}

TEST(ApiVersion, LibraryAndHeadersAgree) {
    EXPECT_STREQ(pnb::version(), PENUMBRA_VERSION);
    EXPECT_EQ(PENUMBRA_VERSION_NUMBER, PENUMBRA_VERSION_MAJOR * 10000 + PENUMBRA_VERSION_MINOR * 100 +
                                           PENUMBRA_VERSION_PATCH);
    EXPECT_STREQ(pnb::errorCodeName(pnb::ErrorCode::Cancelled), "cancelled");
}

}  // namespace

// Waiting for a job inside its own callbacks could never return (the job's
// thread, or a render thread it waits for, would wait for itself): it throws,
// and the job still finishes. Waiting for the job from outside still works.
TEST(ApiAsync, WaitingInsideTheJobsOwnCallbacksThrowsInsteadOfDeadlocking) {
    const pnb::Renderer renderer = quietRenderer();
    const pnb::PreparedScene prepared = renderer.prepare(roomScene());
    pnb::RenderSettings st;
    st.width = 16;
    st.height = 16;
    st.spp = 4;
    pnb::RenderJob job;
    std::atomic<int> progressThrew{0}, passThrew{0}, completeThrew{0};
    const auto throwsInvalid = [&](std::atomic<int>& count, auto&& call) {
        if (codeOf(call) == pnb::ErrorCode::InvalidArgument) ++count;
    };
    pnb::AsyncOptions options;
    options.passSamples = 2;
    options.progress = [&](double) { throwsInvalid(progressThrew, [&] { job.wait(); }); };
    options.onPass = [&](const pnb::Framebuffer&, std::uint32_t) {
        throwsInvalid(passThrew, [&] { job.wait(); });
        throwsInvalid(passThrew, [&] { (void)job.stats(); });
    };
    options.onComplete = [&](const pnb::JobResult&) {
        throwsInvalid(completeThrew, [&] { (void)job.framebuffer(); });
        throwsInvalid(completeThrew, [&] { (void)job.error(); });
    };
    // The callbacks read `job` only once it is assigned: the first pass waits for this.
    std::mutex assigned;
    std::unique_lock<std::mutex> hold(assigned);
    auto gate = options.progress;
    options.progress = [&, gate](double f) {
        { std::lock_guard<std::mutex> wait(assigned); }
        gate(f);
    };
    job = renderer.renderAsync(prepared, roomCamera(), st, options);
    hold.unlock();
    job.wait();
    EXPECT_EQ(job.status(), pnb::JobStatus::Finished);
    EXPECT_GT(progressThrew.load(), 0);
    EXPECT_EQ(passThrew.load(), 4);      // two passes, two calls each
    EXPECT_EQ(completeThrew.load(), 2);
    EXPECT_EQ(job.framebuffer().width(), 16);
}
