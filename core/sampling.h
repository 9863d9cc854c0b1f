// Warping functions from the unit square, each with its pdf.
#pragma once

#include "core/math.h"

namespace penumbra {

/// sin a and cos a for |a| <= pi/4 by their Taylor series to a^9 and a^8
/// (truncation below 2e-9 and 3e-8, under float rounding): no call and no
/// branch, so that loops over lanes vectorise it.
struct SinCos {
    float sin, cos;
};
inline SinCos sinCosOctant(float a) {
    const float a2 = a * a;
    const float s = a * (1.f + a2 * (-1.f / 6 + a2 * (1.f / 120 + a2 * (-1.f / 5040 + a2 * (1.f / 362880)))));
    const float c = 1.f + a2 * (-0.5f + a2 * (1.f / 24 + a2 * (-1.f / 720 + a2 * (1.f / 40320))));
    return {s, c};
}

/// Concentric map of [0,1)^2 to the unit disk (Shirley & Chiu 1997); uniform, pdf 1/pi.
/// The radius is the larger coordinate of the square [-1, 1)^2, the angle
/// from that axis pi/4 times the ratio of the other to it.
inline Vec2f squareToConcentricDisk(Vec2f u) {
    const float x = 2.f * u.x - 1.f, y = 2.f * u.y - 1.f;
    const bool xMajor = std::fabs(x) > std::fabs(y);
    const float r = xMajor ? x : y, minor = xMajor ? y : x;
    const float a = r == 0.f ? 0.f : (kPi / 4.f) * (minor / r);  // r = 0: the centre
    const SinCos sc = sinCosOctant(a);
    return xMajor ? Vec2f{r * sc.cos, r * sc.sin} : Vec2f{r * sc.sin, r * sc.cos};
}

/// Uniform direction on the unit sphere; pdf 1/(4 pi).
inline Vec3f squareToUniformSphere(Vec2f u) {
    float z = 1.f - 2.f * u.x;
    float r = std::sqrt(std::max(0.f, 1.f - z * z));
    float phi = 2.f * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

/// Cosine-weighted direction on the hemisphere around +z; pdf cos(theta)/pi.
inline Vec3f squareToCosineHemisphere(Vec2f u) {
    Vec2f d = squareToConcentricDisk(u);
    float z = std::sqrt(std::max(0.f, 1.f - d.x * d.x - d.y * d.y));
    return {d.x, d.y, z};
}

/// Uniform barycentrics on a triangle (the square-root map); returns (b1, b2).
inline Vec2f squareToTriangle(Vec2f u) {
    float su = std::sqrt(u.x);
    return {1.f - su, u.y * su};
}

}  // namespace penumbra
