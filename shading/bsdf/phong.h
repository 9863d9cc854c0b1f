// The Phong reflection model in Penumbra's two flavours.
//
// Let n be the shading normal, wo the direction to the viewer, wi the
// direction to the light, cos(theta) = n.wi, and cos(alpha) = max(0, r.wo)
// with r = 2(n.wi)n - wi the mirror direction of wi.
//
// Normalized (default, energy-conserving when kd + ks <= 1):
//     f_r = kd/pi + ks (n+2)/(2 pi) cos^n(alpha)
//   every light contributes f_r * L * cos(theta) (divided by the pdf for area lights).
//
// Classic (Phong's formula L = ka La + sum kd Lj (n.s) + ks Lj (v.r)^n):
//   point and directional lights contribute (kd cos(theta) + ks cos^n(alpha)) * Lj,
//   where Lj is the light's irradiance at the point (I/d^2, or E);
//   area lights use the area-light shading of Suffern's Matte/Phong
//   BRDFs: f_r = kd/pi + ks cos^n(alpha), i.e. a Lambertian diffuse part and
//   the unnormalised specular lobe, in the same estimator as the normalized model.
//
// Ambient is ka * La in both models.
#pragma once

#include "core/color.h"
#include "core/material.h"
#include "core/math.h"

namespace penumbra {

/// The factor that multiplies the light's L (radiance for area lights, then
/// divided by the pdf; I/d^2 or E for delta lights): f_r cos(theta) in the
/// normalized model, as described above in the classic one. Zero when wi is
/// below the surface. kd is the material's diffuse albedo after texturing.
inline Rgb phongResponse(const Material& m, const Rgb& kd, const Vec3f& n, const Vec3f& wo, const Vec3f& wi, bool deltaLight) {
    const float cosTheta = dot(n, wi);
    if (!(cosTheta > 0.f)) return {};
    float specular = 0.f;
    if (m.isGlossy()) {
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
