// A bounce off a Lambertian surface (sampleBsdf's closed form): its
// directions follow cos/pi, its weight is kd over the lobe's probability and
// its pdf is the Phong model's for the same direction; the lane-wise
// directions are the scalar ones, bit for bit.
#include "shading/bsdf/bsdf.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/multi_jitter.h"
#include "support/chi_square.h"

using namespace penumbra;
using penumbra::test::chiSquareDirections;

namespace {

// A Lambertian point with a tilted shading normal, so that no lobe sits on
// the chi-square grid's pole; the geometric normal leans a little away from it.
ShadingPoint lambertPoint(const Material& m) {
    ShadingPoint sp;
    sp.material = &m;
    sp.kd = m.kd;
    sp.ns = normalize(Vec3f{0.3f, -0.4f, 0.8f});
    sp.ng = normalize(Vec3f{0.25f, -0.4f, 0.85f});
    sp.wo = normalize(Vec3f{0.f, 0.2f, 1.f});
    sp.glossy = m.isGlossy();
    return sp;
}

}  // namespace

TEST(LambertBounce, FollowsCosineOverPiWithWeightKdOverTheLobesShare) {
    Material m;
    m.kd = Rgb(0.6f, 0.3f, 0.3f);
    m.kr = Rgb(0.4f);  // a mirror lobe too: the smooth one is picked with probability 1/2
    const ShadingPoint sp = lambertPoint(m);
    const BsdfLobes lobes = bsdfLobes(sp);
    ASSERT_FLOAT_EQ(lobes.smooth, 0.5f);
    const uint32_t N = 200000;
    int bad = 0, smooth = 0;
    const auto sample = [&](uint32_t i) -> std::optional<Vec3f> {
        // u.x within the smooth lobe's share, so that every sample is Lambertian.
        const Vec2f v = multiJitter2D(i, N, 5);
        const Vec2f u{v.x * lobes.smooth, v.y};
        if (!bouncesLambert(sp, lobes, u)) ++bad;
        const std::optional<BsdfBounce> b = sampleBsdf(sp, lobes, u);
        if (!b) return std::nullopt;
        ++smooth;
        if (!(b->weight == m.kd * (1.f / lobes.smooth))) ++bad;
        const float pdf = lobes.smooth * phongPdf(m, sp.kd, sp.ns, sp.wo, b->wi);
        if (std::fabs(b->pdf - pdf) > 1e-5f * pdf || b->delta || b->transmitted) ++bad;
        if (std::fabs(length(b->wi) - 1.f) > 1e-6f || !(dot(b->wi, sp.ng) > 0.f)) ++bad;
        return b->wi;
    };
    // Directions below the geometric surface are dropped: that mass goes to the rejected cell.
    const auto pdf = [&](const Vec3f& w) -> double {
        return dot(w, sp.ng) > 0.f ? std::max(0.f, dot(w, sp.ns)) * kInvPi : 0.0;
    };
    const auto r = chiSquareDirections(sample, pdf);
    EXPECT_TRUE(r.passed) << r.message;
    EXPECT_EQ(bad, 0);
    EXPECT_GT(smooth, int(0.99 * N));
    // The rest of u.x picks the mirror.
    EXPECT_FALSE(bouncesLambert(sp, lobes, Vec2f{0.75f, 0.5f}));
    EXPECT_TRUE(sampleBsdf(sp, lobes, Vec2f{0.75f, 0.5f})->delta);
}

TEST(LambertBounce, AGlossyPointBouncesByItsPhongLobes) {
    Material m;
    m.kd = Rgb(0.5f);
    m.ks = Rgb(0.3f);
    const ShadingPoint sp = lambertPoint(m);
    EXPECT_FALSE(bouncesLambert(sp, bsdfLobes(sp), Vec2f{0.1f, 0.5f}));
}

TEST(LambertBounce, LanesGiveTheScalarDirectionsBitForBit) {
    constexpr int N = LambertLanes::kLanes;
    alignas(64) float nx[N], ny[N], nz[N], ux[N], uy[N], smooth[N];
    for (uint32_t round = 0; round < 256; ++round) {
        for (int c = 0; c < N; ++c) {
            const uint32_t i = round * N + uint32_t(c);
            const Vec2f a = multiJitter2D(i, 256 * N, 11), u = multiJitter2D(i, 256 * N, 12);
            // Normals over the whole sphere (both signs of z: Frame::fromNormal's two branches).
            const float z = 1.f - 2.f * a.x, r = std::sqrt(std::max(0.f, 1.f - z * z)), phi = 2.f * kPi * a.y;
            nx[c] = r * std::cos(phi), ny[c] = r * std::sin(phi), nz[c] = z;
            ux[c] = u.x, uy[c] = u.y;
            smooth[c] = c % 3 == 0 ? 1.f : 0.25f + 0.05f * float(c);
        }
        LambertLanes lanes;
        lambertLanes(nx, ny, nz, ux, uy, smooth, lanes);
        for (int c = 0; c < N; ++c) {
            const LambertDirection want =
                sampleLambert(Vec3f{nx[c], ny[c], nz[c]}, smoothLobeU(Vec2f{ux[c], uy[c]}, smooth[c]));
            const LambertDirection got = lanes.at(c);
            ASSERT_EQ(got.wi, want.wi) << "round " << round << " lane " << c;
            ASSERT_EQ(got.cosTheta, want.cosTheta) << "round " << round << " lane " << c;
        }
    }
}

TEST(LambertBounce, LambertEvaluateIsPhongEvaluateWithoutALobe) {
    for (const PhongModel model : {PhongModel::Normalized, PhongModel::Classic}) {
        Material m;
        m.model = model;
        m.kd = Rgb(0.7f, 0.2f, 0.05f);
        m.exponent = 12.f;
        ShadingPoint sp = lambertPoint(m);
        const uint32_t N = 4096;
        for (uint32_t i = 0; i < N; ++i) {
            const Vec2f a = multiJitter2D(i, N, 13);
            const float z = 1.f - 2.f * a.x, r = std::sqrt(std::max(0.f, 1.f - z * z)), phi = 2.f * kPi * a.y;
            const Vec3f wi{r * std::cos(phi), r * std::sin(phi), z};
            const BsdfSample want = phongEvaluate(m, sp.kd, sp.ns, sp.wo, wi), got = bsdfEvaluate(sp, wi);
            ASSERT_EQ(got.fCos, want.fCos) << i;
            ASSERT_EQ(got.pdf, want.pdf) << i;
            ASSERT_EQ(got.wi, want.wi) << i;
        }
    }
}
