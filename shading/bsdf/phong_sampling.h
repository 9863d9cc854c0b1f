// Sampling the Phong BRDF (Lafortune & Willems 1994): a mixture of the
// cosine-weighted diffuse lobe and the cos^n lobe about the mirror direction
// of wo, for both models of shading/bsdf/phong.h.
//
// Directions and normals are unit vectors pointing away from the surface; n is
// the shading normal (facing wo) and every cosine below is taken with it. The
// pdf is per unit solid angle and exact for the mixture actually sampled:
//     pdf(wi) = P_d max(0, n.wi) / pi + (1 - P_d) (e+1)/(2 pi) max(0, r.wi)^e,
// r = 2(n.wo)n - wo, e = the Phong exponent, P_d the diffuse lobe's share.
// Directions below the surface have pdf > 0 (the specular lobe reaches there)
// but f = 0: sampling them is a wasted sample, which the pdf accounts for.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>

#include "core/color.h"
#include "core/material.h"
#include "core/math.h"
#include "shading/bsdf/bsdf_sample.h"

namespace penumbra {

/// Probability of choosing the diffuse lobe: the lobes' share of the
/// reflected energy (kd against ks, the classic lobe scaled by its integral
/// 2 pi / (e + 2)); 0 or 1 for materials with one lobe.
float phongDiffuseProbability(const Material& m, const Rgb& kd);

/// Samples wi with u in [0,1)^2 (u.x also picks the lobe, then is rescaled).
/// nullopt when the sample lands below the surface or the material reflects
/// nothing. kd is the textured diffuse albedo, as for phongResponse.
std::optional<BsdfSample> samplePhong(const Material& m, const Rgb& kd, const Vec3f& n, const Vec3f& wo, Vec2f u);

/// samplePhong for many samples at one shading point: what does not depend
/// on u (the diffuse lobe's probability, the frames about n and about the
/// mirror direction) is worked out once. sample(u) returns what
/// samplePhong(m, kd, n, wo, u) returns, bit for bit. Keeps a reference to m.
class PhongSampler {
public:
    PhongSampler(const Material& m, const Rgb& kd, const Vec3f& n, const Vec3f& wo);
    std::optional<BsdfSample> sample(Vec2f u) const;
    /// sample() in two steps, for callers that may not need f and the pdf
    /// (a direct-light BRDF sample that meets no light): the direction alone
    /// (nullopt below the surface, or where nothing is reflected), then its
    /// f cos and pdf. sample(u) is direction(u), then evaluate(), dropping a
    /// zero pdf.
    std::optional<Vec3f> direction(Vec2f u) const;
    BsdfSample evaluate(const Vec3f& wi) const;

    /// Where direction(u) goes, told from u alone before the direction is
    /// made: the lobe u picks and the sample's coordinates in it (the
    /// rescaled u is direction()'s own). s grows with the direction's angle
    /// from that lobe's axis: the concentric disk's radius, the sine of the
    /// angle from n, for the diffuse lobe; 1 - cos^(e+1) of the angle from
    /// the mirror direction of wo for the cos^e lobe. azimuth is the
    /// direction's azimuth about the axis in the lobe's frame (lobeFrame:
    /// from s towards t), in eighths of a turn, exactly (the concentric map
    /// is linear in it along each octant), in [-1, 8).
    struct Polar {
        bool diffuse;
        float s, azimuth;
    };
    Polar polar(Vec2f u) const;
    /// polar() of 16 points as lanes: the same values, as one loop without
    /// branches (LightWindows::mayReachLanes).
    static constexpr int kLanes = 16;
    void polarLanes(const float (&ux)[kLanes], const float (&uy)[kLanes], int32_t (&diffuse)[kLanes],
                    float (&s)[kLanes], float (&azimuth)[kLanes]) const;
    /// The frame whose n is the axis of the diffuse lobe (the shading
    /// normal) or of the cos^e lobe (the mirror direction of wo), as
    /// direction() uses it; only for a lobe u can pick (picks()).
    const Frame& lobeFrame(bool diffuse) const { return diffuse ? diffuse_ : lobe_; }
    bool picks(bool diffuse) const { return diffuse ? pd_ > 0.f : pd_ < 1.f; }
    /// An angle by its cosine and sine: LightWindows works the cone's bounds
    /// out from the light's without a trigonometric call.
    struct Angle {
        double cos, sin;
    };
    /// The closed range [lo, hi] of polar coordinates of a lobe whose exact
    /// directions (without rounding) make an angle in [minAngle, maxAngle]
    /// with its axis, for minAngle in (-pi/2, pi) and maxAngle in
    /// [max(0, minAngle), 3 pi/2); lo > hi where there are none.
    std::pair<float, float> polarRange(bool diffuse, Angle minAngle, Angle maxAngle) const;

private:
    const Material& m_;
    Rgb kd_;
    Vec3f n_, wo_;
    float pd_;
    Frame diffuse_, lobe_;  // where the lobe can be picked (pd > 0, pd < 1)
};

// Inline so that it compiles into the caller's lane clones (core/lane_clones.h).
[[gnu::always_inline]] inline void PhongSampler::polarLanes(const float (&ux)[kLanes], const float (&uy)[kLanes],
                                                            int32_t (&diffuse)[kLanes], float (&s)[kLanes],
                                                            float (&azimuth)[kLanes]) const {
    const float pd = pd_;
    for (int c = 0; c < kLanes; ++c) {
        // pickLobe, both ways, then the one picked (std::min's operand order).
        const bool d = ux[c] < pd;
        const float v = d ? ux[c] / pd : (ux[c] - pd) / (1.f - pd);
        const float vx = 0x1.fffffep-1f < v ? 0x1.fffffep-1f : v, vy = uy[c];
        // The concentric disk's radius and angle (polar()); |x| = |y| = 0 is the centre.
        const float x = 2.f * vx - 1.f, y = 2.f * vy - 1.f;
        const float ax = std::fabs(x), ay = std::fabs(y);
        const bool xMajor = ax > ay;
        const float alongX = (x > 0.f ? 0.f : 4.f) + y / x, alongY = (y > 0.f ? 2.f : 6.f) - x / y;
        const float diskAzimuth = xMajor ? alongX : (ay == 0.f ? 0.f : alongY);
        diffuse[c] = d;
        s[c] = d ? (xMajor ? ax : ay) : vx;
        azimuth[c] = d ? diskAzimuth : 8.f * vy;
    }
}

/// Solid-angle pdf with which samplePhong returns wi (for MIS weights).
float phongPdf(const Material& m, const Rgb& kd, const Vec3f& n, const Vec3f& wo, const Vec3f& wi);

/// f cos (as phongResponse for an area light) and pdf (as phongPdf) of wi in
/// one go, with one pow instead of two: what a light sample under MIS needs.
/// fCos is zero below the surface; wi is returned as given.
BsdfSample phongEvaluate(const Material& m, const Rgb& kd, const Vec3f& n, const Vec3f& wo, const Vec3f& wi);

}  // namespace penumbra
