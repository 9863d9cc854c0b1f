// Where a light can send light, in the terms a light hierarchy works with
// (Conty Estevez & Kulla 2018, "Importance sampling of many lights with
// adaptive tree splitting"): a box that holds the emitter and a cone that
// holds the directions it emits along. The cone is the emitter's normals
// (within thetaO of axis) widened by how far past a normal it still emits
// (thetaE: pi/2 for a Lambertian surface). Lights at infinity have none.
#pragma once

#include "core/math.h"

namespace penumbra {

struct LightBounds {
    Bounds3f box;
    Vec3f axis{0.f, 0.f, 1.f};  // unit
    float cosThetaO = -1.f;     // the normals' spread about axis: -1 = every direction
    float cosThetaE = 0.f;      // emission past a normal: 0 = up to pi/2 (Lambertian)
    bool twoSided = false;      // emits along -axis's cone too
};

/// Bounds holding both a and b: the box of their boxes, the smallest cone
/// about one axis that holds both cones (from a's and b's own, not the
/// lights'), the wider emission and either's two-sidedness.
LightBounds unite(const LightBounds& a, const LightBounds& b);

/// The smallest cone (axis, cos of its half angle) holding the cones (a,
/// cosA) and (b, cosB); cos = -1 (every direction) where that is wider than pi.
struct DirectionCone {
    Vec3f axis{0.f, 0.f, 1.f};
    float cosTheta = 1.f;
};
DirectionCone unite(const DirectionCone& a, const DirectionCone& b);

/// The solid angle a cluster's emission covers, each direction weighted by
/// the cosine of its angle past the normals' cone (Conty Estevez & Kulla's
/// M_Omega): 2 pi (1 - cos thetaO) for the cone itself plus the cosine-
/// weighted band of width thetaE around it. The light BVH's split cost.
float orientationMeasure(float cosThetaO, float cosThetaE);

}  // namespace penumbra
