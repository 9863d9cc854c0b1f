// The environment light: its importance sampling agrees with its pdf (a
// chi-square test over bins on the sphere), the pdf integrates to 1, the
// mapping puts a known texel where docs/rendering.md says, and LightSet finds it.
//
// Two chi-square tests: a local one whose bins follow the texels exactly (so
// the expected counts are exact), and the shared tests/support/chi_square.h
// one (bins about +z, the pdf integrated numerically).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/error.h"
#include "core/multi_jitter.h"
#include "core/sampling.h"
#include "lights/environment_light.h"
#include "lights/light_lanes.h"
#include "lights/light_set.h"
#include "support/chi_square.h"

using namespace penumbra;

namespace {

// Upper quantile of the chi-square distribution with k degrees of freedom for
// a normal quantile z (Wilson-Hilferty; good to a few percent for k >= 10).
double chiSquareQuantile(int k, double z) {
    const double a = 2.0 / (9.0 * k);
    return k * std::pow(1.0 - a + z * std::sqrt(a), 3.0);
}

struct ChiSquare {
    double statistic = 0;
    int dof = 0;
};

// Pearson's statistic of observed against expected counts; bins expecting
// fewer than 5 are pooled (as pbrt's and Mitsuba's tests do).
ChiSquare chiSquare(const std::vector<double>& observed, const std::vector<double>& expected) {
    ChiSquare r;
    double pooledObs = 0, pooledExp = 0;
    int bins = 0;
    for (size_t i = 0; i < observed.size(); ++i) {
        if (expected[i] < 5.0) {
            pooledObs += observed[i];
            pooledExp += expected[i];
            continue;
        }
        const double d = observed[i] - expected[i];
        r.statistic += d * d / expected[i];
        ++bins;
    }
    if (pooledExp > 0) {
        const double d = pooledObs - pooledExp;
        r.statistic += d * d / std::max(pooledExp, 1.0);
        ++bins;
    }
    r.dof = bins - 1;
    return r;
}

// A 16 x 8 image with smooth variation, a bright texel and black texels.
RgbImage testImage() {
    RgbImage img;
    img.width = 16;
    img.height = 8;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            float v = 0.2f + float((x * 5 + y * 3) % 7);
            if (x == 3 && y == 5) v = 60.f;
            if (x >= 10 && x < 12 && y == 2) v = 0.f;
            img.pixels.push_back(Rgb{v, 0.5f * v, 2.f * v});
        }
    return img;
}

// World polar angle from +y and azimuth atan2(x, -z) in [0, 2 pi).
void angles(const Vec3f& d, double& theta, double& phi) {
    theta = std::acos(std::clamp(double(d.y), -1.0, 1.0));
    phi = std::atan2(double(d.x), -double(d.z));
    if (phi < 0) phi += 2 * M_PI;
}

Vec3f direction(double theta, double phi) {
    return Vec3f{float(std::sin(theta) * std::sin(phi)), float(std::cos(theta)), float(-std::sin(theta) * std::cos(phi))};
}

// Integral of light.pdf over the sphere region [t0, t1] x [p0, p1], midpoint rule.
double integratePdf(const EnvironmentLight& light, double t0, double t1, double p0, double p1, int n) {
    double sum = 0;
    const double dt = (t1 - t0) / n, dp = (p1 - p0) / n;
    for (int i = 0; i < n; ++i) {
        const double t = t0 + (i + 0.5) * dt;
        for (int j = 0; j < n; ++j) sum += light.pdf(direction(t, p0 + (j + 0.5) * dp)) * std::sin(t);
    }
    return sum * dt * dp;
}

}  // namespace

TEST(EnvironmentLight, ImageSamplingPassesChiSquareAgainstItsPdf) {
    // Rotated by 90 degrees: a quarter of the 16 columns, so the texels stay
    // aligned with the 32 x 16 bins and the binned pdf integrals are exact
    // (p / sin(theta) times sin(theta) is constant inside a texel).
    const EnvironmentLight light(testImage(), 1.f, 90.f, 1.f);
    const int nt = 16, np = 32;
    const int samples = 400000;
    std::vector<double> observed(size_t(nt * np), 0.0), expected(size_t(nt * np), 0.0);
    int mismatched = 0;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> uni(0.f, 1.f);
    for (int k = 0; k < samples; ++k) {
        const Vec2f u{std::min(uni(rng), 0.99999994f), std::min(uni(rng), 0.99999994f)};
        const auto ls = light.sample(Vec3f{1, 2, 3}, u);
        if (!ls) continue;
        ASSERT_NEAR(length(ls->wi), 1.f, 1e-5f);
        ASSERT_TRUE(std::isinf(ls->distance));
        ASSERT_FALSE(ls->delta);
        // The sample's pdf and radiance are what pdf() and radiance() say of its
        // direction (but for rounding onto a neighbouring texel at an edge).
        if (std::fabs(ls->pdf - light.pdf(ls->wi)) > 2e-3f * ls->pdf || !(ls->L == light.radiance(ls->wi))) ++mismatched;
        double t, p;
        angles(ls->wi, t, p);
        const int it = std::min(int(t / M_PI * nt), nt - 1), ip = std::min(int(p / (2 * M_PI) * np), np - 1);
        observed[size_t(it * np + ip)] += 1;
    }
    double total = 0;
    for (int i = 0; i < nt; ++i)
        for (int j = 0; j < np; ++j) {
            const double e = integratePdf(light, M_PI * i / nt, M_PI * (i + 1) / nt, 2 * M_PI * j / np,
                                          2 * M_PI * (j + 1) / np, 8);
            expected[size_t(i * np + j)] = e * samples;
            total += e;
        }
    EXPECT_NEAR(total, 1.0, 1e-3);
    EXPECT_LT(mismatched, samples / 10000);
    // The black texels (2 columns of row 2) are never sampled.
    const ChiSquare c = chiSquare(observed, expected);
    ASSERT_GT(c.dof, 100);
    EXPECT_LT(c.statistic, chiSquareQuantile(c.dof, 3.09)) << "dof " << c.dof;  // significance 0.001
}

namespace {

// The shared chi-square test of a light's samples against a density.
template <class Pdf>
void expectSamplesFollow(const Light& light, Pdf pdf, uint32_t seed) {
    test::ChiSquareOptions options;
    options.samples = 300000;
    const MultiJitterSet set(options.samples, seed);
    const auto result = test::chiSquareDirections(
        [&](uint32_t i) -> std::optional<Vec3f> {
            const auto ls = light.sample(Vec3f{}, set.sample(i));
            if (!ls) return std::nullopt;
            return ls->wi;
        },
        [&](const Vec3f& w) { return double(pdf(w)); }, options);
    EXPECT_TRUE(result.passed) << result.message;
    EXPECT_NEAR(result.pdfIntegral, 1.0, 2e-3);
}

}  // namespace

TEST(EnvironmentLight, ImageSamplingPassesTheSharedChiSquareTest) {
    const EnvironmentLight light(testImage(), 1.f, 37.f, 1.f);
    expectSamplesFollow(light, [&](const Vec3f& w) { return light.pdf(w); }, 11);
}

// The compensated map's samples follow Lookup::misPdf.
TEST(EnvironmentLight, MisSampledPassesTheSharedChiSquareTest) {
    const EnvironmentLight light(testImage(), 1.f, 37.f, 1.f);
    expectSamplesFollow(light.misSampled(), [&](const Vec3f& w) { return light.lookup(w).misPdf; }, 13);
}

TEST(EnvironmentLight, PdfIntegratesToOneOverTheSphere) {
    for (float rotate : {0.f, 37.f, -150.f}) {
        const EnvironmentLight image(testImage(), 2.f, rotate, 1.f);
        // A grid not aligned with the texels: the error is the texel edges'.
        EXPECT_NEAR(integratePdf(image, 0, M_PI, 0, 2 * M_PI, 1024), 1.0, 2e-3) << rotate;
    }
    const EnvironmentLight constant(Rgb{0.5f, 1.f, 2.f}, 1.f);
    EXPECT_NEAR(integratePdf(constant, 0, M_PI, 0, 2 * M_PI, 64), 1.0, 1e-3);
}

TEST(EnvironmentLight, EstimatesOfTheIncidentIntegralMatchTheImage) {
    // E[L / pdf] over light samples = integral of L over the sphere = 4 pi * mean.
    const EnvironmentLight light(testImage(), 0.5f, 20.f, 1.f);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> uni(0.f, 1.f);
    double sum = 0;
    const int n = 200000;
    for (int k = 0; k < n; ++k) {
        const auto ls = light.sample(Vec3f{}, Vec2f{std::min(uni(rng), 0.99999994f), std::min(uni(rng), 0.99999994f)});
        if (ls) sum += ls->L.g / ls->pdf;
    }
    EXPECT_NEAR(sum / n / (4 * M_PI), light.meanRadiance().g, 0.01 * light.meanRadiance().g);
}

// misSampled() leaves the image's darker parts to BSDF samples: alone it
// misses them, but one of its samples and one uniform "BSDF" sample combined
// by the power heuristic (its pdf from Lookup::misPdf, as DirectLight::escape
// takes it) estimate the integral of L over the sphere without bias.
TEST(EnvironmentLight, MisSampledWithBsdfSamplesEstimatesTheIncidentIntegral) {
    const EnvironmentLight light(testImage(), 0.5f, 20.f, 1.f);
    const Light& mis = light.misSampled();
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> uni(0.f, 1.f);
    const auto u01 = [&] { return std::min(uni(rng), 0.99999994f); };
    const double bsdfPdf = 1.0 / (4 * M_PI);
    double combined = 0, alone = 0;
    int darkDirections = 0;
    const int n = 200000;
    for (int k = 0; k < n; ++k) {
        if (const auto ls = mis.sample(Vec3f{}, Vec2f{u01(), u01()})) {
            const EnvironmentLight::Lookup seen = light.lookup(ls->wi);
            ASSERT_NEAR(seen.misPdf, ls->pdf, 2e-3f * ls->pdf);
            ASSERT_EQ(seen.L, ls->L);
            const double p = ls->pdf;
            combined += ls->L.g / p * (p * p / (p * p + bsdfPdf * bsdfPdf));
            alone += ls->L.g / p;
        }
        const Vec3f wb = squareToUniformSphere(Vec2f{u01(), u01()});
        const EnvironmentLight::Lookup e = light.lookup(wb);
        if (!(e.misPdf > 0.f)) ++darkDirections;
        const double p = e.misPdf;
        combined += e.L.g / bsdfPdf * (bsdfPdf * bsdfPdf / (p * p + bsdfPdf * bsdfPdf));
    }
    const double truth = 4 * M_PI * light.meanRadiance().g;
    EXPECT_NEAR(combined / n, truth, 0.01 * truth);
    EXPECT_GT(darkDirections, n / 10);       // much of the image lies below its mean...
    EXPECT_LT(alone / n, 0.97 * truth);      // ...and the light samples alone miss it
}

TEST(EnvironmentLight, ASingleBrightTexelIsSampledWhereTheMappingSays) {
    // 64 x 32, the bright texel at the image centre: u in [0.5, 0.516), v in
    // [0.5, 0.531), i.e. just below the horizon, just right of straight ahead
    // (-z, towards +x). docs/rendering.md: u = 0.5 looks along -z, +x at u = 0.75.
    RgbImage img;
    img.width = 64;
    img.height = 32;
    img.pixels.assign(64 * 32, Rgb(1e-4f));
    img.pixels[16 * 64 + 32] = Rgb(1000.f);
    for (float rotate : {0.f, 90.f}) {
        const EnvironmentLight light(img, 3.f, rotate, 1.f);
        int inTexel = 0;
        const int n = 4096;
        for (int k = 0; k < n; ++k) {
            const auto ls = light.sample(Vec3f{}, Vec2f{(k % 64 + 0.5f) / 64.f, (k / 64 + 0.5f) / 64.f});
            ASSERT_TRUE(ls.has_value());
            const Vec3f d = ls->wi;
            // Rotating 90 degrees about +y (counter-clockwise from above) takes -z to -x and +x to -z.
            const bool there = rotate == 0.f ? (d.z < -0.98f && d.x >= 0.f && d.y <= 0.f)
                                             : (d.x < -0.98f && d.z <= 0.f && d.y <= 0.f);
            if (there) {
                ++inTexel;
                EXPECT_EQ(ls->L, Rgb(3000.f));
            }
        }
        EXPECT_GT(inTexel, n * 99 / 100) << rotate;
        const Vec3f ahead = rotate == 0.f ? Vec3f{0.02f, -0.05f, -1.f} : Vec3f{-1.f, -0.05f, -0.02f};
        EXPECT_EQ(light.radiance(ahead), Rgb(3000.f)) << rotate;
        EXPECT_FLOAT_EQ(light.radiance(Vec3f{0, 1, 0}).g, 3e-4f);
    }
}

// The batched samplers (sampleLanes for one sample per point, sampleMany for
// many at one point) return exactly what sample() returns, lane by lane, and
// nothing where a lane is not wanted; lookup() gives the radiance and pdf of
// each sampled direction.
TEST(EnvironmentLight, BatchedSamplesAreTheSamplesOneByOne) {
    const EnvironmentLight light(testImage(), 2.f, 30.f, 1.f);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> uni(0.f, 1.f);
    LanePoints at;
    alignas(64) float ux[LightLanes::kWidth], uy[LightLanes::kWidth];
    int32_t want[LightLanes::kWidth];
    for (int l = 0; l < LightLanes::kWidth; ++l) {
        at.set(l, Vec3f{float(l), 1.f, -2.f}, Vec3f{0, 1, 0});
        ux[l] = uni(rng);
        uy[l] = uni(rng);
        want[l] = l % 3 != 1;
    }
    LightLanes out;
    light.sampleLanes(at, ux, uy, want, LightLanes::kWidth, out);
    EXPECT_FALSE(out.delta);
    for (int l = 0; l < LightLanes::kWidth; ++l) {
        const std::optional<LightSample> one = light.sample(at.p(l), Vec2f{ux[l], uy[l]});
        ASSERT_EQ(out.ok[l] != 0, want[l] && one.has_value()) << l;
        if (!out.ok[l]) continue;
        const LightSample s = out.get(l);
        EXPECT_EQ(s.wi, one->wi) << l;
        EXPECT_EQ(s.point, one->point) << l;
        EXPECT_EQ(s.pdf, one->pdf) << l;
        EXPECT_EQ(s.L, one->L) << l;
        const EnvironmentLight::Lookup seen = light.lookup(s.wi);
        EXPECT_EQ(seen.L, s.L) << l;
        EXPECT_NEAR(seen.pdf, s.pdf, 2e-3f * s.pdf) << l;
    }
    std::vector<Vec2f> u(40);
    for (Vec2f& v : u) v = Vec2f{uni(rng), uni(rng)};
    std::vector<std::optional<LightSample>> many(u.size());
    const Vec3f p{0.5f, 0.f, 3.f};
    light.sampleMany(p, u, many);
    for (size_t k = 0; k < u.size(); ++k) {
        const std::optional<LightSample> one = light.sample(p, u[k]);
        ASSERT_EQ(many[k].has_value(), one.has_value()) << k;
        if (!one) continue;
        EXPECT_EQ(many[k]->wi, one->wi) << k;
        EXPECT_EQ(many[k]->pdf, one->pdf) << k;
        EXPECT_EQ(many[k]->L, one->L) << k;
    }
}

TEST(EnvironmentLight, ConstantColourIsUniform) {
    const EnvironmentLight light(Rgb{1.f, 2.f, 3.f}, 2.f);
    EXPECT_EQ(light.radiance(Vec3f{0.3f, -0.2f, 0.9f}), (Rgb{1.f, 2.f, 3.f}));
    const auto ls = light.sample(Vec3f{}, Vec2f{0.2f, 0.7f});
    ASSERT_TRUE(ls.has_value());
    EXPECT_FLOAT_EQ(ls->pdf, 1.f / (4.f * kPi));
    EXPECT_FLOAT_EQ(light.pdf(Vec3f{0, 0, 1}), 1.f / (4.f * kPi));
    // pi^2 R^2 L: a directional light of irradiance pi L over the scene's disk.
    EXPECT_NEAR(light.power(), kPi * kPi * 4.f * 2.f, 1e-3f);  // 2: the mean of the channels
}

TEST(LightSet, FindsTheEnvironmentAsItsLastLight) {
    Scene s;
    s.materials.push_back(Material{});
    s.pointLights.push_back(PointLight{Vec3f{0, 1, 0}, Rgb(1.f)});
    EXPECT_EQ(LightSet(s).environment(), nullptr);
    EnvironmentDesc env;
    env.color = Rgb(0.5f);
    env.scale = 2.f;
    s.environment = env;
    LightSet lights(s);
    ASSERT_NE(lights.environment(), nullptr);
    EXPECT_EQ(lights.size(), 2u);
    EXPECT_EQ(&lights[1], lights.environment());
    EXPECT_EQ(lights.environment()->radiance(Vec3f{1, 0, 0}), Rgb(1.f));
    // An image environment needs its pixels.
    s.environment->image = "sky.exr";
    EXPECT_THROW(LightSet{s}, Error);
    RgbImage img;
    img.width = 2;
    img.height = 1;
    img.pixels = {Rgb(1.f), Rgb(3.f)};
    LightSet withImage(s, img);
    ASSERT_NE(withImage.environment(), nullptr);
    EXPECT_TRUE(withImage.environment()->hasImage());
}

TEST(LightSet, PowerSelectionWeighsTheEnvironmentLikeADirectionalLight) {
    // Same irradiance on a surface facing them (pi * L = E), same power, same chance.
    Scene s;
    s.materials.push_back(Material{});
    s.spheres.push_back(Sphere{Vec3f{0, 0, 0}, 1.f, 0});
    s.directionalLights.push_back(DirectionalLight{Vec3f{0, -1, 0}, Rgb(kPi)});
    EnvironmentDesc env;
    env.color = Rgb(1.f);
    s.environment = env;
    LightSet lights(s);
    ASSERT_EQ(lights.size(), 2u);
    EXPECT_NEAR(lights.powerPicker().pick(0.25f, Vec3f{}, Vec3f{}).probability, 0.5f, 1e-5f);
    EXPECT_EQ(lights.powerPicker().pick(0.75f, Vec3f{}, Vec3f{}).index, 1u);
}
