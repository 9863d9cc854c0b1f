#include "lights/light_bounds.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {

float safeAcos(float c) { return std::acos(std::clamp(c, -1.f, 1.f)); }

// The angle between unit vectors, accurate also where they nearly coincide
// (where acos of their dot product is not).
float angleBetween(const Vec3f& a, const Vec3f& b) { return 2.f * std::atan2(length(a - b), length(a + b)); }

// The union's half angle is widened by this (radians): a cone's angle is
// known only through its cosine, which as a float near 1 pins the angle
// down to about 3.5e-4, and no cone may end up a little outside the union.
constexpr float kConeSlack = 1e-3f;

}  // namespace

DirectionCone unite(const DirectionCone& a, const DirectionCone& b) {
    if (a.cosTheta <= -1.f || b.cosTheta <= -1.f) return {a.axis, -1.f};
    const float thetaA = safeAcos(a.cosTheta), thetaB = safeAcos(b.cosTheta);
    const float thetaD = angleBetween(a.axis, b.axis);
    // One cone inside the other.
    if (std::min(thetaD + thetaB, kPi) <= thetaA) return a;
    if (std::min(thetaD + thetaA, kPi) <= thetaB) return b;
    // The cone through a's far edge and b's far edge, in the plane of the axes.
    const float theta = 0.5f * (thetaA + thetaD + thetaB) + kConeSlack;
    if (theta >= kPi) return {a.axis, -1.f};
    // Turn a's axis towards b's by theta - thetaA, about their common normal.
    Vec3f k = cross(a.axis, b.axis);
    if (!(lengthSquared(k) > 1e-12f)) k = Frame::fromNormal(a.axis).s;  // opposite axes: any normal
    k = normalize(k);
    const float turn = theta - thetaA;
    const Vec3f axis = normalize(a.axis * std::cos(turn) + cross(k, a.axis) * std::sin(turn));
    return {axis, std::cos(theta)};
}

LightBounds unite(const LightBounds& a, const LightBounds& b) {
    LightBounds u;
    u.box = a.box;
    u.box.extend(b.box);
    const DirectionCone cone = unite(DirectionCone{a.axis, a.cosThetaO}, DirectionCone{b.axis, b.cosThetaO});
    u.axis = cone.axis;
    u.cosThetaO = cone.cosTheta;
    u.cosThetaE = std::min(a.cosThetaE, b.cosThetaE);
    u.twoSided = a.twoSided || b.twoSided;
    return u;
}

float orientationMeasure(float cosThetaO, float cosThetaE) {
    const float thetaO = safeAcos(cosThetaO), thetaE = safeAcos(cosThetaE);
    const float thetaW = std::min(thetaO + thetaE, kPi);
    const float sinO = std::sin(thetaO);
    // 2 pi int_0^thetaO sin t dt + 2 pi int_thetaO^thetaW cos(t - thetaO) sin t dt
    return 2.f * kPi * (1.f - cosThetaO) +
           0.5f * kPi * (cosThetaO - std::cos(2.f * thetaW - thetaO) + 2.f * (thetaW - thetaO) * sinO);
}

}  // namespace penumbra
