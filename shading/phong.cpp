#include "shading/phong.h"

namespace penumbra {

Rgb phongResponse(const Material& m, const Rgb& kd, const Vec3f& n, const Vec3f& wo, const Vec3f& wi, bool deltaLight) {
    const float cosTheta = dot(n, wi);
    if (!(cosTheta > 0.f)) return {};
    float specular = 0.f;
    if (m.ks.maxComponent() > 0.f) {
        const Vec3f r = 2.f * cosTheta * n - wi;
        const float cosAlpha = dot(r, wo);
        if (cosAlpha > 0.f) specular = std::pow(cosAlpha, m.exponent);
    }
    if (m.model == PhongModel::Normalized) {
        const float norm = (m.exponent + 2.f) * kInv2Pi;
        return (kd * kInvPi + m.ks * (norm * specular)) * cosTheta;
    }
    if (deltaLight) return kd * cosTheta + m.ks * specular;
    return (kd * kInvPi + m.ks * specular) * cosTheta;
}

}  // namespace penumbra
