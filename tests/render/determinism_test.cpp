// Bit-identical films for any thread count, tile size, pass split and crop.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/log.h"
#include "shading/renderer.h"

using namespace penumbra;

namespace {

Logger quietLogger() { return Logger([](LogLevel, std::string_view) {}, LogLevel::Error); }

// A small room with an area light, a mirror sphere, a box and a point light.
Scene testScene() {
    Scene s;
    Material white;
    white.kd = Rgb(0.7f);
    Material red;
    red.kd = Rgb(0.7f, 0.1f, 0.1f);
    red.ks = Rgb(0.2f);
    red.exponent = 30.f;
    Material mirror;
    mirror.kd = Rgb(0.f);
    mirror.kr = Rgb(0.9f);
    Material light;
    light.kd = Rgb(0.f);
    light.ke = Rgb(8.f);
    s.materials = {white, red, mirror, light};
    s.planes.push_back(Plane{Vec3f{0, 0, 0}, Vec3f{0, 1, 0}, true, 0});
    s.rectangles.push_back(Rectangle{Vec3f{-2, 0, -2}, Vec3f{4, 0, 0}, Vec3f{0, 3, 0}, 1});  // back wall
    s.spheres.push_back(Sphere{Vec3f{-0.6f, 0.5f, 0}, 0.5f, 2});
    s.boxes.push_back(makeBox(Vec3f{0.2f, 0, -0.3f}, Vec3f{0.9f, 0.8f, 0.4f}, Transform::rotate(20.f, Vec3f{0, 1, 0}), 0));
    s.rectangles.push_back(Rectangle{Vec3f{-0.5f, 2.5f, -0.5f}, Vec3f{1, 0, 0}, Vec3f{0, 0, 1}, 3});
    s.pointLights.push_back(PointLight{Vec3f{1.5f, 2.f, 1.5f}, Rgb(1.f)});
    return s;
}

CameraDesc testCamera() {
    CameraDesc c;
    c.eye = Vec3f{0, 1.2f, 4.f};
    c.lookAt = Vec3f{0, 0.8f, 0};
    c.vfovDegrees = 45.f;
    return c;
}

RenderSettings testSettings() {
    RenderSettings st;
    st.width = 48;
    st.height = 36;
    st.spp = 9;
    st.lightSamples = 4;
    st.seed = 7;
    return st;
}

bool sameFilm(const Film& a, const Film& b) {
    std::vector<float> x = a.radianceBuffer(), y = b.radianceBuffer();
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(float)) == 0;
}

}  // namespace

class Determinism : public ::testing::Test {
protected:
    static void SetUpTestSuite() { prepared_ = new PreparedScene(testScene(), {}, quietLogger()); }
    static void TearDownTestSuite() {
        delete prepared_;
        prepared_ = nullptr;
    }
    static Film renderWith(RenderSettings st) {
        Film f = makeFilm(st);
        render(*prepared_, testCamera(), st, f);
        return f;
    }
    static PreparedScene* prepared_;
};
PreparedScene* Determinism::prepared_ = nullptr;

TEST_F(Determinism, SameImageForOneAndTwoThreadsAndAnyTileSize) {
    RenderSettings st = testSettings();
    st.threads = 1;
    st.tileSize = 16;
    Film one = renderWith(st);
    st.threads = 2;
    Film two = renderWith(st);
    st.tileSize = 5;
    Film oddTiles = renderWith(st);
    st.threads = 0;
    st.tileSize = 64;
    Film all = renderWith(st);
    EXPECT_TRUE(sameFilm(one, two));
    EXPECT_TRUE(sameFilm(one, oddTiles));
    EXPECT_TRUE(sameFilm(one, all));
    // And the image is not trivially black.
    double sum = 0;
    for (float v : one.radianceBuffer()) sum += v;
    EXPECT_GT(sum, 1.0);
}

TEST_F(Determinism, DifferentSeedsGiveDifferentNoise) {
    RenderSettings st = testSettings();
    Film a = renderWith(st);
    st.seed = 8;
    Film b = renderWith(st);
    EXPECT_FALSE(sameFilm(a, b));
}

TEST_F(Determinism, ProgressivePassesEqualOneShot) {
    RenderSettings st = testSettings();
    Film oneShot = renderWith(st);
    Film passes = makeFilm(st);
    renderPass(*prepared_, testCamera(), st, passes, 0, 2);
    renderPass(*prepared_, testCamera(), st, passes, 2, 3);
    EXPECT_FALSE(sameFilm(oneShot, passes));  // not converged yet
    renderPass(*prepared_, testCamera(), st, passes, 5, 4);
    EXPECT_EQ(passes.sampleCount(), 9u);
    EXPECT_TRUE(sameFilm(oneShot, passes));
}

TEST_F(Determinism, CropWindowsTileIntoTheFullFrame) {
    RenderSettings st = testSettings();
    Film full = renderWith(st);
    std::vector<float> fullPx = full.radianceBuffer();
    const CropWindow windows[] = {{0, 0, 20, 36}, {20, 0, 48, 17}, {20, 17, 48, 36}};
    for (const CropWindow& w : windows) {
        RenderSettings cs = st;
        cs.crop = w;
        Film part = renderWith(cs);
        std::vector<float> px = part.radianceBuffer();
        for (int y = w.y0; y < w.y1; ++y)
            for (int x = w.x0; x < w.x1; ++x)
                for (int c = 0; c < 3; ++c)
                    ASSERT_EQ(px[((y - w.y0) * (w.x1 - w.x0) + (x - w.x0)) * 3 + c], fullPx[(y * 48 + x) * 3 + c])
                        << "pixel " << x << "," << y;
    }
}

TEST_F(Determinism, CancelStopsTheRenderAndSaysSo) {
    RenderSettings st = testSettings();
    std::atomic<bool> cancel{true};
    RenderControl control;
    control.cancel = &cancel;
    Film f = makeFilm(st);
    PassResult stats = render(*prepared_, testCamera(), st, f, control);
    EXPECT_TRUE(stats.cancelled);
    EXPECT_EQ(f.sampleCount(), 0u);
}

TEST_F(Determinism, StatisticsCountRaysByKind) {
    RenderSettings st = testSettings();
    Film f = makeFilm(st);
    RenderStats stats = render(*prepared_, testCamera(), st, f).stats;
    EXPECT_EQ(stats.cameraRays, uint64_t(48 * 36 * 9));
    EXPECT_GT(stats.shadowRays, stats.cameraRays);   // several lights and samples per hit
    EXPECT_GT(stats.reflectionRays, 0u);             // the mirror sphere
    EXPECT_EQ(stats.nonFiniteSamples, 0u);
    EXPECT_EQ(stats.invalidRays, 0u);
}

// BRDF-sampled rays under MIS are closest-hit queries and are counted apart
// from the shadow rays (occlusion queries): MIS traces exactly the light
// samples' shadow rays that light sampling alone traces, and its BRDF samples
// besides (the glossy back wall takes them).
TEST_F(Determinism, StatisticsCountBrdfSampledRaysApartFromShadowRays) {
    RenderSettings st = testSettings();
    st.directLight = DirectLightSampling::Light;
    Film lightOnly = makeFilm(st);
    const RenderStats light = render(*prepared_, testCamera(), st, lightOnly).stats;
    st.directLight = DirectLightSampling::Mis;
    Film mis = makeFilm(st);
    const RenderStats both = render(*prepared_, testCamera(), st, mis).stats;
    EXPECT_EQ(light.brdfRays, 0u);
    EXPECT_EQ(both.shadowRays, light.shadowRays);
    EXPECT_GT(both.brdfRays, 0u);
    // At most (4 + 1) / 2 = 2 BRDF samples per shading point (camera and mirror hits).
    EXPECT_LE(both.brdfRays, 2 * (both.cameraRays + both.reflectionRays));
    EXPECT_EQ(both.totalRays(), both.cameraRays + both.shadowRays + both.reflectionRays + both.brdfRays);
}

// The same room with a glass ball, for both integrators: paths split (whitted)
// or are sampled (path) at the glass, and stay deterministic.
class GlassDeterminism : public ::testing::TestWithParam<IntegratorKind> {
protected:
    static void SetUpTestSuite() {
        Scene s = testScene();
        Material glass;
        glass.kd = Rgb(0.f);
        glass.kt = Rgb(0.95f, 0.95f, 0.9f);
        glass.ior = 1.5f;
        s.materials.push_back(glass);
        s.spheres.push_back(Sphere{Vec3f{0.4f, 1.3f, 0.6f}, 0.35f, uint32_t(s.materials.size() - 1)});
        prepared_ = new PreparedScene(std::move(s), {}, quietLogger());
    }
    static void TearDownTestSuite() {
        delete prepared_;
        prepared_ = nullptr;
    }
    RenderSettings settings() const {
        RenderSettings st = testSettings();
        st.integrator = GetParam();
        st.lightSamples = 2;
        return st;
    }
    static Film renderWith(RenderSettings st, RenderStats* stats = nullptr) {
        Film f = makeFilm(st);
        const PassResult r = render(*prepared_, testCamera(), st, f);
        if (stats) *stats = r.stats;
        return f;
    }
    static PreparedScene* prepared_;
};
PreparedScene* GlassDeterminism::prepared_ = nullptr;

TEST_P(GlassDeterminism, SameImageForAnyThreadCountTileSizeAndPassSplit) {
    RenderSettings st = settings();
    st.threads = 1;
    st.tileSize = 16;
    Film one = renderWith(st);
    st.threads = 2;
    st.tileSize = 5;
    Film two = renderWith(st);
    EXPECT_TRUE(sameFilm(one, two));
    Film passes = makeFilm(st);
    renderPass(*prepared_, testCamera(), st, passes, 0, 4);
    renderPass(*prepared_, testCamera(), st, passes, 4, 5);
    EXPECT_TRUE(sameFilm(one, passes));
    double sum = 0;
    for (float v : one.radianceBuffer()) sum += v;
    EXPECT_GT(sum, 1.0);
}

TEST_P(GlassDeterminism, StatisticsCountTransmissionAndPathLengths) {
    RenderStats stats;
    renderWith(settings(), &stats);
    EXPECT_EQ(stats.cameraRays, uint64_t(48 * 36 * 9));
    EXPECT_GT(stats.transmissionRays, 0u);  // the glass ball
    EXPECT_GT(stats.reflectionRays, 0u);
    EXPECT_GE(stats.pathLengthSum, stats.cameraRays);  // every path has its camera ray
    EXPECT_GE(stats.pathLengthMax, 3u);                // into the ball and out again at least
    EXPECT_LE(stats.pathLengthMax, uint32_t(settings().maxDepth + 1));
    if (GetParam() == IntegratorKind::Path) {
        EXPECT_GT(stats.indirectRays, 0u);  // diffuse bounces
        EXPECT_GT(double(stats.pathLengthSum) / double(stats.cameraRays), 2.0);
    } else {
        EXPECT_EQ(stats.indirectRays, 0u);
    }
    EXPECT_EQ(stats.nonFiniteSamples, 0u);
}

INSTANTIATE_TEST_SUITE_P(Integrators, GlassDeterminism, ::testing::Values(IntegratorKind::Whitted, IntegratorKind::Path),
                         [](const ::testing::TestParamInfo<IntegratorKind>& info) {
                             return std::string(info.param == IntegratorKind::Path ? "path" : "whitted");
                         });

// Embree and the naive loop find the same primitives; their hit distances may
// differ in the last bits, which moves shadow-ray origins and, with `path`,
// can send a path elsewhere: pixel values agree closely and the means agree.
TEST_P(GlassDeterminism, EmbreeAndNaiveAgree) {
    Scene s = testScene();
    Material glass;
    glass.kd = Rgb(0.f);
    glass.kt = Rgb(1.f);
    glass.ior = 1.5f;
    s.materials.push_back(glass);
    s.spheres.push_back(Sphere{Vec3f{0.4f, 1.3f, 0.6f}, 0.35f, uint32_t(s.materials.size() - 1)});
    PrepareOptions naive;
    naive.accelerator = AcceleratorKind::Naive;
    const PreparedScene withNaive(s, naive, quietLogger());
    const RenderSettings st = settings();
    Film b = makeFilm(st);
    render(withNaive, testCamera(), st, b);
    const PreparedScene withEmbree(std::move(s), {}, quietLogger());
    Film c = makeFilm(st);
    render(withEmbree, testCamera(), st, c);
    const std::vector<float> x = c.radianceBuffer(), y = b.radianceBuffer();
    double sx = 0, sy = 0;
    size_t same = 0;
    for (size_t i = 0; i < x.size(); ++i) {
        sx += x[i];
        sy += y[i];
        same += std::fabs(x[i] - y[i]) <= 1e-3f * std::max(1.f, std::fabs(y[i]));
    }
    EXPECT_NEAR(sx / sy, 1.0, 0.01);
    EXPECT_GT(double(same) / double(x.size()), GetParam() == IntegratorKind::Path ? 0.9 : 0.99)
        << "share of pixel values within 0.1%";
}

// The AOVs describe the first hit, whichever integrator shades it: identical for both.
TEST(IntegratorAovs, FirstHitAovsDoNotDependOnTheIntegrator) {
    const PreparedScene prepared(testScene(), {}, quietLogger());
    RenderSettings st = testSettings();
    st.aovs = true;
    Film whitted = makeFilm(st);
    render(prepared, testCamera(), st, whitted);
    st.integrator = IntegratorKind::Path;
    Film path = makeFilm(st);
    render(prepared, testCamera(), st, path);
    ASSERT_TRUE(path.hasAovs());
    size_t lit = 0;
    for (size_t i = 0; i < size_t(st.width * st.height); ++i) {
        EXPECT_EQ(whitted.albedo(i), path.albedo(i)) << i;
        EXPECT_EQ(whitted.depth(i), path.depth(i)) << i;
        lit += path.albedo(i).maxComponent() > 0.f;
    }
    EXPECT_GT(lit, size_t(st.width * st.height / 2));
}
