// The metal-roughness BSDF rendered through the public API, in both
// integrators: a white furnace (a white metal sphere in a uniform white
// environment shows its directional albedo), a polished metal that mirrors
// the environment, the same image from both accelerators; and a textured
// emitter, which is seen and lights the scene as its texture says.
#include <gtest/gtest.h>

#include <penumbra/penumbra.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/multi_jitter.h"
#include "shading/bsdf/metal_roughness.h"
#include "support/test_support.h"

namespace {
namespace fs = std::filesystem;

pnb::Renderer quietRenderer() {
    return pnb::Renderer([](pnb::LogLevel, std::string_view) {}, pnb::LogLevel::Error);
}

/// A white metal sphere of the given roughness in a uniform environment of radiance 1.
pnb::Scene furnace(float roughness) {
    pnb::Scene s;
    pnb::Material m;
    m.kind = pnb::MaterialKind::MetalRoughness;
    m.baseColor = pnb::gray(1.f);
    m.metallic = 1.f;
    m.roughness = roughness;
    s.addSphere({0, 0, 0}, 1.f, s.addMaterial(m));
    s.setEnvironment(pnb::gray(1.f));
    return s;
}

pnb::Camera frontCamera() {
    pnb::Camera c;
    c.eye = {0, 0, 4};
    c.lookAt = {0, 0, 0};
    c.vfovDegrees = 4.f;  // the centre pixels see the sphere within a few degrees of head-on
    return c;
}

pnb::RenderSettings furnaceSettings(pnb::IntegratorKind integrator) {
    pnb::RenderSettings st;
    st.width = st.height = 4;
    st.spp = 256;
    st.lightSamples = 4;
    st.integrator = integrator;
    st.seed = 7;
    return st;
}

double meanRed(const pnb::Framebuffer& fb) {
    double sum = 0;
    for (int y = 0; y < fb.height(); ++y)
        for (int x = 0; x < fb.width(); ++x) sum += fb.pixel(x, y).r;
    return sum / (fb.width() * fb.height());
}

/// The BSDF's own white-metal albedo seen head-on (E[f cos / pdf], shading/bsdf/metal_roughness.h).
double headOnAlbedo(float roughness) {
    const penumbra::Vec3f n{0.f, 0.f, 1.f};
    const penumbra::MetalRoughnessBsdf bsdf(penumbra::Rgb(1.f), 1.f, roughness, n, n);
    const uint32_t N = 1u << 16;
    double sum = 0;
    for (uint32_t i = 0; i < N; ++i)
        if (const auto s = bsdf.sample(penumbra::multiJitter2D(i, N, 1))) sum += s->fCos.r / s->pdf;
    return sum / N;
}

const pnb::IntegratorKind kBoth[] = {pnb::IntegratorKind::Whitted, pnb::IntegratorKind::Path};

}  // namespace

TEST(MetalRoughnessRender, WhiteFurnaceShowsTheAlbedoInBothIntegrators) {
    const pnb::Renderer r = quietRenderer();
    const pnb::PreparedScene p = r.prepare(furnace(0.5f));
    const double albedo = headOnAlbedo(0.5f);  // 0.916: single-scattering GGX loses the rest
    for (pnb::IntegratorKind k : kBoth) {
        const double seen = meanRed(r.render(p, frontCamera(), furnaceSettings(k)));
        EXPECT_NEAR(seen, albedo, 0.01) << (k == pnb::IntegratorKind::Path ? "path" : "whitted");
        EXPECT_LT(seen, 1.0);
    }
}

TEST(MetalRoughnessRender, PolishedMetalMirrorsTheEnvironmentInBothIntegrators) {
    // Whitted takes a mirror bounce below kMirrorRoughness; the path tracer samples the sharp lobe.
    const pnb::Renderer r = quietRenderer();
    const pnb::PreparedScene p = r.prepare(furnace(0.f));
    for (pnb::IntegratorKind k : kBoth)
        EXPECT_NEAR(meanRed(r.render(p, frontCamera(), furnaceSettings(k))), 1.0, 0.01)
            << (k == pnb::IntegratorKind::Path ? "path" : "whitted");
}

TEST(MetalRoughnessRender, BothAcceleratorsRenderTheSameImage) {
    const pnb::Renderer r = quietRenderer();
    pnb::Scene s = furnace(0.3f);
    pnb::Material red;
    red.kind = pnb::MaterialKind::MetalRoughness;
    red.baseColor = {0.8f, 0.1f, 0.1f};
    red.metallic = 0.f;
    red.roughness = 0.6f;
    s.addPlane({0, -1, 0}, {0, 1, 0}, s.addMaterial(red));
    pnb::Camera cam;
    cam.eye = {0, 1, 5};
    cam.lookAt = {0, 0, 0};
    for (pnb::IntegratorKind k : kBoth) {
        pnb::RenderSettings st = furnaceSettings(k);
        st.width = st.height = 24;
        st.spp = 4;
        pnb::PrepareOptions embree, naive;
        naive.accelerator = pnb::AcceleratorKind::Naive;
        const pnb::Framebuffer a = r.render(r.prepare(s, embree), cam, st);
        const pnb::Framebuffer b = r.render(r.prepare(s, naive), cam, st);
        int differ = 0;
        for (int y = 0; y < st.height; ++y)
            for (int x = 0; x < st.width; ++x) {
                const pnb::Color ca = a.pixel(x, y), cb = b.pixel(x, y);
                differ += std::fabs(ca.r - cb.r) + std::fabs(ca.g - cb.g) + std::fabs(ca.b - cb.b) > 1e-4f;
            }
        EXPECT_EQ(differ, 0);
    }
}

namespace {

// A 2 x 1 linear image (PFM): left texel `left`, right texel `right`.
fs::path writeTexture(const fs::path& path, float left, float right) {
    std::string bytes = "PF\n2 1\n-1.0\n";
    const float px[6] = {left, left, left, right, right, right};
    bytes.append(reinterpret_cast<const char*>(px), sizeof px);
    return penumbra::test::writeFile(path, bytes);
}

// A unit square emitter facing down at height 1 (uvs across it), over a white
// Lambertian floor; the emitter's material is `lamp`.
pnb::Scene lampOverFloor(const pnb::Material& lamp) {
    pnb::Scene s;
    pnb::Material floor;
    floor.kd = pnb::gray(1.f);
    s.addPlane({0, 0, 0}, {0, 1, 0}, s.addMaterial(floor));
    static const float pos[] = {-0.5f, 1, -0.5f, 0.5f, 1, -0.5f, 0.5f, 1, 0.5f, -0.5f, 1, 0.5f};
    static const float uvs[] = {0, 0, 1, 0, 1, 1, 0, 1};
    static const uint32_t idx[] = {0, 1, 2, 0, 2, 3};  // facing down
    pnb::MeshDesc d;
    d.positions = pos;
    d.vertexCount = 4;
    d.indices = idx;
    d.triangleCount = 2;
    d.uvs = uvs;
    d.material = s.addMaterial(lamp);
    s.addMesh(d);
    s.setDefaultLight(false);
    return s;
}

pnb::Camera below(float vfov) {
    pnb::Camera c;
    c.eye = {0, 0.01f, 0};
    c.lookAt = {0, 1, 0};
    c.up = {0, 0, 1};
    c.vfovDegrees = vfov;
    return c;
}

pnb::Camera above() {
    pnb::Camera c;
    c.eye = {0, 0.9f, 0};
    c.lookAt = {0, 0, 0};
    c.up = {0, 0, -1};
    c.vfovDegrees = 60.f;
    return c;
}

}  // namespace

TEST(MetalRoughnessRender, TexturedEmissionIsSeenAndLightsAsItsTextureSays) {
    const fs::path dir = penumbra::test::tempDir();
    const pnb::Renderer r = quietRenderer();
    pnb::Material grey;
    grey.kd = pnb::gray(0.f);
    grey.ke = pnb::gray(1.f);
    grey.emissiveTexture.path = writeTexture(dir / "grey.pfm", 0.5f, 0.5f).string();
    pnb::Material half = grey;
    half.emissiveTexture.path.clear();
    half.ke = pnb::gray(0.5f);
    pnb::Material split = grey;
    split.emissiveTexture.path = writeTexture(dir / "split.pfm", 1.f, 0.f).string();
    split.emissiveTexture.filter = pnb::TextureFilter::Nearest;
    const pnb::PreparedScene textured = r.prepare(lampOverFloor(grey));
    const pnb::PreparedScene plain = r.prepare(lampOverFloor(half));
    for (pnb::IntegratorKind k : kBoth) {
        pnb::RenderSettings st = furnaceSettings(k);
        st.width = st.height = 8;
        st.spp = 64;
        // The floor under a texture of 0.5 gets what it gets under emission 0.5:
        // light samples carry the texture, and hits on the emitter see it.
        const double a = meanRed(r.render(textured, above(), st)), b = meanRed(r.render(plain, above(), st));
        EXPECT_GT(b, 0.05);
        EXPECT_NEAR(a / b, 1.0, 0.02) << (k == pnb::IntegratorKind::Path ? "path" : "whitted");
        // Seen from below, the left half of the texture is lit and the right half dark.
        st.spp = 1;
        const pnb::Framebuffer seen = r.render(r.prepare(lampOverFloor(split)), below(20.f), st);
        for (int y = 0; y < st.height; ++y) {
            float left = 0.f, right = 0.f;
            for (int x = 0; x < st.width / 2; ++x) {
                left += seen.pixel(x, y).r;
                right += seen.pixel(st.width - 1 - x, y).r;
            }
            EXPECT_TRUE((left > 3.5f && right < 0.01f) || (right > 3.5f && left < 0.01f)) << left << " " << right;
        }
    }
}
