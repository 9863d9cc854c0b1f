// Warping functions from the unit square, each with its pdf.
#pragma once

#include "core/math.h"

namespace penumbra {

/// Concentric map of [0,1)^2 to the unit disk (Shirley & Chiu 1997); uniform, pdf 1/pi.
inline Vec2f squareToConcentricDisk(Vec2f u) {
    float x = 2.f * u.x - 1.f, y = 2.f * u.y - 1.f;
    if (x == 0.f && y == 0.f) return {0.f, 0.f};
    float r, phi;
    if (std::fabs(x) > std::fabs(y)) {
        r = x;
        phi = (kPi / 4.f) * (y / x);
    } else {
        r = y;
        phi = (kPi / 2.f) - (kPi / 4.f) * (x / y);
    }
    return {r * std::cos(phi), r * std::sin(phi)};
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
