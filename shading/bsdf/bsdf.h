// The material at a shading point as the direct-light estimator and the
// integrators ask for it. Its smooth lobes (Phong, classic or normalised:
// phong.h, phong_sampling.h; or glTF's metal-roughness BRDF:
// metal_roughness.h) give f cos and the pdf of a direction and sample
// directions; a bounce chooses among those lobes, the mirror (mirror.h) and
// the dielectric (dielectric.h). These functions are the one dispatch on the
// material's model: a new model is a file in this folder and a case in each.
// Conventions: shading/shading_point.h (both normals on wo's side).
#pragma once

#include <algorithm>
#include <optional>

#include "shading/bsdf/bsdf_sample.h"
#include "shading/bsdf/lambert.h"
#include "shading/bsdf/metal_roughness.h"
#include "shading/bsdf/phong.h"
#include "shading/bsdf/phong_sampling.h"
#include "shading/shading_point.h"

namespace penumbra {

/// What multiplies the radiance L of a light sample in direction wi: f cos
/// for area lights and the environment; for point and directional lights
/// (deltaLight) the same in the normalised model and the classic Phong
/// formula in the classic one (shading/bsdf/phong.h). Zero below the shading
/// surface.
inline Rgb bsdfResponse(const ShadingPoint& sp, const Vec3f& wi, bool deltaLight) {
    if (sp.metalRoughness) return metalRoughnessAt(sp).evaluate(wi).fCos;
    return phongResponse(*sp.material, sp.kd, sp.ns, sp.wo, wi, deltaLight);
}

/// f cos of the smooth lobes towards wi and the pdf with which BsdfSampler
/// draws wi: what a light sample's MIS weight needs.
inline BsdfSample bsdfEvaluate(const ShadingPoint& sp, const Vec3f& wi) {
    if (!sp.glossy && sp.reflectsLight()) return lambertEvaluate(sp.kd, sp.ns, wi);
    if (sp.metalRoughness) return metalRoughnessAt(sp).evaluate(wi);
    return phongEvaluate(*sp.material, sp.kd, sp.ns, sp.wo, wi);
}

/// Pi times the largest value of the smooth lobes' sampling pdf (1 for a
/// Lambertian surface): how sharp they are, for the rule that decides where
/// BSDF samples pay (shading/direct_light.cpp).
float bsdfPiPeakPdf(const ShadingPoint& sp);

/// Samples of the smooth lobes at one shading point, their set-up shared:
/// direction(u) alone (nullopt below the surface, or where nothing is
/// reflected), then evaluate() for f cos and the pdf where they are needed.
class BsdfSampler {
public:
    explicit BsdfSampler(const ShadingPoint& sp) {
        if (sp.metalRoughness)
            metalRoughness_.emplace(metalRoughnessAt(sp));
        else
            phong_.emplace(*sp.material, sp.kd, sp.ns, sp.wo);
    }
    std::optional<Vec3f> direction(Vec2f u) const {
        return phong_ ? phong_->direction(u) : metalRoughness_->direction(u);
    }
    BsdfSample evaluate(const Vec3f& wi) const { return phong_ ? phong_->evaluate(wi) : metalRoughness_->evaluate(wi); }
    /// The Phong sampler itself, for strategies written for its lobes
    /// (shading/light_windows.h); nullptr for another model.
    const PhongSampler* phong() const { return phong_ ? &*phong_ : nullptr; }

private:
    std::optional<PhongSampler> phong_;
    std::optional<MetalRoughnessBsdf> metalRoughness_;
};

/// The probabilities with which a bounce picks each of the material's lobes:
/// in proportion to their reflectance (kd + ks for the smooth lobes, kr for
/// the mirror, 1 for glass, which reflects and transmits up to 1). All zero
/// where nothing scatters.
struct BsdfLobes {
    float smooth = 0.f, mirror = 0.f, glass = 0.f;
    bool any() const { return smooth > 0.f || mirror > 0.f || glass > 0.f; }
};
BsdfLobes bsdfLobes(const ShadingPoint& sp);

/// One sampled bounce.
struct BsdfBounce {
    Vec3f wi;
    Rgb weight;        // f cos / pdf, the lobe's probability included
    float pdf;         // solid-angle pdf, the lobe's probability included; 0 for a delta lobe
    bool delta;        // the mirror or the dielectric: no light sample can find this direction
    bool transmitted;  // refracted through a dielectric
};

/// Samples a bounce with u in [0, 1)^2: u.x picks the lobe, then, rescaled
/// within the lobe's share, samples it. nullopt where the smooth lobes'
/// sample lands below the surface or has no density.
std::optional<BsdfBounce> sampleBsdf(const ShadingPoint& sp, const BsdfLobes& lobes, Vec2f u);

/// Whether sampleBsdf's bounce for u is Lambertian: u picks the smooth
/// lobes where they are kd/pi alone (no Phong lobe, not metal-roughness).
inline bool bouncesLambert(const ShadingPoint& sp, const BsdfLobes& lobes, Vec2f u) {
    return u.x < lobes.smooth && !sp.glossy;
}
/// u with u.x rescaled to [0, 1) within the smooth lobes' share: the point
/// that samples them once u.x has picked them.
inline Vec2f smoothLobeU(Vec2f u, float smooth) { return {std::min(u.x / smooth, 0x1.fffffep-1f), u.y}; }
/// The Lambertian bounce along l = sampleLambert(sp.ns, smoothLobeU(u,
/// smooth)): weight kd / smooth and pdf smooth cos / pi in closed form;
/// nullopt where l lies in or below either surface.
inline std::optional<BsdfBounce> lambertBounce(const ShadingPoint& sp, float smooth, const LambertDirection& l) {
    if (!(l.cosTheta > 0.f) || dot(l.wi, sp.ng) <= 0.f) return std::nullopt;
    return BsdfBounce{l.wi, sp.kd * (1.f / smooth), smooth * l.cosTheta * kInvPi, false, false};
}

/// sampleLambert(n, smoothLobeU(u, smooth)) of 16 lanes: the same values,
/// as one loop without branches. Inline so that it compiles into the
/// caller's lane clones (core/lane_clones.h).
struct LambertLanes {
    static constexpr int kLanes = 16;
    alignas(64) float x[kLanes], y[kLanes], z[kLanes], cosTheta[kLanes];
    LambertDirection at(int c) const { return {Vec3f{x[c], y[c], z[c]}, cosTheta[c]}; }
};
[[gnu::always_inline]] inline void lambertLanes(const float (&nx)[LambertLanes::kLanes],
                                                const float (&ny)[LambertLanes::kLanes],
                                                const float (&nz)[LambertLanes::kLanes],
                                                const float (&ux)[LambertLanes::kLanes],
                                                const float (&uy)[LambertLanes::kLanes],
                                                const float (&smooth)[LambertLanes::kLanes], LambertLanes& out) {
    for (int c = 0; c < LambertLanes::kLanes; ++c) {
        const Vec2f v = smoothLobeU(Vec2f{ux[c], uy[c]}, smooth[c]);
        const LambertDirection l = sampleLambert(Vec3f{nx[c], ny[c], nz[c]}, v);
        out.x[c] = l.wi.x;
        out.y[c] = l.wi.y;
        out.z[c] = l.wi.z;
        out.cosTheta[c] = l.cosTheta;
    }
}

}  // namespace penumbra
