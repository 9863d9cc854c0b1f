#include "shading/bsdf/metal_roughness.h"

#include <algorithm>
#include <cmath>

#include "core/sampling.h"

namespace penumbra {

namespace {

float pow5(float x) {
    const float x2 = x * x;
    return x2 * x2 * x;
}

Rgb schlick(const Rgb& f0, float cosTheta) { return f0 + (Rgb(1.f) - f0) * pow5(std::clamp(1.f - cosTheta, 0.f, 1.f)); }

constexpr float kDielectricF0 = 0.04f;

// What the dielectric's specular layer lets through to the base along a
// direction at cosTheta to the normal, relative to head-on: one direction's
// share of the base's reciprocal weight (1 - F(wo)) (1 - F(wi)) / (1 - F0).
float dielectricTransmittance(float cosTheta) {
    return 1.f - pow5(std::clamp(1.f - cosTheta, 0.f, 1.f));
}

Rgb specularF0(const Rgb& baseColor, float metallic) {
    return Rgb(kDielectricF0 * (1.f - metallic)) + baseColor * metallic;
}

}  // namespace

Rgb metalRoughnessMirrorWeight(const ShadingPoint& sp) {
    const float metallic = std::clamp(sp.metallic, 0.f, 1.f);
    return schlick(specularF0(sp.kd, metallic), dot(sp.wo, sp.ns));
}

MetalRoughnessBsdf::MetalRoughnessBsdf(const Rgb& baseColor, float metallic, float roughness, const Vec3f& n,
                                       const Vec3f& wo, bool specularLobe)
    : frame_(Frame::fromNormal(n)), wo_(frame_.toLocal(wo)), ggx_(ggxAlpha(roughness)) {
    metallic = std::clamp(metallic, 0.f, 1.f);
    f0_ = specularF0(baseColor, metallic);
    specularLobe_ = specularLobe;
    diffuse_ = baseColor * (1.f - metallic);
    // The lobes' shares of what reaches wo, by their Fresnel weights at
    // normal-to-wo incidence: a cheap stand-in for their albedos.
    baseTransmittance_ = wo_.z > 0.f ? (1.f - kDielectricF0) * dielectricTransmittance(wo_.z) : 0.f;
    const float fresnel = schlick(f0_, wo_.z).average();
    const float base = diffuse_.average() * baseTransmittance_;
    specular_ = !specularLobe ? 0.f : fresnel + base > 0.f ? fresnel / (fresnel + base) : 1.f;
    g1o_ = wo_.z > 0.f ? ggx_.g1(wo_) : 0.f;
}

float MetalRoughnessBsdf::pdfLocal(const Vec3f& wi, const Vec3f& h) const {
    // The visible normal's density turned into wi's: dwh/dwi = 1 / (4 wo.h).
    const float specularPdf = g1o_ * ggx_.d(h) / (4.f * wo_.z);
    return specular_ * specularPdf + (1.f - specular_) * wi.z * kInvPi;
}

BsdfSample MetalRoughnessBsdf::evaluate(const Vec3f& wi) const {
    const Vec3f l = frame_.toLocal(wi);
    if (!(l.z > 0.f) || !(wo_.z > 0.f)) return {wi, Rgb(0.f), 0.f};
    const Vec3f h = normalize(wo_ + l);
    const Rgb f = specularLobe_ ? schlick(f0_, dot(wo_, h)) : Rgb(0.f);
    const float specular = ggx_.d(h) * ggx_.g2(wo_, l) / (4.f * wo_.z);  // times l.z / l.z
    const float base = baseTransmittance_ * dielectricTransmittance(l.z) * l.z * kInvPi;
    const Rgb fCos = f * specular + diffuse_ * base;
    return {wi, fCos, pdfLocal(l, h)};
}

std::optional<Vec3f> MetalRoughnessBsdf::direction(Vec2f u) const {
    if (!(wo_.z > 0.f)) return std::nullopt;
    constexpr float kBelowOne = 0x1.fffffep-1f;
    Vec3f l;
    if (u.x < specular_) {
        const Vec3f h = ggx_.sampleVisibleNormal(wo_, Vec2f{std::min(u.x / specular_, kBelowOne), u.y});
        l = reflect(-wo_, h);
    } else {
        l = squareToCosineHemisphere(Vec2f{std::min((u.x - specular_) / (1.f - specular_), kBelowOne), u.y});
    }
    if (!(l.z > 0.f)) return std::nullopt;
    return frame_.toWorld(l);
}

std::optional<BsdfSample> MetalRoughnessBsdf::sample(Vec2f u) const {
    const std::optional<Vec3f> wi = direction(u);
    if (!wi) return std::nullopt;
    const BsdfSample s = evaluate(*wi);
    if (!(s.pdf > 0.f)) return std::nullopt;
    return s;
}

}  // namespace penumbra
