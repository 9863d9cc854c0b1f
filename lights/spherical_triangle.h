// Spherical triangle sampling (Arvo 1995): directions uniform in the solid
// angle a triangle subtends at a point, so the 1/d^2 and the emitter's cosine
// drop out of the estimator.
#pragma once

#include <optional>

#include "core/math.h"

namespace penumbra {

/// Solid angle (steradians) the triangle p0 p1 p2 subtends at o
/// (Van Oosterom & Strackee 1983); 0 for a degenerate or edge-on triangle.
float triangleSolidAngle(const Vec3f& o, const Vec3f& p0, const Vec3f& p1, const Vec3f& p2);

/// A direction sampled uniformly in a spherical triangle, with the point where
/// it meets the planar triangle.
struct SphericalTriangleSample {
    Vec3f wi;          // unit direction from o
    Vec3f point;       // on the triangle
    float solidAngle;  // pdf = 1 / solidAngle
};

/// Samples the triangle p0 p1 p2 seen from o uniformly by solid angle with
/// u in [0,1)^2. nullopt when o lies in the triangle's plane (no solid angle).
std::optional<SphericalTriangleSample> sampleSphericalTriangle(const Vec3f& o, const Vec3f& p0, const Vec3f& p1,
                                                               const Vec3f& p2, Vec2f u);

}  // namespace penumbra
