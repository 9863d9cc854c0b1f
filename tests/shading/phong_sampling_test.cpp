// Phong BRDF sampling: chi-square fits of the sampled directions against
// phongPdf for both models, several exponents and lobe mixes; the returned
// f cos matches phongResponse; the estimate f cos / pdf integrates the
// BRDF's albedo.
#include "shading/bsdf/phong_sampling.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/multi_jitter.h"
#include "shading/bsdf/phong.h"
#include "support/chi_square.h"

using namespace penumbra;
using penumbra::test::chiSquareDirections;

namespace {

struct Case {
    PhongModel model;
    float kd, ks, exponent;
    float viewAngleDeg;
};

void expectPhongFits(const Case& c) {
    Material m;
    m.model = c.model;
    m.kd = Rgb(c.kd);
    m.ks = Rgb(c.ks);
    m.exponent = c.exponent;
    // A tilted normal so no lobe sits on the grid's pole.
    const Vec3f n = normalize(Vec3f{0.3f, -0.4f, 0.8f});
    const Frame f = Frame::fromNormal(n);
    const float a = c.viewAngleDeg * kPi / 180.f;
    const Vec3f wo = f.toWorld(Vec3f{std::sin(a), 0.f, std::cos(a)});
    const uint32_t N = 200000;
    int badF = 0;
    const auto sample = [&](uint32_t i) -> std::optional<Vec3f> {
        const auto s = samplePhong(m, m.kd, n, wo, multiJitter2D(i, N, 9));
        if (!s) return std::nullopt;
        const Rgb expected = phongResponse(m, m.kd, n, wo, s->wi, false);
        if (std::fabs(s->fCos.r - expected.r) > 1e-5f * std::max(1.f, expected.r)) ++badF;
        if (std::fabs(s->pdf - phongPdf(m, m.kd, n, wo, s->wi)) > 1e-5f * s->pdf) ++badF;
        return s->wi;
    };
    // The sampler returns nothing below the surface: that mass goes to the
    // rejected cell, so the histogram is compared with the upper part of the pdf.
    const auto pdf = [&](const Vec3f& w) -> double { return dot(w, n) > 0.f ? phongPdf(m, m.kd, n, wo, w) : 0.0; };
    const auto r = chiSquareDirections(sample, pdf);
    EXPECT_TRUE(r.passed) << r.message;
    EXPECT_EQ(badF, 0);
    EXPECT_LE(r.pdfIntegral, 1.0 + 1e-3) << r.message;
    // Over the whole sphere the mixture integrates to 1.
    const auto whole = chiSquareDirections([](uint32_t) { return std::optional<Vec3f>(); },
                                           [&](const Vec3f& w) -> double { return phongPdf(m, m.kd, n, wo, w); },
                                           penumbra::test::ChiSquareOptions{1, 20, 40, 8, 128, 0.01});
    EXPECT_NEAR(whole.pdfIntegral, 1.0, 2e-3);
}

}  // namespace

TEST(PhongSampling, NormalizedDiffuseOnlyFits) { expectPhongFits({PhongModel::Normalized, 0.8f, 0.f, 1.f, 30.f}); }
TEST(PhongSampling, NormalizedGlossyOnlyFits) { expectPhongFits({PhongModel::Normalized, 0.f, 0.9f, 20.f, 40.f}); }
TEST(PhongSampling, NormalizedMixFits) { expectPhongFits({PhongModel::Normalized, 0.5f, 0.3f, 60.f, 20.f}); }
TEST(PhongSampling, NormalizedSharpLobeAtGrazingViewFits) {
    expectPhongFits({PhongModel::Normalized, 0.2f, 0.7f, 200.f, 75.f});
}
TEST(PhongSampling, NormalizedLowExponentLosesMassBelowTheSurfaceAndFits) {
    expectPhongFits({PhongModel::Normalized, 0.1f, 0.8f, 2.f, 70.f});
}
TEST(PhongSampling, ClassicMixFits) { expectPhongFits({PhongModel::Classic, 0.6f, 0.2f, 10.f, 35.f}); }
TEST(PhongSampling, ClassicSharpLobeFits) { expectPhongFits({PhongModel::Classic, 0.3f, 0.5f, 100.f, 50.f}); }

// Direct light's BRDF samples at one shading point come from a PhongSampler
// (the lobe probability and frames worked out once): the same samples, bit
// for bit, as samplePhong for each, whichever lobes the material has, and
// the same again in two steps (direction, then evaluate where it is needed).
TEST(PhongSampling, ASamplerAtOnePointGivesSamplePhongsSamples) {
    const Case cases[] = {{PhongModel::Classic, 0.3f, 0.2f, 40.f, 20.f},   {PhongModel::Normalized, 0.5f, 0.3f, 60.f, 70.f},
                          {PhongModel::Normalized, 0.8f, 0.f, 1.f, 30.f},  {PhongModel::Classic, 0.f, 0.9f, 20.f, 40.f},
                          {PhongModel::Normalized, 0.f, 0.f, 10.f, 10.f}};
    for (const Case& c : cases) {
        Material m;
        m.model = c.model;
        m.kd = Rgb(c.kd, 0.5f * c.kd, 0.25f * c.kd);
        m.ks = Rgb(c.ks);
        m.exponent = c.exponent;
        const Vec3f n = normalize(Vec3f{0.3f, -0.4f, 0.8f});
        const float a = c.viewAngleDeg * kPi / 180.f;
        const Vec3f wo = Frame::fromNormal(n).toWorld(Vec3f{std::sin(a), 0.f, std::cos(a)});
        const PhongSampler sampler(m, m.kd, n, wo);
        int some = 0;
        for (uint32_t i = 0; i < 4096; ++i) {
            const Vec2f u = multiJitter2D(i, 4096, 3);
            const auto want = samplePhong(m, m.kd, n, wo, u), got = sampler.sample(u);
            ASSERT_EQ(got.has_value(), want.has_value()) << "sample " << i;
            const std::optional<Vec3f> wi = sampler.direction(u);
            const std::optional<BsdfSample> twoSteps =
                wi && sampler.evaluate(*wi).pdf > 0.f ? std::optional(sampler.evaluate(*wi)) : std::nullopt;
            ASSERT_EQ(twoSteps.has_value(), want.has_value()) << "sample " << i;
            if (!want) continue;
            ++some;
            ASSERT_EQ(got->wi, want->wi) << "sample " << i;
            ASSERT_EQ(got->fCos, want->fCos) << "sample " << i;
            ASSERT_EQ(got->pdf, want->pdf) << "sample " << i;
            ASSERT_EQ(twoSteps->wi, want->wi) << "sample " << i;
            ASSERT_EQ(twoSteps->fCos, want->fCos) << "sample " << i;
            ASSERT_EQ(twoSteps->pdf, want->pdf) << "sample " << i;
        }
        EXPECT_EQ(some > 0, c.kd > 0.f || c.ks > 0.f);
    }
}

TEST(PhongSampling, EstimatesTheAlbedoItSamples) {
    // E[f cos / pdf] over sampled directions = the directional albedo
    // integral of f cos, computed here by brute force on a fine grid.
    Material m;
    m.kd = Rgb(0.4f);
    m.ks = Rgb(0.5f);
    m.exponent = 30.f;
    const Vec3f n{0, 0, 1};
    const Vec3f wo = normalize(Vec3f{0.5f, 0.f, 1.f});
    const uint32_t N = 65536;
    double est = 0;
    for (uint32_t i = 0; i < N; ++i)
        if (auto s = samplePhong(m, m.kd, n, wo, multiJitter2D(i, N, 4))) est += s->fCos.r / s->pdf;
    est /= N;
    double ref = 0;
    const int T = 1024, P = 2048;
    for (int t = 0; t < T; ++t)
        for (int p = 0; p < P; ++p) {
            const double th = (t + 0.5) * (M_PI / 2) / T, ph = (p + 0.5) * 2 * M_PI / P;
            const Vec3f wi{float(std::sin(th) * std::cos(ph)), float(std::sin(th) * std::sin(ph)), float(std::cos(th))};
            ref += phongResponse(m, m.kd, n, wo, wi, false).r * std::sin(th) * (M_PI / 2 / T) * (2 * M_PI / P);
        }
    EXPECT_NEAR(est, ref, 2e-3 * ref);
    // The diffuse share follows the lobes' energy.
    EXPECT_NEAR(phongDiffuseProbability(m, m.kd), 0.4f / 0.9f, 1e-6f);
    m.model = PhongModel::Classic;
    const float ws = 0.5f * 2.f * kPi / 32.f;
    EXPECT_NEAR(phongDiffuseProbability(m, m.kd), 0.4f / (0.4f + ws), 1e-6f);
    // Black materials give no sample.
    m.kd = Rgb(0.f);
    m.ks = Rgb(0.f);
    EXPECT_FALSE(samplePhong(m, m.kd, n, wo, Vec2f{0.3f, 0.3f}).has_value());
}

TEST(PhongSampling, LobeMomentsPinTheExponent) {
    // Lobe about the normal (wo = n): cos(alpha) = n.wi with density
    // (e+1)/(2 pi) cos^e, so E[cos] = (e+1)/(e+2) and E[cos^2] = (e+1)/(e+3):
    // a finer check of the exponent than a histogram of a sharp lobe.
    for (float e : {1.f, 20.f, 500.f}) {
        Material m;
        m.kd = Rgb(0.f);
        m.ks = Rgb(1.f);
        m.exponent = e;
        const Vec3f n{0, 0, 1};
        const uint32_t N = 65536;
        double m1 = 0, m2 = 0;
        for (uint32_t i = 0; i < N; ++i) {
            const auto s = samplePhong(m, m.kd, n, n, multiJitter2D(i, N, 2));
            ASSERT_TRUE(s.has_value());
            m1 += s->wi.z;
            m2 += double(s->wi.z) * s->wi.z;
        }
        EXPECT_NEAR(m1 / N, (e + 1.0) / (e + 2.0), 1e-4) << "exponent " << e;
        EXPECT_NEAR(m2 / N, (e + 1.0) / (e + 3.0), 1e-4) << "exponent " << e;
    }
}

#include "shading/mis.h"

TEST(Mis, PowerHeuristicWeightsSumToOne) {
    EXPECT_FLOAT_EQ(powerHeuristic(1, 2.f, 1, 2.f), 0.5f);
    EXPECT_FLOAT_EQ(powerHeuristic(1, 3.f, 1, 1.f), 0.9f);
    EXPECT_FLOAT_EQ(powerHeuristic(1, 3.f, 1, 1.f) + powerHeuristic(1, 1.f, 1, 3.f), 1.f);
    EXPECT_FLOAT_EQ(powerHeuristic(4, 1.f, 1, 2.f), 0.8f);  // (4*1)^2 / ((4*1)^2 + (1*2)^2)
    EXPECT_EQ(powerHeuristic(1, 0.f, 1, 1.f), 0.f);
    EXPECT_EQ(powerHeuristic(1, 1.f, 1, 0.f), 1.f);
    EXPECT_NEAR(powerHeuristic(1, 1e30f, 1, 1e30f), 0.5f, 1e-6f);  // no overflow
}
