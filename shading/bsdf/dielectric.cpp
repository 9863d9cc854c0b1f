#include "shading/bsdf/dielectric.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

float fresnelDielectric(float cosThetaI, float eta) {
    cosThetaI = std::clamp(cosThetaI, 0.f, 1.f);
    const float sin2T = (1.f - cosThetaI * cosThetaI) / (eta * eta);
    if (sin2T >= 1.f) return 1.f;
    const float cosT = std::sqrt(1.f - sin2T);
    // Parallel and perpendicular amplitude ratios (Hecht, Optics, 4.42-4.43).
    const float rPar = (eta * cosThetaI - cosT) / (eta * cosThetaI + cosT);
    const float rPerp = (cosThetaI - eta * cosT) / (cosThetaI + eta * cosT);
    return 0.5f * (rPar * rPar + rPerp * rPerp);
}

std::optional<Vec3f> refract(const Vec3f& wo, const Vec3f& n, float eta) {
    const float cosI = std::clamp(dot(wo, n), 0.f, 1.f);
    const float sin2T = (1.f - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.f) return std::nullopt;
    const float cosT = std::sqrt(1.f - sin2T);
    return normalize(-wo / eta + (cosI / eta - cosT) * n);
}

DielectricSplit splitDielectric(const Vec3f& wo, const Vec3f& ns, const Vec3f& ng, float eta, const Rgb& kt) {
    // The shading normal decides the directions unless it sends one of them to
    // the wrong side of the surface; then the geometric normal does (as for mirrors).
    Vec3f n = ns;
    Vec3f r = reflect(-wo, n);
    std::optional<Vec3f> t = refract(wo, n, eta);
    if (dot(r, ng) <= 0.f || (t && dot(*t, ng) >= 0.f)) {
        n = ng;
        r = reflect(-wo, n);
        t = refract(wo, n, eta);
    }
    DielectricSplit s;
    s.reflected = normalize(r);
    const float F = t ? fresnelDielectric(dot(wo, n), eta) : 1.f;
    s.reflectedWeight = Rgb(F);
    if (t && F < 1.f) {
        s.transmitted = *t;
        s.transmittedWeight = kt * ((1.f - F) / (eta * eta));
    }
    return s;
}

DielectricSample sampleDielectric(const Vec3f& wo, const Vec3f& ns, const Vec3f& ng, float eta, const Rgb& kt, float u) {
    const DielectricSplit s = splitDielectric(wo, ns, ng, eta, kt);
    const float F = s.reflectedWeight.r;
    if (!s.transmitted || u < F) return {s.reflected, Rgb(1.f), s.transmitted ? F : 1.f, false};
    return {*s.transmitted, kt * (1.f / (eta * eta)), 1.f - F, true};
}

}  // namespace penumbra
