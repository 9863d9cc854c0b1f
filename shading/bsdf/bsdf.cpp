#include "shading/bsdf/bsdf.h"

#include <algorithm>

#include "shading/bsdf/dielectric.h"
#include "shading/bsdf/lambert.h"
#include "shading/bsdf/mirror.h"

namespace penumbra {

float bsdfPiPeakPdf(const ShadingPoint& sp) {
    if (sp.metalRoughness) return metalRoughnessAt(sp).piPeakPdf();
    const float pd = phongDiffuseProbability(*sp.material, sp.kd);
    return pd + (1.f - pd) * 0.5f * (sp.material->exponent + 1.f);
}

BsdfLobes bsdfLobes(const ShadingPoint& sp) {
    if (sp.metalRoughness) return {1.f, 0.f, 0.f};
    const Material& m = *sp.material;
    const float smooth = sp.reflectsLight() ? Rgb(sp.kd).average() + Rgb(m.ks).average() : 0.f;
    const float mirror = m.isDielectric() ? 0.f : Rgb(m.kr).average();
    const float glass = m.isDielectric() ? 1.f : 0.f;
    if (mirror == 0.f && glass == 0.f) return {smooth > 0.f ? 1.f : 0.f, 0.f, 0.f};  // the quotients below, exactly
    const float total = smooth + mirror + glass;
    if (!(total > 0.f)) return {};
    return {smooth / total, mirror / total, glass / total};
}

std::optional<BsdfBounce> sampleBsdf(const ShadingPoint& sp, const BsdfLobes& lobes, Vec2f u) {
    if (bouncesLambert(sp, lobes, u))
        return lambertBounce(sp, lobes.smooth, sampleLambert(sp.ns, smoothLobeU(u, lobes.smooth)));
    const Material& m = *sp.material;
    constexpr float kBelowOne = 0x1.fffffep-1f;
    if (u.x < lobes.smooth) {
        const Vec2f v = smoothLobeU(u, lobes.smooth);
        const std::optional<BsdfSample> s =
            sp.metalRoughness ? metalRoughnessAt(sp).sample(v) : samplePhong(m, sp.kd, sp.ns, sp.wo, v);
        if (!s || !(s->pdf > 0.f) || dot(s->wi, sp.ng) <= 0.f) return std::nullopt;
        const float pdf = lobes.smooth * s->pdf;
        return BsdfBounce{s->wi, s->fCos * (1.f / pdf), pdf, false, false};
    }
    if (u.x < lobes.smooth + lobes.mirror)
        return BsdfBounce{mirrorDirection(sp.wo, sp.ns, sp.ng), Rgb(m.kr) * (1.f / lobes.mirror), 0.f, true, false};
    // The lobe choice's leftover range, rescaled, picks reflection or refraction.
    const float eta = sp.front ? m.ior : 1.f / m.ior;
    const float v = std::min((u.x - lobes.smooth - lobes.mirror) / lobes.glass, kBelowOne);
    const DielectricSample s = sampleDielectric(sp.wo, sp.ns, sp.ng, eta, Rgb(m.kt), v);
    return BsdfBounce{s.wi, s.weight * (1.f / lobes.glass), 0.f, true, s.transmitted};
}

}  // namespace penumbra
