// The direct-light estimators of issue 15 against closed forms: a sphere
// light seen by a Lambertian point, a ball inside a closed emissive mesh, a
// glossy point inside a uniform emitter (all three estimators agree with the
// albedo integral), power selection under MIS, and noise that MIS lowers.
#include <gtest/gtest.h>

#include <cmath>

#include "core/log.h"
#include "core/multi_jitter.h"
#include "shading/path_integrator.h"
#include "shading/whitted_integrator.h"
#include "shading/bsdf/phong.h"
#include "shading/renderer.h"
#include "support/both_accelerators.h"

using namespace penumbra;

namespace {

Logger quietLogger() { return Logger([](LogLevel, std::string_view) {}, LogLevel::Error); }

uint32_t addMaterial(Scene& s, Material m) {
    s.materials.push_back(m);
    return uint32_t(s.materials.size() - 1);
}

Material emitter(float le, bool twoSided = false) {
    Material m;
    m.kd = Rgb(0.f);
    m.ke = Rgb(le);
    m.twoSidedEmission = twoSided;
    return m;
}

// The direct-light estimators: the public settings' two and the benchmark
// tools' baseline (InternalSettings::areaLightSamples).
enum class Estimator { Mis, Light, Area };

Rgb radianceAlong(const PreparedScene& ps, const Ray& ray, int lightSamples, Estimator mode,
                  uint32_t index = 0, LightSelection selection = LightSelection::All) {
    RenderSettings st;
    st.lightSamples = lightSamples;
    st.directLight = mode == Estimator::Mis ? DirectLightSampling::Mis : DirectLightSampling::Light;
    st.lightSelection = selection;
    InternalSettings internal;
    internal.areaLightSamples = mode == Estimator::Area;
    WhittedIntegrator integ({ps.scene(), ps.accelerator(), ps.lights(), ps.textures(), st, 0.f, internal});
    RayCounts counts;
    return integ.Li(ray, SampleKey{pixelSampleKey(7, 3), index}, counts, nullptr);
}

// Mean and standard deviation of the estimate over `runs` camera-sample indices.
struct Stats {
    double mean, sd;
};
Stats estimate(const PreparedScene& ps, const Ray& ray, int lightSamples, Estimator mode, int runs,
               LightSelection selection = LightSelection::All) {
    double s = 0, s2 = 0;
    for (int i = 0; i < runs; ++i) {
        const double v = radianceAlong(ps, ray, lightSamples, mode, uint32_t(i), selection).g;
        s += v;
        s2 += v * v;
    }
    const double mean = s / runs;
    return {mean, std::sqrt(std::max(0.0, s2 / runs - mean * mean))};
}

// A closed cube [-h, h]^3 facing inwards, each face split into split x split
// quads of two triangles (split 1: 12 triangles).
TriangleMesh insideOutCube(float h, uint32_t material, int split = 1) {
    TriangleMesh m;
    // Faces as (corner, edge a, edge b), a x b pointing inwards.
    const Vec3f faces[6][3] = {{{-h, -h, -h}, {2 * h, 0, 0}, {0, 2 * h, 0}},  {{-h, -h, h}, {0, 2 * h, 0}, {2 * h, 0, 0}},
                               {{-h, -h, -h}, {0, 0, 2 * h}, {2 * h, 0, 0}},  {{-h, h, -h}, {2 * h, 0, 0}, {0, 0, 2 * h}},
                               {{-h, -h, -h}, {0, 2 * h, 0}, {0, 0, 2 * h}},  {{h, -h, -h}, {0, 0, 2 * h}, {0, 2 * h, 0}}};
    for (const auto& f : faces)
        for (int i = 0; i < split; ++i)
            for (int j = 0; j < split; ++j) {
                const auto corner = [&](int di, int dj) {
                    return f[0] + f[1] * (float(i + di) / float(split)) + f[2] * (float(j + dj) / float(split));
                };
                const uint32_t base = uint32_t(m.positions.size());
                for (Vec3f p : {corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)}) m.positions.push_back(p);
                for (uint32_t v : {0u, 1u, 2u, 0u, 2u, 3u}) m.indices.push_back(base + v);
            }
    m.material = material;
    return m;
}

// A sharp glossy floor (y = 0) under a 4 x 4 rectangle light at y = 2 facing it.
Scene sharpGlossyFloorUnderALargeLight() {
    Scene s;
    Material g;
    g.kd = Rgb(0.05f);
    g.ks = Rgb(0.8f);
    g.exponent = 300.f;
    const uint32_t gm = addMaterial(s, g);
    const uint32_t lm = addMaterial(s, emitter(4.f));
    s.planes.push_back(Plane{Vec3f{0, 0, 0}, Vec3f{0, 1, 0}, true, gm});
    s.rectangles.push_back(Rectangle{Vec3f{-2, 2, -2}, Vec3f{4, 0, 0}, Vec3f{0, 0, 4}, lm});  // faces -y
    return s;
}

class DirectLightTest : public test::ForBothAccelerators {
protected:
    PrepareOptions prep() const {
        PrepareOptions o;
        o.accelerator = GetParam();
        return o;
    }
};

}  // namespace

TEST_P(DirectLightTest, LambertianPointFacingASphereLightMatchesTheClosedForm) {
    // E = pi L (r/d)^2 for a sphere wholly above the horizon; L_out = kd/pi E.
    Scene s;
    Material floor;
    floor.kd = Rgb(0.7f);
    const uint32_t fm = addMaterial(s, floor);
    const uint32_t lm = addMaterial(s, emitter(3.f));
    s.planes.push_back(Plane{Vec3f{0, 0, 0}, Vec3f{0, 1, 0}, true, fm});
    const float r = 0.8f, d = 2.f;
    s.spheres.push_back(Sphere{Vec3f{0, d, 0}, r, lm});
    PreparedScene ps(std::move(s), prep(), quietLogger());
    const Ray ray{Vec3f{0.3f, 0.5f, 0.f}, normalize(Vec3f{-0.3f, -0.5f, 0.f}), 0.f, kInfinity};
    const double expected = 0.7 * 3.0 * (r / d) * (r / d);
    for (Estimator mode : {Estimator::Mis, Estimator::Light}) {
        const Stats st = estimate(ps, ray, 64, mode, 64);
        EXPECT_NEAR(st.mean, expected, 0.002 * expected);
    }
    // Cone sampling leaves only the cosine's variation: far less noise than area sampling.
    const Stats cone = estimate(ps, ray, 4, Estimator::Light, 256);
    const Stats area = estimate(ps, ray, 4, Estimator::Area, 256);
    EXPECT_NEAR(area.mean, expected, 4.0 * area.sd / 16.0);  // 4 standard errors
    EXPECT_LT(cone.sd, 0.25 * area.sd) << "cone sd " << cone.sd << ", area sd " << area.sd;
}

TEST_P(DirectLightTest, BallInsideAClosedEmissiveMeshReflectsKdTimesLe) {
    // Every direction above the ball's tangent plane reaches the emitting
    // cube, so L = kd Le exactly; area sampling was off by +-3% at 1024 samples.
    // 12 triangles: BRDF samples test the light's triangles first (at most
    // LightSet::kMaxTestedEmitters); 48: they take closest-hit queries.
    for (int split : {1, 2}) {
        Scene s;
        Material ball;
        ball.kd = Rgb(0.6f);
        const uint32_t bm = addMaterial(s, ball);
        const uint32_t lm = addMaterial(s, emitter(2.f));
        s.spheres.push_back(Sphere{Vec3f{0.3f, -0.2f, 0.1f}, 1.f, bm});
        s.meshes.push_back(insideOutCube(3.f, lm, split));
        PreparedScene ps(std::move(s), prep(), quietLogger());
        ASSERT_EQ(ps.lights().size(), 1u);
        ASSERT_EQ(ps.lights().emittersTestable(), split == 1);
        for (Vec3f dir : {Vec3f{0, -1, 0}, normalize(Vec3f{1, -1, 0.5f}), normalize(Vec3f{-0.2f, 0.3f, -1.f})}) {
            const Ray ray{Vec3f{0.3f, -0.2f, 0.1f} - 2.5f * dir, dir, 0.f, kInfinity};
            const Rgb L = radianceAlong(ps, ray, 1024, Estimator::Mis);
            EXPECT_NEAR(L.g, 1.2f, 0.003f * 1.2f)
                << "split " << split << ", direction " << dir.x << "," << dir.y << "," << dir.z;
        }
    }
}

TEST_P(DirectLightTest, BrdfSamplesStopAtWhatLiesInFrontOfTheLight) {
    // A sharp glossy floor under a large light, seen near the mirror
    // direction (most of its light comes from BRDF samples). A box just under
    // the light that covers it as seen from the point leaves no light at all;
    // one that covers half of it leaves what light samples alone estimate.
    for (float cover : {1.f, 0.5f}) {
        Scene s = sharpGlossyFloorUnderALargeLight();
        const uint32_t bm = addMaterial(s, Material{});
        s.boxes.push_back(makeBox(Vec3f{-3, 1.8f, -3}, Vec3f{-3 + 6 * cover, 1.9f, 3}, Transform(), bm));
        PreparedScene ps(std::move(s), prep(), quietLogger());
        const Ray ray{Vec3f{-1.f, 1.f, 0.f}, normalize(Vec3f{1.f, -1.f, 0.f}), 0.f, kInfinity};
        if (cover == 1.f) {
            for (uint32_t i = 0; i < 8; ++i)
                EXPECT_EQ(radianceAlong(ps, ray, 16, Estimator::Mis, i).g, 0.f) << "camera sample " << i;
            continue;
        }
        const Stats mis = estimate(ps, ray, 16, Estimator::Mis, 128);
        const Stats light = estimate(ps, ray, 256, Estimator::Light, 64);
        ASSERT_GT(mis.mean, 0.05);
        EXPECT_NEAR(mis.mean, light.mean, 4.0 * std::hypot(mis.sd / std::sqrt(128.0), light.sd / 8.0))
            << "mis " << mis.mean << " +- " << mis.sd << ", light " << light.mean << " +- " << light.sd;
    }
}

TEST_P(DirectLightTest, EstimatorsAgreeOnAGlossyPointInsideAUniformEmitter) {
    // A glossy, partly diffuse point inside a two-sided emissive sphere of
    // radiance Le reflects Le times its directional albedo, integrated here
    // on a fine grid; MIS must weigh light and BRDF samples to exactly that.
    for (PhongModel model : {PhongModel::Normalized, PhongModel::Classic}) {
        Scene s;
        Material g;
        g.kd = Rgb(0.2f);
        g.ks = Rgb(0.5f);
        g.exponent = 40.f;
        g.model = model;
        const uint32_t gm = addMaterial(s, g);
        const uint32_t lm = addMaterial(s, emitter(1.5f, true));
        s.planes.push_back(Plane{Vec3f{0, 0, 0}, Vec3f{0, 1, 0}, false, gm});
        s.spheres.push_back(Sphere{Vec3f{0, 0, 0}, 50.f, lm});
        PreparedScene ps(std::move(s), prep(), quietLogger());
        const Vec3f wo = normalize(Vec3f{0.6f, 1.f, 0.f});
        const Ray ray{2.f * wo, -wo, 0.f, kInfinity};
        double albedo = 0;
        const int T = 1024, P = 2048;
        for (int t = 0; t < T; ++t)
            for (int p = 0; p < P; ++p) {
                const double th = (t + 0.5) * (M_PI / 2) / T, ph = (p + 0.5) * 2 * M_PI / P;
                const Vec3f wi{float(std::sin(th) * std::cos(ph)), float(std::cos(th)), float(std::sin(th) * std::sin(ph))};
                albedo += phongResponse(g, g.kd, Vec3f{0, 1, 0}, wo, wi, false).g * std::sin(th) * (M_PI / 2 / T) *
                          (2 * M_PI / P);
            }
        const double expected = 1.5 * albedo;
        for (Estimator mode : {Estimator::Mis, Estimator::Light, Estimator::Area}) {
            const Stats st = estimate(ps, ray, 256, mode, 16);
            // Within 4 standard errors (the light-only estimators are noisy on a glossy lobe) and 1%.
            EXPECT_NEAR(st.mean, expected, std::min(0.01 * expected, 4.0 * st.sd / 4.0))
                << "mode " << int(mode) << ", model " << int(model) << ", sd " << st.sd;
        }
        const Stats power = estimate(ps, ray, 256, Estimator::Mis, 16, LightSelection::Power);
        EXPECT_NEAR(power.mean, expected, 0.003 * expected) << "power selection";
    }
}

// A point on the wall of a closed box that emits Le on both sides and reflects
// with albedo a sees Le + a Le (less the 0.2% of its cosine-weighted
// hemisphere a ball hides): the point lies in the plane of two of the light's
// own triangles, where solid-angle picks degenerate; uniform-area samples (the
// benchmark tools' baseline) must get it right too.
TEST_P(DirectLightTest, APointOnTheLightItselfIsLitExactlyByEveryEstimator) {
    constexpr float kLe = 1.f, kA = 0.5f;
    Scene s;
    Material walls;
    walls.kd = Rgb(kA);
    walls.ke = Rgb(kLe);
    walls.twoSidedEmission = true;
    Material ball;
    ball.kd = Rgb(0.6f);
    const uint32_t wm = addMaterial(s, walls), bm = addMaterial(s, ball);
    TriangleMesh box;
    for (Vec3f p : {Vec3f{-10, -10, -10}, Vec3f{10, -10, -10}, Vec3f{10, 10, -10}, Vec3f{-10, 10, -10},
                    Vec3f{-10, -10, 10}, Vec3f{10, -10, 10}, Vec3f{10, 10, 10}, Vec3f{-10, 10, 10}})
        box.positions.push_back(p);
    box.indices = {0, 1, 2, 0, 2, 3, 5, 4, 7, 5, 7, 6, 4, 0, 3, 4, 3, 7, 1, 5, 6, 1, 6, 2, 3, 2, 6, 3, 6, 7, 4, 5, 1, 4, 1, 0};
    box.material = wm;
    s.meshes.push_back(box);
    s.spheres.push_back(Sphere{Vec3f{0, 0, 0}, 0.5f, bm});
    PreparedScene ps(std::move(s), prep(), quietLogger());
    // On the diagonal the wall's two triangles share, at (5, 5, -10).
    const Ray ray{Vec3f{5, 5, 0}, Vec3f{0, 0, -1}, 0.f, kInfinity};
    const double expected = kLe * (1 + kA);
    for (Estimator mode : {Estimator::Mis, Estimator::Light, Estimator::Area}) {
        const Stats st = estimate(ps, ray, 4, mode, 1024);
        EXPECT_NEAR(st.mean, expected, std::max(0.006 * expected, 4.0 * st.sd / 32.0)) << "mode " << int(mode);
    }
}

// Issue 43: two sphere lights of radiance 3e38 emit more than the largest
// float; their float powers summed to infinity, every selection probability
// was inf / inf, and with power selection nothing was ever picked (a black
// image). A Lambertian point below both: L = 2 kd Le (r/d)^2 cos(theta) per the
// sphere's closed form, with both integrators.
TEST_P(DirectLightTest, PowerSelectionPicksLightsBrighterThanTheFloatRange) {
    Scene s;
    Material floor;
    floor.kd = Rgb(0.5f);
    const uint32_t fm = addMaterial(s, floor);
    const uint32_t lm = addMaterial(s, emitter(3e38f));
    s.planes.push_back(Plane{Vec3f{0, 0, 0}, Vec3f{0, 1, 0}, true, fm});
    const float r = 0.5f;  // each emits 3e38 * 4 pi r^2 * pi = 3e39
    s.spheres.push_back(Sphere{Vec3f{-1, 2, 0}, r, lm});
    s.spheres.push_back(Sphere{Vec3f{1, 2, 0}, r, lm});
    PreparedScene ps(std::move(s), prep(), quietLogger());
    const Ray ray{Vec3f{0.f, 1.f, 1.f}, normalize(Vec3f{0.f, -1.f, -1.f}), 0.f, kInfinity};
    const double d2 = 5.0, cosTheta = 2.0 / std::sqrt(5.0);
    const double expected = 2.0 * 0.5 * 3e38 * (double(r) * r / d2) * cosTheta;
    // 4 light samples per point (the default): their sum, before it is divided by 4, stays a float.
    const Stats whitted = estimate(ps, ray, 4, Estimator::Mis, 64, LightSelection::Power);
    EXPECT_NEAR(whitted.mean, expected, 0.01 * expected);
    RenderSettings st;
    st.lightSamples = 4;
    st.lightSelection = LightSelection::Power;
    st.integrator = IntegratorKind::Path;
    st.maxDepth = 1;  // direct light only
    const PathIntegrator path({ps.scene(), ps.accelerator(), ps.lights(), ps.textures(), st});
    double sum = 0;
    for (uint32_t i = 0; i < 64; ++i) {
        RayCounts counts;
        sum += path.Li(ray, SampleKey{pixelSampleKey(7, 3), i}, counts).g;
    }
    EXPECT_NEAR(sum / 64, expected, 0.01 * expected);
}

TEST_P(DirectLightTest, MisLowersTheNoiseOfASharpHighlightOfALargeLight) {
    // A sharp glossy floor under a large rectangle light seen near the mirror
    // direction: light samples rarely land in the lobe, BRDF samples do.
    Scene s = sharpGlossyFloorUnderALargeLight();
    PreparedScene ps(std::move(s), prep(), quietLogger());
    const Ray ray{Vec3f{-1.f, 1.f, 0.f}, normalize(Vec3f{1.f, -1.f, 0.f}), 0.f, kInfinity};
    const Stats mis = estimate(ps, ray, 4, Estimator::Mis, 256);
    const Stats light = estimate(ps, ray, 4, Estimator::Light, 256);
    const Stats ref = estimate(ps, ray, 256, Estimator::Mis, 32);
    EXPECT_NEAR(mis.mean, ref.mean, 4.0 * mis.sd / 16.0);  // 4 standard errors
    EXPECT_NEAR(light.mean, ref.mean, 4.0 * light.sd / 16.0);
    EXPECT_LT(mis.sd, 0.5 * light.sd) << "mis sd " << mis.sd << ", light-only sd " << light.sd;
}

TEST_P(DirectLightTest, GlossyPointsTakeBrdfSamplesOnlyUnderALightLargeForTheirLobe) {
    // A glossy floor seen so that it mirrors a small lamp 4 above it (0.2 x 0.2:
    // about 0.002 sr). For a cos^40 lobe the lamp is small (the sampling pdf
    // peaks near 4 per sr: large lights subtend more than 0.08 sr): MIS takes
    // no BRDF samples and its estimate is the light samples' alone, bit for
    // bit. For a cos^4000 lobe it is large (above 0.0008 sr), and the BRDF
    // samples find it.
    for (float exponent : {40.f, 4000.f}) {
        Scene s;
        Material g;
        g.kd = Rgb(0.3f);
        g.ks = Rgb(0.5f);
        g.exponent = exponent;
        const uint32_t gm = addMaterial(s, g);
        const uint32_t lm = addMaterial(s, emitter(100.f));
        s.planes.push_back(Plane{Vec3f{0, 0, 0}, Vec3f{0, 1, 0}, true, gm});
        s.rectangles.push_back(Rectangle{Vec3f{0.9f, 4, -0.1f}, Vec3f{0.2f, 0, 0}, Vec3f{0, 0, 0.2f}, lm});
        PreparedScene ps(std::move(s), prep(), quietLogger());
        // From (-0.25, 1, 0) to the origin: the mirror direction points at the lamp's centre (1, 4, 0).
        const Ray ray{Vec3f{-0.25f, 1.f, 0.f}, normalize(Vec3f{0.25f, -1.f, 0.f}), 0.f, kInfinity};
        uint64_t brdfRays = 0;
        for (uint32_t i = 0; i < 32; ++i) {
            RenderSettings st;
            st.lightSamples = 4;
            st.directLight = DirectLightSampling::Mis;
            WhittedIntegrator mis({ps.scene(), ps.accelerator(), ps.lights(), ps.textures(), st});
            RayCounts counts;
            const Rgb both = mis.Li(ray, SampleKey{pixelSampleKey(7, 3), i}, counts, nullptr);
            brdfRays += counts.brdf;
            if (exponent == 40.f) {
                EXPECT_EQ(both.g, radianceAlong(ps, ray, 4, Estimator::Light, i).g) << "camera sample " << i;
            }
        }
        if (exponent == 40.f) {
            EXPECT_EQ(brdfRays, 0u);
        } else {
            EXPECT_GT(brdfRays, 0u);
        }
    }
}

PENUMBRA_FOR_BOTH_ACCELERATORS(DirectLightTest);
