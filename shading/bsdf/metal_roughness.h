// glTF 2.0's metal-roughness BRDF (the specification's Appendix B): a mix,
// by `metallic`, of a metal (a GGX specular lobe tinted by Schlick's Fresnel
// with F0 = the base colour) and a dielectric (the same lobe with F0 = 0.04
// over a Lambertian base of the base colour, which gets what the lobe's
// Fresnel leaves). With h the half vector of wo and wi, x^5 = (1 - x)^5:
//     F       = F0 + (1 - F0)(1 - wo.h)^5,   F0 = lerp(0.04, baseColor, metallic)
//     f_r     = F D(h) G2(wo, wi) / (4 n.wo n.wi) + c_diff T(wo) T(wi) / ((1 - 0.04) pi),
//     T(w)    = 1 - Fd(n.w) = 0.96 (1 - (1 - n.w)^5),   c_diff = (1 - metallic) baseColor,
// D and G2 GGX's (shading/bsdf/microfacet.h) with alpha = roughness^2.
// The one departure from Appendix B is the base's Fresnel weight: the
// appendix takes 1 - F(wo.h), which with the lobe's own F sums past 1 at
// grazing views (a white dielectric reflects 1.85 times what arrives at 89
// degrees); T(wo) T(wi) / (1 - 0.04) is reciprocal, equals the appendix's
// weight head-on, and keeps the white furnace at or below 1.
//
// Roughness is kept at or above kMinGgxAlpha's square root: below it the
// lobe is narrower than float directions resolve, so the model has no delta
// path of its own; a polished surface is a very sharp lobe, which BSDF
// sampling and MIS find as they find any sharp lobe, and the Whitted
// integrator adds the mirror bounce (shading/whitted_integrator.h).
//
// Sampling: the specular lobe by visible normals, or the cosine-weighted
// diffuse base, chosen with the probability specularProbability() (the
// Fresnel weight at wo against the base's albedo); pdf() is the density of
// the mixture, so the weight f cos / pdf is that of the whole BRDF.
// Conventions: unit directions away from the surface, n the shading normal on
// wo's side; nothing is reflected where wo or wi is below it.
#pragma once

#include <optional>

#include "core/color.h"
#include "core/math.h"
#include "shading/bsdf/bsdf_sample.h"
#include "shading/bsdf/microfacet.h"
#include "shading/shading_point.h"

namespace penumbra {

/// The narrowest GGX width the model uses (roughness 0.032).
inline constexpr float kMinGgxAlpha = 1e-3f;

/// GGX's alpha for glTF's perceptual roughness in [0, 1].
inline float ggxAlpha(float roughness) { return std::max(roughness * roughness, kMinGgxAlpha); }

/// The BRDF at one shading point (wo and the normal fixed), set up once for
/// many evaluations and samples.
class MetalRoughnessBsdf {
public:
    /// specularLobe false: the diffuse base alone (the specular lobe's light
    /// is carried by a mirror bounce instead: ShadingPoint::mirrorSpecular).
    MetalRoughnessBsdf(const Rgb& baseColor, float metallic, float roughness, const Vec3f& n, const Vec3f& wo,
                       bool specularLobe = true);

    /// f cos towards wi and the pdf with which direction() draws wi.
    BsdfSample evaluate(const Vec3f& wi) const;
    /// A direction drawn with u in [0, 1)^2 (u.x also picks the lobe, then is
    /// rescaled); nullopt where it lands below the surface or wo is below it.
    std::optional<Vec3f> direction(Vec2f u) const;
    /// direction(u), then evaluate(); nullopt also where the pdf is 0.
    std::optional<BsdfSample> sample(Vec2f u) const;

    /// The probability that direction() samples the specular lobe.
    float specularProbability() const { return specular_; }
    /// Pi times the largest value of pdf(): the sharper lobe's (the specular
    /// lobe's peak taken as seen head-on, 1 / (4 pi alpha^2)).
    float piPeakPdf() const {
        return specular_ / (4.f * ggx_.alpha() * ggx_.alpha()) + (1.f - specular_);
    }

private:
    float pdfLocal(const Vec3f& wi, const Vec3f& h) const;

    Frame frame_;
    Vec3f wo_;  // local
    GgxDistribution ggx_;
    Rgb f0_, diffuse_;  // F0 and c_diff
    float specular_;
    bool specularLobe_;
    float baseTransmittance_;  // T(wo) / (1 - 0.04): the base's weight on wo's side
    float g1o_;  // G1(wo), part of every specular pdf
};

/// The BRDF at a metal-roughness shading point.
inline MetalRoughnessBsdf metalRoughnessAt(const ShadingPoint& sp) {
    return MetalRoughnessBsdf(sp.kd, sp.metallic, sp.roughness, sp.ns, sp.wo, !sp.mirrorSpecular);
}

/// The reflectance of the specular lobe of a polished surface seen along wo
/// (Schlick's Fresnel at n.wo): the weight of the Whitted integrator's mirror
/// bounce where that bounce stands in for the lobe.
Rgb metalRoughnessMirrorWeight(const ShadingPoint& sp);

}  // namespace penumbra
