// glTF's metal-roughness BRDF and GGX: chi-square fits of visible-normal
// sampling and of the BRDF's sampling against their pdfs, sample weights
// equal to f cos / pdf, reciprocity, and the white-furnace albedo (at most 1;
// 1 for a polished white metal seen head-on; the energy rough GGX loses to
// single scattering, printed).
#include "shading/bsdf/metal_roughness.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/multi_jitter.h"
#include "core/sampling.h"
#include "shading/bsdf/microfacet.h"
#include "support/chi_square.h"

using namespace penumbra;
using penumbra::test::chiSquareDirections;

namespace {

// A tilted normal, so that no lobe sits on the chi-square grid's pole.
const Vec3f kNormal = normalize(Vec3f{0.3f, -0.4f, 0.8f});

Vec3f viewAt(const Frame& f, float degrees) {
    const float a = degrees * kPi / 180.f;
    return f.toWorld(Vec3f{std::sin(a), 0.f, std::cos(a)});
}

struct Case {
    float base, metallic, roughness, viewDeg;
};

void expectVisibleNormalsFit(float alpha, float viewDeg) {
    const Frame f = Frame::fromNormal(kNormal);
    const Vec3f wo = f.toLocal(viewAt(f, viewDeg));
    const GgxDistribution ggx(alpha);
    const uint32_t N = 200000;
    const auto r = chiSquareDirections(
        [&](uint32_t i) -> std::optional<Vec3f> { return f.toWorld(ggx.sampleVisibleNormal(wo, multiJitter2D(i, N, 5))); },
        [&](const Vec3f& w) -> double { return ggx.visibleNormalPdf(wo, f.toLocal(w)); });
    EXPECT_TRUE(r.passed) << "alpha " << alpha << " view " << viewDeg << ": " << r.message;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 3e-3) << r.message;
}

void expectBsdfFits(const Case& c) {
    const Frame f = Frame::fromNormal(kNormal);
    const Vec3f wo = viewAt(f, c.viewDeg);
    const MetalRoughnessBsdf bsdf(Rgb(c.base), c.metallic, c.roughness, kNormal, wo);
    const uint32_t N = 200000;
    int bad = 0;
    const auto sample = [&](uint32_t i) -> std::optional<Vec3f> {
        const auto s = bsdf.sample(multiJitter2D(i, N, 11));
        if (!s) return std::nullopt;
        const BsdfSample e = bsdf.evaluate(s->wi);
        if (s->fCos != e.fCos || s->pdf != e.pdf || !(s->pdf > 0.f)) ++bad;
        return s->wi;
    };
    const auto pdf = [&](const Vec3f& w) -> double { return bsdf.evaluate(w).pdf; };
    const auto r = chiSquareDirections(sample, pdf);
    EXPECT_TRUE(r.passed) << "roughness " << c.roughness << " view " << c.viewDeg << ": " << r.message;
    EXPECT_EQ(bad, 0);
    // The sampler loses the mass of the reflections that go below the surface.
    EXPECT_LE(r.pdfIntegral, 1.0 + 3e-3) << r.message;
    EXPECT_GT(r.pdfIntegral, 0.5) << r.message;
}

/// The directional albedo, the integral of f cos over wi, estimated by the
/// BRDF's own sampling (E[f cos / pdf]).
Rgb albedo(const Rgb& base, float metallic, float roughness, float viewDeg, uint32_t n = 1u << 18) {
    const Vec3f normal{0.f, 0.f, 1.f};
    const Vec3f wo = viewAt(Frame::fromNormal(normal), viewDeg);
    const MetalRoughnessBsdf bsdf(base, metallic, roughness, normal, wo);
    double r = 0, g = 0, b = 0;
    for (uint32_t i = 0; i < n; ++i)
        if (const auto s = bsdf.sample(multiJitter2D(i, n, 3))) {
            r += s->fCos.r / s->pdf;
            g += s->fCos.g / s->pdf;
            b += s->fCos.b / s->pdf;
        }
    return Rgb(float(r / n), float(g / n), float(b / n));
}

}  // namespace

TEST(Ggx, DistributionIsNormalisedAndMaskingBounded) {
    for (float alpha : {0.01f, 0.2f, 0.7f, 1.f}) {
        const GgxDistribution ggx(alpha);
        // The projected area of the microfacets is the macro-surface's: the integral of D(h) cos.
        double sum = 0;
        const int T = 4096;
        for (int t = 0; t < T; ++t) {
            const double th = (t + 0.5) * (M_PI / 2) / T;
            const Vec3f h{float(std::sin(th)), 0.f, float(std::cos(th))};
            sum += ggx.d(h) * std::cos(th) * std::sin(th) * (M_PI / 2 / T) * 2 * M_PI;
        }
        EXPECT_NEAR(sum, 1.0, alpha < 0.05f ? 2e-2 : 1e-3) << alpha;
        EXPECT_FLOAT_EQ(ggx.g1(Vec3f{0.f, 0.f, 1.f}), 1.f);
        const Vec3f grazing = normalize(Vec3f{1.f, 0.f, 0.05f});
        EXPECT_LT(ggx.g1(grazing), 1.f);
        EXPECT_LE(ggx.g2(grazing, grazing), ggx.g1(grazing));
    }
}

TEST(Ggx, VisibleNormalSamplingFits) {
    for (float alpha : {0.05f, 0.3f, 0.7f, 1.f})
        for (float view : {0.f, 40.f, 75.f, 88.f}) expectVisibleNormalsFit(alpha, view);
}

TEST(MetalRoughness, SamplingFitsItsPdf) {
    expectBsdfFits({1.f, 1.f, 0.5f, 30.f});
    expectBsdfFits({0.8f, 0.f, 0.5f, 60.f});
    expectBsdfFits({0.5f, 0.5f, 0.25f, 10.f});
    expectBsdfFits({0.9f, 0.f, 1.f, 80.f});
    expectBsdfFits({0.3f, 1.f, 0.8f, 85.f});
    expectBsdfFits({0.6f, 0.2f, 0.15f, 45.f});
}

TEST(MetalRoughness, SampleWeightIsFCosOverPdfAndEvaluateAgrees) {
    const Vec3f wo = viewAt(Frame::fromNormal(kNormal), 50.f);
    const MetalRoughnessBsdf bsdf(Rgb(0.7f, 0.5f, 0.2f), 0.4f, 0.35f, kNormal, wo);
    int some = 0;
    for (uint32_t i = 0; i < 4096; ++i) {
        const auto s = bsdf.sample(multiJitter2D(i, 4096, 2));
        if (!s) continue;
        ++some;
        EXPECT_GT(dot(s->wi, kNormal), 0.f);
        const BsdfSample e = bsdf.evaluate(s->wi);
        EXPECT_EQ(s->fCos, e.fCos);
        EXPECT_EQ(s->pdf, e.pdf);
    }
    EXPECT_GT(some, 4000);
    // Below the surface, or seen from below: nothing.
    EXPECT_EQ(bsdf.evaluate(-kNormal).fCos, Rgb(0.f));
    EXPECT_EQ(bsdf.evaluate(-kNormal).pdf, 0.f);
    const MetalRoughnessBsdf below(Rgb(1.f), 1.f, 0.5f, kNormal, -wo);
    EXPECT_FALSE(below.sample(Vec2f{0.3f, 0.6f}).has_value());
}

TEST(MetalRoughness, IsReciprocal) {
    const Vec3f n = kNormal;
    const Frame f = Frame::fromNormal(n);
    int checked = 0;
    for (uint32_t i = 0; i < 500; ++i) {
        const Vec2f a = multiJitter2D(i, 500, 21), b = multiJitter2D(i, 500, 22);
        const Vec3f wo = f.toWorld(squareToCosineHemisphere(a)), wi = f.toWorld(squareToCosineHemisphere(b));
        const float roughness = 0.1f + 0.9f * float(i % 7) / 6.f, metallic = float(i % 3) / 2.f;
        const Rgb base(0.9f, 0.6f, 0.3f);
        const Rgb fo = MetalRoughnessBsdf(base, metallic, roughness, n, wo).evaluate(wi).fCos / dot(wi, n);
        const Rgb fi = MetalRoughnessBsdf(base, metallic, roughness, n, wi).evaluate(wo).fCos / dot(wo, n);
        if (!(dot(wi, n) > 1e-3f && dot(wo, n) > 1e-3f)) continue;
        ++checked;
        EXPECT_NEAR(fo.r, fi.r, 2e-4f * std::max(1.f, fo.r));
        EXPECT_NEAR(fo.g, fi.g, 2e-4f * std::max(1.f, fo.g));
        EXPECT_NEAR(fo.b, fi.b, 2e-4f * std::max(1.f, fo.b));
    }
    EXPECT_GT(checked, 450);
}

TEST(MetalRoughness, WhiteFurnaceAlbedoIsAtMostOne) {
    // Single-scattering GGX loses the light that would bounce between
    // microfacets: most for rough surfaces at grazing views. The table is the
    // figure docs/rendering.md quotes.
    std::printf("white albedo, metal | dielectric (rows: roughness; columns: view angle 0 30 60 80 89 deg)\n");
    for (float roughness : {0.f, 0.25f, 0.5f, 0.75f, 1.f}) {
        std::printf("  %.2f:", roughness);
        for (float view : {0.f, 30.f, 60.f, 80.f, 89.f}) {
            const float metal = albedo(Rgb(1.f), 1.f, roughness, view).r;
            const float dielectric = albedo(Rgb(1.f), 0.f, roughness, view).r;
            std::printf(" %.4f|%.4f", metal, dielectric);
            EXPECT_LE(metal, 1.f + 2e-3f) << roughness << " " << view;
            EXPECT_GT(metal, 0.3f) << roughness << " " << view;
            EXPECT_LE(dielectric, 1.f + 2e-3f) << roughness << " " << view;
        }
        std::printf("\n");
    }
    // A polished white metal seen head-on reflects everything.
    EXPECT_NEAR(albedo(Rgb(1.f), 1.f, 0.f, 0.f).r, 1.f, 1e-3f);
    // A polished coloured metal reflects its base colour head-on (F = F0).
    const Rgb gold = albedo(Rgb(1.f, 0.78f, 0.34f), 1.f, 0.f, 0.f);
    EXPECT_NEAR(gold.g, 0.78f, 2e-3f);
    EXPECT_NEAR(gold.b, 0.34f, 2e-3f);
    // Rough GGX at roughness 0.5 head-on keeps most of it (what the furnace render checks).
    const float half = albedo(Rgb(1.f), 1.f, 0.5f, 0.f).r;
    EXPECT_GT(half, 0.9f);
    EXPECT_LT(half, 1.f);
}

TEST(MetalRoughness, SampledAlbedoMatchesTheIntegralOfFCos) {
    // E[f cos / pdf] against a brute-force integral of evaluate() on a grid.
    const Rgb base(0.8f, 0.5f, 0.3f);
    const float metallic = 0.3f, roughness = 0.6f, view = 50.f;
    const Rgb est = albedo(base, metallic, roughness, view);
    const Vec3f n{0.f, 0.f, 1.f};
    const MetalRoughnessBsdf bsdf(base, metallic, roughness, n, viewAt(Frame::fromNormal(n), view));
    double ref = 0;
    const int T = 1024, P = 2048;
    for (int t = 0; t < T; ++t)
        for (int p = 0; p < P; ++p) {
            const double th = (t + 0.5) * (M_PI / 2) / T, ph = (p + 0.5) * 2 * M_PI / P;
            const Vec3f wi{float(std::sin(th) * std::cos(ph)), float(std::sin(th) * std::sin(ph)), float(std::cos(th))};
            ref += bsdf.evaluate(wi).fCos.r * std::sin(th) * (M_PI / 2 / T) * (2 * M_PI / P);
        }
    EXPECT_NEAR(est.r, ref, 3e-3 * ref);
}

TEST(MetalRoughness, LobeChoiceFollowsTheFresnelWeight) {
    const Vec3f n{0.f, 0.f, 1.f};
    EXPECT_FLOAT_EQ(MetalRoughnessBsdf(Rgb(0.5f), 1.f, 0.5f, n, n).specularProbability(), 1.f);
    const float p = MetalRoughnessBsdf(Rgb(1.f), 0.f, 0.5f, n, n).specularProbability();
    EXPECT_NEAR(p, 0.04f / (0.04f + 0.96f), 1e-6f);
    // Grazing views favour the specular lobe as its Fresnel weight grows.
    const Vec3f grazing = normalize(Vec3f{1.f, 0.f, 0.1f});
    EXPECT_GT(MetalRoughnessBsdf(Rgb(1.f), 0.f, 0.5f, n, grazing).specularProbability(), 0.3f);
}
